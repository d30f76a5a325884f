// set_const() refuses parameters that are not a physical model, with a sentence saying which.
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
      {"NaN body position", [nan](lever::Model& m) { m.body_pos[2].y() = nan; }, "position"},
      {"negative damping", [](lever::Model& m) { m.dof_damping[0] = -0.1; }, "damping"},
      {"negative armature", [](lever::Model& m) { m.dof_armature[1] = -0.1; }, "armature"},
      {"negative stiffness", [](lever::Model& m) { m.jnt_stiffness[0] = -1; }, "stiffness"},
      {"reversed range",
       [](lever::Model& m) {
         m.jnt_range[0] = {1.0, -1.0};
       },
       "range"},
      {"NaN solref", [nan](lever::Model& m) { m.jnt_solref[1][0] = nan; }, "limit parameters"},
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
      {"qpos0 too short", [](lever::Model& m) { m.qpos0.resize(1); }, "qpos0"},
      {"motor on no joint", [](lever::Model& m) { m.actuator_trnid[0] = 7; }, "names no joint"},
      {"array too short", [](lever::Model& m) { m.dof_damping.pop_back(); }, "dof_damping"},
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
