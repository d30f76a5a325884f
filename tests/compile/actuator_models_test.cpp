// Actuators compiled by mjcf_lite and by MuJoCo 2.2.2: the models of tests/models/actuators/ and
// the real files whose actuators are not on joints or tendons (the slider-cranks of MuJoCo's
// sample), field by field (actuator_trntype, actuator_trnid, actuator_cranklength, and the
// constants actuator_length0 and actuator_acc0); and the transmissions lever refuses, by name.
#include <catch2/catch.hpp>
#include <lever/derivatives.hpp>
#include <lever/forward.hpp>
#include <lever/mjcf.hpp>
#include <lever/parameters.hpp>
#include <lever/regressor.hpp>

#include <filesystem>

#include <lever/harness/models.hpp>
#include "mujoco_xml.hpp"

namespace {

void compare_actuators_with_mujoco(const std::string& name, const std::string& xml) {
  INFO(name);
  const lever::Model ours = lever::mjcf::load_string(xml, name);
  std::string error;
  const lever::test::MjModelHandle theirs = lever::test::mujoco_compile(xml, &error);
  INFO("mujoco: " << error);
  REQUIRE(theirs);
  std::vector<std::string> differences = lever::test::compare_parameters(ours, *theirs);
  const std::vector<std::string> constants = lever::test::compare_constants(ours, *theirs);
  differences.insert(differences.end(), constants.begin(), constants.end());
  for (const std::string& d : differences) FAIL_CHECK(name << ": " << d);
}

std::string actuator_refusal(const std::string& xml) {
  try {
    lever::mjcf::load_string(xml, "refused.xml");
  } catch (const lever::mjcf::ParseError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("the actuator models compile to MuJoCo 2.2.2's parameters", "[compile][actuators]") {
  const std::string path = lever::test::model_path("tests/models/actuators/transmissions.xml");
  compare_actuators_with_mujoco("transmissions.xml", lever::test::read_text(path));
  const lever::Model m = lever::mjcf::load_file(path);
  REQUIRE(m.nu == 10);
  CHECK(m.actuator_trntype[2] == lever::TransmissionType::kJointInParent);
  CHECK(m.actuator_trntype[6] == lever::TransmissionType::kSite);
  CHECK(m.actuator_trnid[6][1] == -1);     // no reference site
  CHECK(m.actuator_trnid[7][1] == m.site("tool"));
  CHECK(m.actuator_trntype[9] == lever::TransmissionType::kSliderCrank);
  CHECK(m.actuator_trnid[9] == std::array<int, 2>{m.site("crank"), m.site("base")});
  CHECK(m.actuator_cranklength[9] == 0.6);
}

TEST_CASE("MuJoCo's slider-crank sample compiles to MuJoCo 2.2.2's parameters",
          "[compile][actuators][robots]") {
  const std::string file = lever::test::robots_dir() + "/mujoco-2.2.2/slider_crank/slider_crank.xml";
  if (!std::filesystem::exists(file)) {
    WARN("no " << file << ": skipped");
    return;
  }
  compare_actuators_with_mujoco("slider_crank.xml", lever::test::read_text(file));
}

TEST_CASE("transmissions written wrongly are refused by name", "[compile][actuators]") {
  const std::string head = R"(<mujoco><worldbody><site name="s"/><body name="a"><joint name="j"/>
    <geom size="1"/><site name="t"/></body></worldbody><actuator>)";
  CHECK_THAT(actuator_refusal(head + R"(<motor joint="j" site="s"/></actuator></mujoco>)"),
             Catch::Contains("names both joint and site"));
  CHECK_THAT(actuator_refusal(head + R"(<motor joint="j" slidersite="s"/></actuator></mujoco>)"),
             Catch::Contains("belong to a slider-crank"));
  CHECK_THAT(actuator_refusal(head + R"(<motor joint="j" refsite="s"/></actuator></mujoco>)"),
             Catch::Contains("refsite belongs to a site transmission"));
  CHECK_THAT(actuator_refusal(head + R"(<motor cranksite="t" cranklength="1"/></actuator></mujoco>)"),
             Catch::Contains("needs slidersite"));
  CHECK_THAT(actuator_refusal(head + R"(<motor cranksite="t" slidersite="s"/></actuator></mujoco>)"),
             Catch::Contains("positive cranklength"));
  CHECK_THAT(actuator_refusal(head + R"(<motor site="x"/></actuator></mujoco>)"),
             Catch::Contains("unknown site 'x'"));
  CHECK_THAT(actuator_refusal(head + R"(<motor site="t" refsite="y"/></actuator></mujoco>)"),
             Catch::Contains("unknown site 'y'"));
  CHECK_THAT(actuator_refusal(head + R"(<motor body="a"/></actuator></mujoco>)"),
             Catch::Contains("body"));
}

TEST_CASE("the muscle model compiles to MuJoCo 2.2.2's parameters, lengthrange included",
          "[compile][actuators][muscles]") {
  // the compiler's length-range simulation (two muscles, both sides) agrees with MuJoCo's
  const std::string path = lever::test::model_path("tests/models/actuators/muscles.xml");
  compare_actuators_with_mujoco("muscles.xml", lever::test::read_text(path));
  const lever::Model m = lever::mjcf::load_file(path);
  REQUIRE(m.na == 6);
  CHECK(m.actuator_dyntype[3] == lever::DynType::kMuscle);
  CHECK(m.actuator_gainprm[4][2] == 300);  // class "strong"
  CHECK(m.actuator_dynprm[4][0] == 0.02);
  CHECK(m.actuator_lengthrange[4] == std::array<double, 2>{0.1, 2});  // as written
  // found by simulation: near the joint's stops (the limit rows are soft)
  CHECK(m.actuator_lengthrange[3][0] == Approx(-1.2).margin(0.05));
  CHECK(m.actuator_lengthrange[3][1] == Approx(1.5).margin(0.05));
  CHECK(m.actuator_actlimited[2] == 1);
}

TEST_CASE("a muscle's lengthrange from its joint's range (uselimit) agrees with MuJoCo",
          "[compile][actuators][muscles]") {
  // the muscle first: MuJoCo 2.2.2 looks up the joint of actuator a as actuator_trnid[a] of its
  // flat array, which is actuator a's own only for a = 0 (see lifecycle/length_range.cpp)
  const std::string xml = R"(<mujoco><compiler angle="radian" autolimits="true"><lengthrange uselimit="true"/>
    </compiler><worldbody><body><joint name="j" axis="0 1 0" range="-0.5 0.8"/>
    <geom size="0.1" contype="0" conaffinity="0"/></body></worldbody>
    <actuator><muscle name="m" joint="j" ctrlrange="0 1"/></actuator></mujoco>)";
  compare_actuators_with_mujoco("uselimit", xml);
  const lever::Model m = lever::mjcf::load_string(xml, "uselimit.xml");
  CHECK(m.actuator_lengthrange[0] == std::array<double, 2>{-0.5, 0.8});
}

TEST_CASE("actuators with dynamics written wrongly are refused by name",
          "[compile][actuators][muscles]") {
  const std::string head = R"(<mujoco><worldbody><body><joint name="j"/><geom size="1"/></body>
    </worldbody><actuator>)";
  CHECK_THAT(actuator_refusal(head + R"(<general joint="j" dyntype="filter"/><motor joint="j"/>
    </actuator></mujoco>)"),
             Catch::Contains("stateless actuators must come before"));
  CHECK_THAT(actuator_refusal(head + R"(<general joint="j" actrange="0 1"/></actuator></mujoco>)"),
             Catch::Contains("needs activation dynamics"));
  CHECK_THAT(actuator_refusal(head + R"(<muscle joint="j" lmin="1.2" lengthrange="0 1"/>
    </actuator></mujoco>)"),
             Catch::Contains("lmin < 1 < lmax"));
  CHECK_THAT(actuator_refusal(head + R"(<general joint="j" dyntype="user"/></actuator></mujoco>)"),
             Catch::Contains("user"));
  // an unlimited joint: the simulation pulls the length without end and does not settle
  CHECK_THAT(actuator_refusal(head + R"(<muscle joint="j"/></actuator></mujoco>)"),
             Catch::Contains("did not settle"));
}

TEST_CASE("derivatives and identification refuse the actuators they do not handle, by name",
          "[compile][actuators]") {
  const lever::Model t =
      lever::mjcf::load_file(lever::test::model_path("tests/models/actuators/transmissions.xml"));
  lever::Data d(t);
  lever::forward(t, d);
  lever::Derivatives deriv(t);
  CHECK_THROWS_WITH(lever::step_derivatives(t, d, deriv),
                    Catch::Contains("actuator 'wrist_joint' drives a ball or free joint"));
  Eigen::MatrixXd Y(t.nv, lever::regressor_columns(t));
  CHECK_THROWS_WITH(lever::regressor(t, d, d.qacc, Y),
                    Catch::Contains("regressor: actuator 'wrist_joint'"));
  // a filter on a hinge, in a model without tendons
  const lever::Model m = lever::mjcf::load_string(
      R"(<mujoco><worldbody><body><joint name="j"/><geom size="0.1"/></body></worldbody>
      <actuator><general name="wrist_filter" joint="j" dyntype="filter"/></actuator></mujoco>)",
      "filter.xml");
  lever::Data dm(m);
  lever::forward(m, dm);
  lever::Derivatives deriv_m(m);
  CHECK_THROWS_WITH(lever::forward_derivatives(m, dm, deriv_m),
                    Catch::Contains("actuator 'wrist_filter' is an actuator with activation"));
}
