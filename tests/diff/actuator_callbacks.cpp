// User-defined actuator parts (gaintype, biastype, dyntype "user"): the model's callbacks
// (Model::actuator_gain_callback, actuator_bias_callback, actuator_dyn_callback), MuJoCo's
// mjcb_act_gain, mjcb_act_bias and mjcb_act_dyn. Callbacks that compute a fixed gain, an affine
// bias and a filter's rate from the actuator's own parameters give the built-in types' numbers
// bit for bit (Euler and RK4; the implicit integrator differentiates a built-in affine bias in
// velocity and not a callback, in lever as in MuJoCo), and agree with MuJoCo 2.2.2 given the same
// callbacks, step by step under every integrator.
#include <mujoco/mujoco.h>
#include <catch2/catch.hpp>

#include <lever/diff/report.hpp>
#include <lever/diff/runs.hpp>
#include <lever/diff/twin.hpp>
#include <lever/lever.hpp>
#include <lever/mjcf.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

#include "diff_checks.hpp"

namespace lever::test {

namespace {

// Two hinges, a motor-like actuator, a servo with an affine bias and a filter with dynamics;
// `kind` is "user" or the built-in types' names.
std::string callback_arm(bool user) {
  const std::string gain = user ? "user" : "fixed", bias = user ? "user" : "affine",
                    dyn = user ? "user" : "filter";
  return R"(<mujoco model="actuator callbacks">
  <compiler autolimits="true"/>
  <option timestep="0.002"/>
  <worldbody>
    <body name="upper" pos="0 0 1">
      <joint name="shoulder" axis="0 1 0" damping="0.5"/>
      <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.04"/>
      <body name="lower" pos="0.3 0 0">
        <joint name="elbow" axis="0 1 0" damping="0.2"/>
        <geom type="capsule" fromto="0 0 0 0.25 0 0" size="0.03"/>
      </body>
    </body>
  </worldbody>
  <actuator>
    <general name="motor" joint="shoulder" gaintype=")" + gain + R"(" gainprm="2.5" ctrlrange="-1 1"/>
    <general name="servo" joint="elbow" gaintype=")" + gain + R"(" gainprm="12" biastype=")" + bias +
         R"(" biasprm="0 -12 -0.7" ctrlrange="-1 1"/>
    <general name="filtered" joint="elbow" dyntype=")" + dyn + R"(" dynprm="0.04" gaintype=")" +
         gain + R"(" gainprm="1.5" ctrlrange="-1 1"/>
  </actuator>
</mujoco>)";
}

// The built-in types, as callbacks: lever's ...
double lever_fixed_gain(const Model& m, const Data&, int a) { return m.actuator_gainprm[a][0]; }
double lever_affine_bias(const Model& m, const Data& d, int a) {
  const auto& b = m.actuator_biasprm[a];
  if (m.actuator_biastype[a] != BiasType::kUser) return 0.0;
  return b[0] + b[1] * d.actuator_length[a] + b[2] * d.actuator_velocity[a];
}
double lever_filter_rate(const Model& m, const Data& d, int a) {
  const int j = a - (m.nu - m.na);
  return (d.ctrl[a] - d.act[j]) / std::max(1e-15, m.actuator_dynprm[a][0]);
}

// ... and MuJoCo's (plain functions, as mjcb_* are)
mjtNum mujoco_fixed_gain(const mjModel* m, const mjData*, int a) {
  return m->actuator_gainprm[mjNGAIN * a];
}
mjtNum mujoco_affine_bias(const mjModel* m, const mjData* d, int a) {
  const mjtNum* b = m->actuator_biasprm + mjNBIAS * a;
  if (m->actuator_biastype[a] != mjBIAS_USER) return 0.0;
  return b[0] + b[1] * d->actuator_length[a] + b[2] * d->actuator_velocity[a];
}
mjtNum mujoco_filter_rate(const mjModel* m, const mjData* d, int a) {
  const int j = a - (m->nu - m->na);
  return (d->ctrl[a] - d->act[j]) / std::max(1e-15, m->actuator_dynprm[mjNDYN * a]);
}

void set_lever_callbacks(Model& m) {
  m.actuator_gain_callback = lever_fixed_gain;
  m.actuator_bias_callback = lever_affine_bias;
  m.actuator_dyn_callback = lever_filter_rate;
}

// MuJoCo's callbacks set for the test's duration (they are global), cleared after it.
struct MujocoActuatorCallbacks {
  MujocoActuatorCallbacks() {
    mjcb_act_gain = mujoco_fixed_gain;
    mjcb_act_bias = mujoco_affine_bias;
    mjcb_act_dyn = mujoco_filter_rate;
  }
  ~MujocoActuatorCallbacks() {
    mjcb_act_gain = nullptr;
    mjcb_act_bias = nullptr;
    mjcb_act_dyn = nullptr;
  }
  MujocoActuatorCallbacks(const MujocoActuatorCallbacks&) = delete;
  MujocoActuatorCallbacks& operator=(const MujocoActuatorCallbacks&) = delete;
};

}  // namespace

TEST_CASE("user actuator callbacks that compute a built-in type give its numbers bit for bit",
          "[diff][actuators][callbacks]") {
  Model builtin = mjcf::load_string(callback_arm(false));
  Model user = mjcf::load_string(callback_arm(true));
  REQUIRE(user.actuator_gaintype[0] == GainType::kUser);
  REQUIRE(user.actuator_biastype[1] == BiasType::kUser);
  REQUIRE(user.actuator_dyntype[2] == DynType::kUser);
  set_lever_callbacks(user);
  for (const Integrator integrator : {Integrator::kEuler, Integrator::kRK4}) {
    builtin.opt.integrator = user.opt.integrator = integrator;
    Data a(builtin), b(user);
    int same = 0, steps = 0;
    for (int k = 0; k < 300; ++k) {
      for (int u = 0; u < builtin.nu; ++u) a.ctrl[u] = b.ctrl[u] = std::sin(0.01 * k + u);
      step(builtin, a);
      step(user, b);
      ++steps;
      same += a.qpos == b.qpos && a.qvel == b.qvel && a.act == b.act &&
              a.actuator_force == b.actuator_force && a.act_dot == b.act_dot;
    }
    INFO(integrator_name(integrator));
    CHECK(same == steps);
  }
  // without callbacks, MuJoCo's values: gain 1, bias 0, act_dot 0
  Model bare = mjcf::load_string(callback_arm(true));
  Data d(bare);
  d.ctrl.setConstant(0.5);
  d.act.setConstant(0.25);
  forward(bare, d);
  CHECK(d.actuator_force[0] == 0.5);
  CHECK(d.actuator_force[1] == 0.5);
  CHECK(d.actuator_force[2] == 0.25);
  CHECK(d.act_dot[0] == 0.0);
  // a callback has no derivative lever could know: refused by the actuator's name
  Derivatives deriv(user);
  Data e(user);
  CHECK_THROWS_WITH(forward_derivatives(user, e, deriv), Catch::Contains("gaintype \"user\""));
  CHECK_THROWS_WITH(step_derivatives(user, e, deriv), Catch::Contains("callback"));
}

TEST_CASE("user actuator callbacks agree with MuJoCo's mjcb_act_* in lockstep",
          "[diff][actuators][callbacks]") {
  REQUIRE(mj_version() == 222);
  const std::filesystem::path file =
      std::filesystem::temp_directory_path() / "lever_actuator_callbacks.xml";
  std::ofstream(file) << callback_arm(true);
  const MujocoActuatorCallbacks mujoco_callbacks;
  for (const diff::Path path : paths_to_compare()) {
    for (const Integrator integrator : kEveryIntegrator) {
      diff::Twin twin(file.string(), path);
      set_lever_callbacks(twin.model);
      INFO(diff::path_name(path) << " path, " << integrator_name(integrator));
      check_within_bound(diff::lockstep(twin, integrator, 0.4, diff::Control::kSmooth));
    }
  }
  std::filesystem::remove(file);
}

}  // namespace lever::test
