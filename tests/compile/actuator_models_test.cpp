// Actuators compiled by mjcf_lite and by MuJoCo 2.2.2: the models of tests/models/actuators/ and
// the real files whose actuators are not on joints or tendons (the slider-cranks of MuJoCo's
// sample), field by field (actuator_trntype, actuator_trnid, actuator_cranklength, and the
// constants actuator_length0 and actuator_acc0); and the transmissions lever refuses, by name.
#include <catch2/catch.hpp>
#include <lever/mjcf.hpp>

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
