// Model::actuator_kind (lever/model.hpp): each actuator element compiles to the kind its force
// law is, a kind follows the parameters when they are edited (set_const), and the questions the
// libraries ask (is it a servo, which bias entry its gain carries) read it.
#include <catch2/catch.hpp>
#include <lever/lever.hpp>
#include <lever/mjcf.hpp>
#include <lever/regressor.hpp>

#include <lever/harness/models.hpp>

using lever::ActuatorKind;

TEST_CASE("actuator kind: each element compiles to its force law's kind", "[mjcf][actuator]") {
  lever::Model m =
      lever::mjcf::load_file(lever::test::model_path("tests/derivatives/servo_affine.xml"));
  REQUIRE(m.nu == 6);
  // shoulder: an affine gain whose bias is tied to gainprm[0] (biasprm[1] = -20); elbow: a
  // <general> written as a position servo; wrist: affine gain and bias, not tied
  const std::vector<ActuatorKind> expected{
      ActuatorKind::kPositionServo, ActuatorKind::kMotor,   ActuatorKind::kPositionServo,
      ActuatorKind::kPositionServo, ActuatorKind::kGeneral, ActuatorKind::kVelocityServo};
  CHECK(m.actuator_kind == expected);
  for (int a = 0; a < m.nu; ++a) {
    INFO(m.actuator_name[a]);
    CHECK(lever::is_servo(m.actuator_kind[a]) == (a != 1));
    const int tied = expected[a] == ActuatorKind::kPositionServo   ? 1
                     : expected[a] == ActuatorKind::kVelocityServo ? 2
                                                                   : 0;
    CHECK(lever::gain_tied_bias(m, a) == tied);
  }

  // edited parameters, then set_const: the kind follows
  m.actuator_biasprm[3][1] = -11;  // elbow_p's bias no longer tied to kp = 10
  m.actuator_biastype[1] = lever::BiasType::kAffine;
  m.actuator_biasprm[1] = {0, 0, -1};  // the motor's gain 1 now tied to velocity
  lever::set_const(m);
  CHECK(m.actuator_kind[3] == ActuatorKind::kGeneral);
  CHECK(m.actuator_kind[1] == ActuatorKind::kVelocityServo);
  m.actuator_biasprm[1] = {0.5, 0, 0};  // a constant bias: the state does not enter
  lever::set_const(m);
  CHECK(m.actuator_kind[1] == ActuatorKind::kMotor);
}

TEST_CASE("actuator kind: the model files' motors and servos", "[mjcf][actuator]") {
  for (const std::string& file : lever::test::all_model_files()) {
    const lever::Model m = lever::mjcf::load_file(file);
    INFO(file);
    REQUIRE(static_cast<int>(m.actuator_kind.size()) == m.nu);
    for (int a = 0; a < m.nu; ++a) {
      const bool motor = m.actuator_biastype[a] == lever::BiasType::kNone &&
                         m.actuator_gaintype[a] == lever::GainType::kFixed;
      if (motor) CHECK(m.actuator_kind[a] == ActuatorKind::kMotor);
    }
  }
  const lever::Model panda = lever::mjcf::load_file(lever::test::model_path("models/panda7.xml"));
  for (int a = 0; a < panda.nu; ++a) CHECK(panda.actuator_kind[a] == ActuatorKind::kPositionServo);
}
