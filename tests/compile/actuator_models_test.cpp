// Actuators compiled by mjcf_lite and by MuJoCo 2.2.2: the models of tests/models/actuators/ and
// tests/derivatives/, the real files whose actuators are not on joints or tendons (the
// slider-cranks of MuJoCo's sample), field by field (actuator_trntype, actuator_trnid,
// actuator_cranklength, and the constants actuator_length0 and actuator_acc0); and the
// transmissions lever refuses, by name.
#include <catch2/catch.hpp>
#include <lever/check.hpp>
#include <lever/derivatives.hpp>
#include <lever/identify.hpp>
#include <lever/forward.hpp>
#include <lever/mjcf.hpp>
#include <lever/parameters.hpp>
#include <lever/regressor.hpp>

#include <filesystem>

#include <lever/harness/models.hpp>
#include "compile_checks.hpp"
#include "robots.hpp"

using lever::test::check_compiles_as_mujoco;
using lever::test::load_refusal;

namespace {

// The actuator arrays the compiler writes, held bit for bit (== on doubles) to MuJoCo's: each
// shortcut's parameters are set, not computed, so they must be the same numbers
std::vector<std::string> actuator_bits_differences(const lever::Model& o, const mjModel& m) {
  std::vector<std::string> out;
  const auto check = [&](const char* field, int a, int k, double ours, double theirs) {
    if (ours != theirs) {
      out.push_back(std::string(field) + "[" + std::to_string(a) + "][" + std::to_string(k) +
                    "]: lever " + std::to_string(ours) + " vs mujoco " + std::to_string(theirs));
    }
  };
  if (o.nu != m.nu || o.na != m.na) return {"nu or na differ"};
  for (int a = 0; a < m.nu; ++a) {
    check("actuator_trntype", a, 0, static_cast<int>(o.actuator_trntype[a]), m.actuator_trntype[a]);
    check("actuator_dyntype", a, 0, static_cast<int>(o.actuator_dyntype[a]), m.actuator_dyntype[a]);
    check("actuator_gaintype", a, 0, static_cast<int>(o.actuator_gaintype[a]),
          m.actuator_gaintype[a]);
    check("actuator_biastype", a, 0, static_cast<int>(o.actuator_biastype[a]),
          m.actuator_biastype[a]);
    check("actuator_ctrllimited", a, 0, o.actuator_ctrllimited[a], m.actuator_ctrllimited[a]);
    check("actuator_forcelimited", a, 0, o.actuator_forcelimited[a], m.actuator_forcelimited[a]);
    check("actuator_actlimited", a, 0, o.actuator_actlimited[a], m.actuator_actlimited[a]);
    for (int k = 0; k < 2; ++k) {
      check("actuator_trnid", a, k, o.actuator_trnid[a][k], m.actuator_trnid[2 * a + k]);
      check("actuator_ctrlrange", a, k, o.actuator_ctrlrange[a][k],
            m.actuator_ctrlrange[2 * a + k]);
      check("actuator_forcerange", a, k, o.actuator_forcerange[a][k],
            m.actuator_forcerange[2 * a + k]);
      check("actuator_actrange", a, k, o.actuator_actrange[a][k], m.actuator_actrange[2 * a + k]);
    }
    for (int k = 0; k < 6; ++k) {
      check("actuator_gear", a, k, o.actuator_gear[a][k], m.actuator_gear[6 * a + k]);
    }
    for (int k = 0; k < mjNDYN; ++k) {
      check("actuator_dynprm", a, k, o.actuator_dynprm[a][k], m.actuator_dynprm[mjNDYN * a + k]);
    }
    for (int k = 0; k < mjNGAIN; ++k) {
      check("actuator_gainprm", a, k, o.actuator_gainprm[a][k],
            m.actuator_gainprm[mjNGAIN * a + k]);
    }
    for (int k = 0; k < mjNBIAS; ++k) {
      check("actuator_biasprm", a, k, o.actuator_biasprm[a][k],
            m.actuator_biasprm[mjNBIAS * a + k]);
    }
  }
  return out;
}

void compare_actuator_bits_with_mujoco(const std::string& name, const std::string& xml) {
  INFO(name);
  const lever::Model ours = lever::mjcf::load_string(xml, name);
  std::string error;
  const lever::test::MjModelHandle theirs = lever::test::mujoco_compile(xml, &error);
  INFO("mujoco: " << error);
  REQUIRE(theirs);
  for (const std::string& d : actuator_bits_differences(ours, *theirs)) {
    FAIL_CHECK(name << ": " << d);
  }
}

}  // namespace

TEST_CASE("the actuator models compile to MuJoCo 2.2.2's parameters", "[compile][actuators]") {
  const std::string path = lever::test::model_path("tests/models/actuators/transmissions.xml");
  check_compiles_as_mujoco("transmissions.xml", lever::test::read_text(path));
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

TEST_CASE("intvelocity, damper and cylinder compile to MuJoCo 2.2.2's parameters, bit for bit",
          "[compile][actuators]") {
  // in <actuator> and in default classes, each shortcut in a class rewriting what the ones
  // before it set
  const std::string path = lever::test::model_path("tests/models/actuators/shortcuts.xml");
  const std::string xml = lever::test::read_text(path);
  check_compiles_as_mujoco("shortcuts.xml", xml);
  compare_actuator_bits_with_mujoco("shortcuts.xml", xml);
  const lever::Model m = lever::mjcf::load_file(path);
  REQUIRE(m.nu == 9);
  REQUIRE(m.na == 6);
  CHECK(m.actuator_gainprm[m.actuator("elbow_damper")][2] == -2);
  CHECK(m.actuator_gainprm[m.actuator("class_damper")][2] == 0);  // the class's kv not taken
  CHECK(m.actuator_dyntype[m.actuator("shoulder_iv")] == lever::DynType::kIntegrator);
  CHECK(m.actuator_actlimited[m.actuator("shoulder_iv")]);
  CHECK(m.actuator_dyntype[m.actuator("narrow_cylinder")] == lever::DynType::kFilter);
  // each on its own, in the simplest form, too
  const std::string head = R"(<mujoco><worldbody><body><joint name="j" range="-1 1"/>
    <geom size="0.1"/></body></worldbody><actuator>)";
  for (const char* one : {R"(<damper joint="j" ctrlrange="0 1"/>)",
                          R"(<intvelocity joint="j" actrange="-1 1"/>)",
                          R"(<cylinder joint="j"/>)", R"(<cylinder joint="j" diameter="0.3"/>)"}) {
    compare_actuator_bits_with_mujoco(one, head + one + "</actuator></mujoco>");
  }
}

TEST_CASE("adhesion and body transmissions compile to MuJoCo 2.2.2's parameters, bit for bit",
          "[compile][actuators]") {
  const std::string path = lever::test::model_path("tests/models/actuators/adhesion.xml");
  const std::string xml = lever::test::read_text(path);
  check_compiles_as_mujoco("adhesion.xml", xml);
  compare_actuator_bits_with_mujoco("adhesion.xml", xml);
  const lever::Model m = lever::mjcf::load_file(path);
  const int pad = m.actuator("pad"), box = m.actuator("box"), ball = m.actuator("ball");
  CHECK(m.actuator_trntype[pad] == lever::TransmissionType::kBody);
  CHECK(m.actuator_trnid[pad] == std::array<int, 2>{m.body("pad"), -1});
  CHECK(m.actuator_gainprm[pad][0] == 20);
  CHECK(m.actuator_gainprm[box][0] == 1);  // the class's gain is not taken
  CHECK(m.actuator_ctrllimited[box]);
  CHECK(m.actuator_trntype[ball] == lever::TransmissionType::kBody);
  CHECK(m.actuator_acc0[pad] == 0);  // no contacts at qpos0 in mj_setConst
}

TEST_CASE("MuJoCo's slider-crank sample compiles to MuJoCo 2.2.2's parameters",
          "[compile][actuators][robots]") {
  const std::string file = lever::test::robots_dir() + "/mujoco-2.2.2/slider_crank/slider_crank.xml";
  if (!lever::test::robots_present(file)) return;
  check_compiles_as_mujoco("slider_crank.xml", lever::test::read_text(file));
}

TEST_CASE("transmissions written wrongly are refused by name", "[compile][actuators]") {
  const std::string head = R"(<mujoco><worldbody><site name="s"/><body name="a"><joint name="j"/>
    <geom size="1"/><site name="t"/></body></worldbody><actuator>)";
  CHECK_THAT(load_refusal(head + R"(<motor joint="j" site="s"/></actuator></mujoco>)"),
             Catch::Contains("names both joint and site"));
  CHECK_THAT(load_refusal(head + R"(<motor joint="j" slidersite="s"/></actuator></mujoco>)"),
             Catch::Contains("belong to a slider-crank"));
  CHECK_THAT(load_refusal(head + R"(<motor joint="j" refsite="s"/></actuator></mujoco>)"),
             Catch::Contains("refsite belongs to a site transmission"));
  CHECK_THAT(load_refusal(head + R"(<motor cranksite="t" cranklength="1"/></actuator></mujoco>)"),
             Catch::Contains("needs slidersite"));
  CHECK_THAT(load_refusal(head + R"(<motor cranksite="t" slidersite="s"/></actuator></mujoco>)"),
             Catch::Contains("positive cranklength"));
  CHECK_THAT(load_refusal(head + R"(<motor site="x"/></actuator></mujoco>)"),
             Catch::Contains("unknown site 'x'"));
  CHECK_THAT(load_refusal(head + R"(<motor site="t" refsite="y"/></actuator></mujoco>)"),
             Catch::Contains("unknown site 'y'"));
  CHECK_THAT(load_refusal(head + R"(<motor body="a"/></actuator></mujoco>)"),
             Catch::Contains("unknown attribute 'body'"));
}

TEST_CASE("the muscle model compiles to MuJoCo 2.2.2's parameters, lengthrange included",
          "[compile][actuators][muscles]") {
  // the compiler's length-range simulation (two muscles, both sides) agrees with MuJoCo's
  const std::string path = lever::test::model_path("tests/models/actuators/muscles.xml");
  check_compiles_as_mujoco("muscles.xml", lever::test::read_text(path));
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
  check_compiles_as_mujoco("uselimit", xml);
  const lever::Model m = lever::mjcf::load_string(xml, "uselimit.xml");
  CHECK(m.actuator_lengthrange[0] == std::array<double, 2>{-0.5, 0.8});
}

TEST_CASE("every option of <compiler><lengthrange> agrees with MuJoCo",
          "[compile][actuators][muscles]") {
  // muscles.xml with the simulation's settings all written: useexisting false recomputes the
  // ranges written too; mode none leaves the written ones and zeros
  const std::string path = lever::test::model_path("tests/models/actuators/muscles.xml");
  const std::string text = lever::test::read_text(path);
  const std::string written = R"(<lengthrange inttotal="6" inteval="1.5"/>)";
  REQUIRE(text.find(written) != std::string::npos);
  const auto with = [&](const std::string& options) {
    std::string xml = text;
    return xml.replace(xml.find(written), written.size(), "<lengthrange " + options + "/>");
  };
  const std::string every = with(
      R"(mode="muscleuser" useexisting="false" accel="30" maxforce="40" timeconst="0.5" )"
      R"(timestep="0.005" inttotal="5" inteval="1" tolrange="0.2")");
  check_compiles_as_mujoco("lengthrange options", every);
  const lever::Model m = lever::mjcf::load_string(every, "options.xml");
  CHECK(m.actuator_lengthrange[4] != std::array<double, 2>{0.1, 2});  // recomputed
  const std::string none = with(R"(mode="none")");
  check_compiles_as_mujoco("lengthrange none", none);
  const lever::Model n = lever::mjcf::load_string(none, "none.xml");
  CHECK(n.actuator_lengthrange[3] == std::array<double, 2>{0, 0});
  CHECK(n.actuator_lengthrange[4] == std::array<double, 2>{0.1, 2});
}

TEST_CASE("lengthrange mode muscleuser finds the ranges of user gains and biases as MuJoCo",
          "[compile][actuators][muscles]") {
  // a user gain and a user bias are user actuators; user dynamics alone and a motor are not
  const std::string head = R"(<mujoco><compiler angle="radian" autolimits="true">)";
  const std::string body = R"(</compiler><worldbody><body>
    <joint name="j" axis="0 1 0" range="-0.6 0.9"/><geom size="0.1" contype="0" conaffinity="0"/>
    </body></worldbody><actuator>
    <general name="gain" joint="j" gaintype="user"/><general name="bias" joint="j" biastype="user"/>
    <motor name="motor" joint="j"/><general name="dyn" joint="j" dyntype="user"/>
    </actuator></mujoco>)";
  const std::string user = head + R"(<lengthrange mode="muscleuser"/>)" + body;
  check_compiles_as_mujoco("muscleuser", user);
  const lever::Model m = lever::mjcf::load_string(user, "muscleuser.xml");
  for (const int a : {0, 1}) {  // simulated to near the soft stops
    CHECK(m.actuator_lengthrange[a][0] == Approx(-0.6).margin(0.1));
    CHECK(m.actuator_lengthrange[a][1] == Approx(0.9).margin(0.1));
  }
  for (const int a : {2, 3}) CHECK(m.actuator_lengthrange[a] == std::array<double, 2>{0, 0});
  // mode muscle leaves the user actuators alone
  const std::string muscle = head + R"(<lengthrange mode="muscle"/>)" + body;
  check_compiles_as_mujoco("muscle", muscle);
  const lever::Model n = lever::mjcf::load_string(muscle, "muscle.xml");
  for (int a = 0; a < 4; ++a) CHECK(n.actuator_lengthrange[a] == std::array<double, 2>{0, 0});
}

TEST_CASE("actuators with dynamics written wrongly are refused by name",
          "[compile][actuators][muscles]") {
  const std::string head = R"(<mujoco><worldbody><body><joint name="j"/><geom size="1"/></body>
    </worldbody><actuator>)";
  CHECK_THAT(load_refusal(head + R"(<general joint="j" dyntype="filter"/><motor joint="j"/>
    </actuator></mujoco>)"),
             Catch::Contains("stateless actuators must come before"));
  CHECK_THAT(load_refusal(head + R"(<general joint="j" actrange="0 1"/></actuator></mujoco>)"),
             Catch::Contains("needs activation dynamics"));
  CHECK_THAT(load_refusal(head + R"(<muscle joint="j" lmin="1.2" lengthrange="0 1"/>
    </actuator></mujoco>)"),
             Catch::Contains("lmin < 1 < lmax"));
  // an unlimited joint: the simulation pulls the length without end and does not settle
  CHECK_THAT(load_refusal(head + R"(<muscle joint="j"/></actuator></mujoco>)"),
             Catch::Contains("did not settle"));
}

TEST_CASE("lever check and identification refuse user actuators by name, callbacks or not",
          "[compile][actuators]") {
  // a motor, then one actuator with a user part each: the refusal names it and its attribute
  const auto user_model = [](const std::string& part) {
    return lever::mjcf::load_string(
        R"(<mujoco><worldbody><body><joint name="j" range="-1 1" limited="true"/>
        <geom type="capsule" size="0.05" fromto="0 0 0 0.3 0 0"/></body></worldbody><actuator>
        <motor name="plain" joint="j"/><general name="custom" joint="j" )" + part +
            R"(/></actuator></mujoco>)",
        "user_actuator.xml");
  };
  for (const std::string type : {"gaintype", "biastype", "dyntype"}) {
    INFO(type);
    lever::Model m = user_model(type + "=\"user\"");
    CHECK_THROWS_WITH(lever::check::check_model(m),
                      Catch::Contains("lever check: actuator 'custom' has " + type + " \"user\"") &&
                          Catch::Contains("callback"));
    // installed callbacks do not change it: the sections read the parameters, not the callback
    const auto callback = [](const lever::Model&, const lever::Data&, int) { return 2.0; };
    m.actuator_gain_callback = m.actuator_bias_callback = m.actuator_dyn_callback = callback;
    CHECK_THROWS_WITH(lever::check::check_model(m), Catch::Contains("has " + type));
    lever::Data d(m);
    lever::forward(m, d);
    Eigen::MatrixXd Y(m.nv, lever::regressor_columns(m));
    CHECK_THROWS_WITH(lever::regressor(m, d, d.qacc, Y),
                      Catch::Contains("regressor: actuator 'custom' has " + type));
    CHECK_THROWS_WITH(lever::identify::identify(m, lever::identify::Trajectory{}),
                      Catch::Contains("identify: actuator 'custom' has " + type));
  }
  // the same model with a built-in gain is checked
  CHECK_NOTHROW(lever::check::check_model(user_model(R"(gaintype="fixed")")));
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
  // a filter on a hinge, in a model without tendons: differentiated
  const lever::Model m = lever::mjcf::load_string(
      R"(<mujoco><worldbody><body><joint name="j"/><geom size="0.1"/></body></worldbody>
      <actuator><general name="wrist_filter" joint="j" dyntype="filter"/></actuator></mujoco>)",
      "filter.xml");
  lever::Data dm(m);
  lever::forward(m, dm);
  lever::Derivatives deriv_m(m);
  // activations are differentiated now: a filter's force is its activation (gain 1), so
  // d qacc / d act is the joint's inverse inertia
  lever::forward_derivatives(m, dm, deriv_m);
  REQUIRE(deriv_m.dqacc_dact.rows() == 1);
  REQUIRE(deriv_m.dqacc_dact.cols() == 1);
  CHECK(deriv_m.dqacc_dact(0, 0) == Approx(dm.qLDiagInv[0]).epsilon(1e-12));
  // a body transmission's moment follows the contacts: not differentiated
  const lever::Model a =
      lever::mjcf::load_file(lever::test::model_path("tests/models/actuators/adhesion.xml"));
  lever::Data da(a);
  lever::forward(a, da);
  lever::Derivatives deriv_a(a);
  CHECK_THROWS_WITH(lever::step_derivatives(a, da, deriv_a),
                    Catch::Contains("actuator 'pad' drives a body through its contacts"));
}

TEST_CASE("the derivative tests' models compile to MuJoCo 2.2.2's parameters",
          "[compile][actuators][derivatives]") {
  // tests/derivatives load these through lever's reader: actuators on sites (with and without a
  // reference site; motor, position, general), servos with an affine bias, actuators on spatial
  // tendons
  for (const char* name : {"site_actuators.xml", "refsite_actuators.xml", "servo_affine.xml",
                           "spatial_tendons.xml"}) {
    const std::string path = lever::test::model_path(std::string("tests/derivatives/") + name);
    check_compiles_as_mujoco(name, lever::test::read_text(path));
  }
  const lever::Model thrusters =
      lever::mjcf::load_file(lever::test::model_path("tests/derivatives/site_actuators.xml"));
  CHECK(thrusters.actuator_trntype[0] == lever::TransmissionType::kSite);
}
