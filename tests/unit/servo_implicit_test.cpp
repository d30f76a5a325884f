// Servos, the implicit step and keyframes on one hinge, against hand calculations: a rotor of
// inertia I about a vertical axis (gravity does no work on it), driven by a position servo.
//   servo force     = kp (clamp(ctrl) - q) - kv qdot, then clamped to forcerange;
//   implicit step   (I + h (kv + d)) qacc = kp (c - q) - (kv + d) qdot, since
//                   d(force - d qdot)/d qdot = -(kv + d) is all of MuJoCo's D here;
//   explicit Euler  qacc = (kp (c - q) - kv qdot) / I, with the joint damping d implicit:
//                   (I + h d) qacc = kp (c - q) - (kv + d) qdot.
#include <catch2/catch.hpp>
#include <cmath>
#include <lever/lab/lab.hpp>
#include <lever/lever.hpp>
#include <lever/mjcf.hpp>
#include <string>

namespace {

constexpr double kI = 0.3;  // rotor inertia about z: the diaginertia's third entry plus armature
constexpr double kArmature = 0.05, kDamping = 0.7, kKp = 40.0, kKv = 3.0, kH = 0.01;

std::string rotor_xml(const std::string& integrator, const std::string& actuator) {
  return R"(<mujoco>
  <option timestep="0.01" integrator=")" +
         integrator + R"(" gravity="0 0 -9.81"/>
  <worldbody>
    <body name="rotor">
      <joint name="spin" axis="0 0 1" armature="0.05" damping="0.7"/>
      <inertial pos="0 0 0" mass="2" diaginertia="0.2 0.2 0.25"/>
    </body>
  </worldbody>
  <actuator>)" +
         actuator + R"(</actuator>
  <keyframe>
    <key name="start" time="1.5" qpos="0.2" qvel="-0.4" ctrl="0.5"/>
    <key name="partial" qvel="0.1"/>
  </keyframe>
</mujoco>)";
}

const std::string kServo =
    R"(<position name="servo" joint="spin" kp="40" ctrlrange="-1 1" forcerange="-5 5"/>)";

}  // namespace

TEST_CASE("a position servo's force is kp (ctrl - q) - kv qdot, with both clamps",
          "[unit][servo]") {
  // MuJoCo 2.2.2's <position> has no kv: written as <general> with biasprm = 0 -kp -kv
  const std::string general =
      R"(<general name="servo" joint="spin" gainprm="40" biastype="affine" biasprm="0 -40 -3")"
      R"( ctrlrange="-1 1" forcerange="-5 5"/>)";
  const lever::Model model = lever::mjcf::load_string(rotor_xml("Euler", general));
  lever::Data data(model);
  const auto force_at = [&](double q, double qdot, double ctrl) {
    data.qpos[0] = q;
    data.qvel[0] = qdot;
    data.ctrl[0] = ctrl;
    lever::forward(model, data);
    CHECK(data.qfrc_actuator[0] == data.actuator_force[0]);  // gear 1 on a hinge
    return data.actuator_force[0];
  };
  CHECK(force_at(0.1, 0.2, 0.15) == Approx(kKp * (0.15 - 0.1) - kKv * 0.2).epsilon(1e-14));
  // ctrl beyond ctrlrange: the target is the range's end
  CHECK(force_at(0.9, 0.0, 3.0) == Approx(kKp * (1.0 - 0.9)).epsilon(1e-14));
  // force beyond forcerange: clamped
  CHECK(force_at(0.0, -1.0, 1.0) == 5.0);
  CHECK(force_at(0.9, 1.0, -1.0) == -5.0);
}

TEST_CASE("a <position> shortcut compiles to gain kp and bias -kp q", "[unit][servo]") {
  const lever::Model model = lever::mjcf::load_string(
      rotor_xml("Euler", R"(<position name="servo" joint="spin" kp="40"/>)"));
  CHECK(model.actuator_gaintype[0] == lever::GainType::kFixed);
  CHECK(model.actuator_biastype[0] == lever::BiasType::kAffine);
  CHECK(model.actuator_gainprm[0][0] == kKp);
  CHECK(model.actuator_biasprm[0][0] == 0.0);
  CHECK(model.actuator_biasprm[0][1] == -kKp);
  CHECK(model.actuator_biasprm[0][2] == 0.0);
  const lever::Model velocity = lever::mjcf::load_string(
      rotor_xml("Euler", R"(<velocity name="servo" joint="spin" kv="3"/>)"));
  CHECK(velocity.actuator_gainprm[0][0] == kKv);
  CHECK(velocity.actuator_biasprm[0][1] == 0.0);
  CHECK(velocity.actuator_biasprm[0][2] == -kKv);
}

TEST_CASE("the implicit step solves (I + h (kv + d)) qacc = kp (c - q) - (kv + d) qdot",
          "[unit][implicit]") {
  const std::string general =
      R"(<general name="servo" joint="spin" gainprm="40" biastype="affine" biasprm="0 -40 -3"/>)";
  const double q = 0.25, qdot = -0.4, c = 0.5;
  const double rhs = kKp * (c - q) - (kKv + kDamping) * qdot;
  for (const std::string integrator : {"implicit", "Euler"}) {
    INFO(integrator);
    const lever::Model model = lever::mjcf::load_string(rotor_xml(integrator, general));
    REQUIRE(model.dof_armature[0] + 0.25 == Approx(kI));
    lever::Data data(model);
    data.qpos[0] = q;
    data.qvel[0] = qdot;
    data.ctrl[0] = c;
    lever::step(model, data);
    const double implicit_in = integrator == "implicit" ? kKv + kDamping : kDamping;
    const double qacc = rhs / (kI + kH * implicit_in);
    CHECK(data.qvel[0] == Approx(qdot + kH * qacc).epsilon(1e-14));
    CHECK(data.qpos[0] == Approx(q + kH * (qdot + kH * qacc)).epsilon(1e-14));
  }
}

TEST_CASE("the implicit step's D is d qfrc_smooth / d qvel where no clamp binds",
          "[unit][implicit]") {
  // a two-link arm in 3D (Coriolis terms in D) with a servo on each joint
  const lever::Model model = lever::mjcf::load_string(R"(<mujoco>
  <option integrator="implicit"/>
  <worldbody>
    <body name="a">
      <joint name="j1" axis="0 0 1" damping="0.3"/>
      <geom type="capsule" fromto="0 0 0 0.4 0 0" size="0.04"/>
      <body name="b" pos="0.4 0 0">
        <joint name="j2" axis="0 1 0" damping="0.1"/>
        <geom type="capsule" fromto="0 0 0 0 0 -0.3" size="0.03"/>
      </body>
    </body>
  </worldbody>
  <actuator>
    <general joint="j1" gainprm="20 0 0.5" gaintype="affine" biastype="affine" biasprm="0 -20 -2"/>
    <velocity joint="j2" kv="1.5"/>
  </actuator>
</mujoco>)");
  lever::Data data(model);
  data.qpos << 0.3, -0.7;
  data.qvel << 1.1, -0.6;
  data.ctrl << 0.2, 0.4;
  lever::forward(model, data);
  Eigen::MatrixXd D(model.nv, model.nv);
  lever::smooth_velocity_derivative(model, data, D);
  const double eps = 1e-6;
  for (int j = 0; j < model.nv; ++j) {
    lever::Data plus = data, minus = data;
    plus.qvel[j] += eps;
    minus.qvel[j] -= eps;
    lever::forward(model, plus);
    lever::forward(model, minus);
    const Eigen::VectorXd column = (plus.qfrc_smooth - minus.qfrc_smooth) / (2 * eps);
    for (int i = 0; i < model.nv; ++i) {
      INFO("D(" << i << ", " << j << ")");
      // qfrc_smooth is affine in qvel through the actuators and damping and quadratic through
      // the bias, so a central difference has no truncation error: what is left is rounding,
      // ~1e-16 |qfrc_smooth| / eps ~ 1e-10 here
      CHECK(D(i, j) == Approx(column[i]).margin(1e-8));
    }
  }
}

TEST_CASE("reset_keyframe sets time, qpos, qvel and ctrl, unwritten values are qpos0 and zero",
          "[unit][keyframe]") {
  const lever::Model model = lever::mjcf::load_string(rotor_xml("implicit", kServo));
  REQUIRE(model.nkey == 2);
  lever::Data data(model);
  data.qfrc_applied[0] = 7.0;
  lever::reset_keyframe(model, data, "start");
  CHECK(data.time == 1.5);
  CHECK(data.qpos[0] == 0.2);
  CHECK(data.qvel[0] == -0.4);
  CHECK(data.ctrl[0] == 0.5);
  CHECK(data.qfrc_applied[0] == 0.0);  // the rest as mj_resetData
  lever::reset_keyframe(model, data, 1);
  CHECK(data.time == 0.0);
  CHECK(data.qpos[0] == model.qpos0[0]);
  CHECK(data.qvel[0] == 0.1);
  CHECK(data.ctrl[0] == 0.0);
  CHECK(model.key("partial") == 1);
}

TEST_CASE("reset_keyframe refuses a keyframe the model does not have", "[unit][keyframe]") {
  const lever::Model model = lever::mjcf::load_string(rotor_xml("implicit", kServo));
  lever::Data data(model);
  CHECK_THROWS_AS(lever::reset_keyframe(model, data, 2), lever::StateError);
  CHECK_THROWS_AS(lever::reset_keyframe(model, data, -1), lever::StateError);
  CHECK_THROWS_WITH(lever::reset_keyframe(model, data, "home"),
                    Catch::Contains("start") && Catch::Contains("partial"));
}

TEST_CASE("set_const refuses servo parameters and keyframes that cannot be simulated",
          "[unit][servo][keyframe]") {
  lever::Model model = lever::mjcf::load_string(rotor_xml("implicit", kServo));
  lever::Model nan_gain = model;
  nan_gain.actuator_gainprm[0][0] = std::nan("");
  CHECK_THROWS_AS(lever::set_const(nan_gain), lever::ModelError);
  lever::Model short_key = model;
  short_key.nkey += 1;  // a keyframe counted but not sized
  CHECK_THROWS_AS(lever::set_const(short_key), lever::ModelError);
}

TEST_CASE("the lab's gravity compensation through a servo adds exactly qfrc_bias",
          "[unit][servo][lab]") {
  // panda7 at rest at its `home` keyframe, each servo's target at the joint's angle: without
  // compensation the servos push nothing and the arm sags; with it, the targets are offset by
  // qfrc_bias / (gear kp) and the actuator torque is gravity's, so the arm does not accelerate
  const lever::Model model =
      lever::mjcf::load_file(std::string(LEVER_SOURCE_DIR) + "/models/panda7.xml");
  lever::Data data(model);
  lever::reset_keyframe(model, data, "home");
  data.qvel.setZero();
  lever::lab::Controller controller;
  controller.torque = data.qpos;  // each servo's target: where its joint is (gear 1, one per joint)
  lever::forward(model, data);
  lever::lab::apply(model, controller, data);
  lever::forward(model, data);
  CHECK(data.qacc.cwiseAbs().maxCoeff() > 1.0);  // sagging
  controller.gravity_compensation = true;
  lever::lab::apply(model, controller, data);
  lever::forward(model, data);
  for (int i = 0; i < model.nv; ++i) {
    INFO("dof " << i);
    // kp (target + offset) - kp q cancels terms of ~7e3 N m (kp 4500, q ~1.57): rounding of
    // ~1e-12 N m, and qacc = M^-1 of that; the margins leave room above rounding only
    CHECK(data.qfrc_actuator[i] == Approx(data.qfrc_bias[i]).margin(1e-9));
    CHECK(std::abs(data.qacc[i]) < 1e-8);
  }
}
