// set_const() refuses parameters that are not a physical model, with a sentence saying which:
// validate() (lever/model_check.hpp), which it runs before computing anything.
#include <catch2/catch.hpp>

#include <lever/lever.hpp>
#include <lever/mjcf.hpp>

#include <functional>
#include <limits>
#include <string>

#include <lever/harness/models.hpp>

namespace {

struct Case {
  const char* what;
  std::function<void(lever::Model&)> edit;
  const char* phrase;  // expected in the message
};

}  // namespace

TEST_CASE("set_const refuses non-physical or inconsistent parameters", "[model]") {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const Case cases[] = {
      {"zero timestep", [](lever::Model& m) { m.opt.timestep = 0; }, "timestep"},
      {"negative timestep", [](lever::Model& m) { m.opt.timestep = -0.002; }, "timestep"},
      {"NaN timestep", [nan](lever::Model& m) { m.opt.timestep = nan; }, "timestep"},
      {"infinite gravity",
       [](lever::Model& m) { m.opt.gravity.z() = -std::numeric_limits<double>::infinity(); },
       "gravity"},
      {"NaN mass", [nan](lever::Model& m) { m.body_mass[2] = nan; }, "mass"},
      {"negative mass", [](lever::Model& m) { m.body_mass[2] = -1; }, "mass"},
      {"negative inertia", [](lever::Model& m) { m.body_inertia[1].x() = -1e-4; }, "inertia"},
      {"zero body quaternion", [](lever::Model& m) { m.body_quat[1].setZero(); }, "quaternion"},
      {"NaN body position", [nan](lever::Model& m) { m.body_pos[2].y() = nan; }, "body_pos"},
      {"negative damping", [](lever::Model& m) { m.dof_damping[0] = -0.1; }, "damping"},
      {"negative armature", [](lever::Model& m) { m.dof_armature[1] = -0.1; }, "armature"},
      {"negative stiffness", [](lever::Model& m) { m.jnt_stiffness[0] = -1; }, "stiffness"},
      {"reversed range",
       [](lever::Model& m) {
         m.jnt_range[0] = {1.0, -1.0};
       },
       "range"},
      {"NaN solref", [nan](lever::Model& m) { m.jnt_solref[1][0] = nan; }, "jnt_solref"},
      {"reversed ctrlrange",
       [](lever::Model& m) {
         m.actuator_ctrlrange[0] = {5, -5};
       },
       "ctrlrange"},
      {"NaN gear", [nan](lever::Model& m) { m.actuator_gear[1][0] = nan; }, "gear"},
      {"axis not unit",
       [](lever::Model& m) {
         m.jnt_axis[0] = {0, -2, 0};
       },
       "axis"},
      {"parent after child", [](lever::Model& m) { m.body_parentid[1] = 2; }, "parent"},
      {"nq changed without the joints", [](lever::Model& m) { m.nq += 1; }, "nq = "},
      {"motor on no joint", [](lever::Model& m) { m.actuator_trnid[0][0] = 7; }, "names no joint"},
      {"body transmission on no body",
       [](lever::Model& m) {
         m.actuator_trntype[0] = lever::TransmissionType::kBody;
         m.actuator_trnid[0][0] = 99;
       },
       "names no body"},
      {"transmission type beyond MuJoCo's",
       [](lever::Model& m) { m.actuator_trntype[0] = static_cast<lever::TransmissionType>(6); },
       "not MuJoCo 2.2.2's"},
      {"a count changed since size_model", [](lever::Model& m) { m.nsite += 1; }, "size_model"},
      {"root id not the world child", [](lever::Model& m) { m.body_rootid[2] = 2; }, "body_rootid"},
      {"NaN geom size", [nan](lever::Model& m) { m.geom_size[0][0] = nan; }, "geom_size"},
      {"zero geom quaternion", [](lever::Model& m) { m.geom_quat[0].setZero(); }, "quaternion"},
      {"NaN qpos0", [nan](lever::Model& m) { m.qpos0[1] = nan; }, "qpos0"},
      {"reversed forcerange",
       [](lever::Model& m) {
         m.actuator_forcelimited[0] = 1;
         m.actuator_forcerange[0] = {1, -1};
       },
       "forcerange"},
  };
  const lever::Model good = lever::mjcf::load_file(lever::test::model_path("models/arm2.xml"));
  for (const Case& c : cases) {
    INFO(c.what);
    lever::Model model = good;
    c.edit(model);
    try {
      lever::set_const(model);
      FAIL("set_const accepted it");
    } catch (const lever::ModelError& e) {
      CHECK_THAT(e.what(), Catch::Matchers::Contains(c.phrase));
    }
  }
}

TEST_CASE("set_const recomputes the constants after a mass changes, as mj_setConst", "[model]") {
  lever::Model model = lever::mjcf::load_file(lever::test::model_path("models/arm2.xml"));
  const double before = model.dof_invweight0[0];
  model.body_mass[2] *= 2;  // the lesson's knowledge check doubles link 2
  lever::set_const(model);
  CHECK(model.dof_invweight0[0] < before);  // a heavier arm is harder to accelerate
  CHECK(model.body_subtreemass[1] == model.body_mass[1] + model.body_mass[2]);
}

TEST_CASE("set_const flags the passes forward() may skip: body transmission, friction loss",
          "[model]") {
  lever::Model arm = lever::mjcf::load_file(lever::test::model_path("models/arm2.xml"));
  CHECK_FALSE(arm.has_body_transmission);
  CHECK_FALSE(arm.has_friction_loss);
  arm.dof_frictionloss[1] = 0.1;  // an edit, then set_const, as after any parameter edit
  lever::set_const(arm);
  CHECK(arm.has_friction_loss);
  const lever::Model adhesion =
      lever::mjcf::load_file(lever::test::model_path("tests/models/actuators/adhesion.xml"));
  CHECK(adhesion.has_body_transmission);
  const lever::Model friction = lever::mjcf::load_file(
      lever::test::model_path("tests/models/constraints/friction_loss.xml"));
  CHECK(friction.has_friction_loss);
}

TEST_CASE("validate names the object at fault, so that a loader can point at its element",
          "[model]") {
  const lever::Model good = lever::mjcf::load_file(lever::test::model_path("models/arm2.xml"));
  CHECK_NOTHROW(lever::validate(good));
  struct Located {
    const char* what;
    std::function<void(lever::Model&)> edit;
    const char* object;
    int index;
    const char* phrase;
  };
  const Located cases[] = {
      // a dof's array belongs to the dof's joint; a qpos entry's to the joint that has it
      {"negative damping of dof 1", [](lever::Model& m) { m.dof_damping[1] = -0.1; }, "joint", 1,
       "joint 'elbow' has a negative dof_damping -0.1"},
      {"infinite qpos0 of joint 0",
       [](lever::Model& m) { m.qpos0[0] = std::numeric_limits<double>::infinity(); }, "joint", 0,
       "non-finite qpos0"},
      {"negative mass of link 2", [](lever::Model& m) { m.body_mass[2] = -1; }, "body", 2,
       "negative body_mass"},
      {"reversed ctrlrange",
       [](lever::Model& m) {
         m.actuator_ctrlrange[1] = {5, -5};
       },
       "actuator", 1, "actuator_ctrlrange (5, -5)"},
  };
  for (const Located& c : cases) {
    INFO(c.what);
    lever::Model model = good;
    c.edit(model);
    const lever::Model edited = model;
    try {
      lever::validate(model);
      FAIL("validate accepted it");
    } catch (const lever::ModelError& e) {
      CHECK(e.object() == c.object);
      CHECK(e.index() == c.index);
      CHECK_THAT(e.what(), Catch::Matchers::Contains(c.phrase));
    }
    CHECK(model.body_mass == edited.body_mass);  // validate changes nothing
  }
}

TEST_CASE("set_const leaves body_rootid as the compiler recorded it", "[model]") {
  lever::Model model = lever::mjcf::load_file(lever::test::model_path("models/arm2.xml"));
  // arm2: the world, then link1 under it and link2 under link1: both hang from link1
  CHECK(model.body_rootid == std::vector<int>{0, 1, 1});
  lever::set_const(model);
  CHECK(model.body_rootid == std::vector<int>{0, 1, 1});
}

TEST_CASE("set_const recomputes what it derives, whatever those arrays held", "[model]") {
  lever::Model model = lever::mjcf::load_file(lever::test::model_path("models/arm2.xml"));
  const lever::Model loaded = model;
  std::fill(model.body_subtreemass.begin(), model.body_subtreemass.end(), -1.0);
  std::fill(model.body_invweight0.begin(), model.body_invweight0.end(),
            std::array<double, 2>{-1.0, -1.0});
  std::fill(model.dof_invweight0.begin(), model.dof_invweight0.end(), -1.0);
  std::fill(model.dof_M0.begin(), model.dof_M0.end(), -1.0);
  std::fill(model.actuator_scalar_dof.begin(), model.actuator_scalar_dof.end(), 7);
  CHECK_NOTHROW(lever::validate(model));
  lever::set_const(model);
  CHECK(model.body_subtreemass == loaded.body_subtreemass);
  CHECK(model.dof_invweight0 == loaded.dof_invweight0);
  CHECK(model.dof_M0 == loaded.dof_M0);
  CHECK(model.body_invweight0 == loaded.body_invweight0);
  CHECK(model.actuator_scalar_dof == loaded.actuator_scalar_dof);
  for (int a = 0; a < model.nu; ++a) {  // arm2's motors drive a hinge each
    CHECK(model.actuator_scalar_dof[a] == lever::actuator_scalar_dof(model, a));
    CHECK(model.actuator_scalar_dof[a] == model.jnt_dofadr[model.actuator_trnid[a][0]]);
  }
}
