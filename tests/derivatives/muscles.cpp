// The step's derivatives through actuators with activation dynamics: tests/models/actuators/
// muscles.xml (a motor, a filter, an integrator with actrange, muscles on joints and on a fixed
// tendon with a negative gear, a <general> muscle), whose state carries the activations:
// A is (2nv + na) square and B (2nv + na) x nu, in mjd_transitionFD's layout. Under Euler (the
// joints are damped: its implicit damping), RK4 and implicit, against centred differences of
// lever's own step (eps 1e-6) and of MuJoCo 2.2.2's mj_step (eps 1e-6 and 1e-5;
// step_differences.hpp), within 1e-6 of the matrix's scale, computed both ways here: at two
// states where muscles shorten and lengthen and some are stretched past their optimal length (their
// passive force on), the integrator's activation clamped at its actrange by the step at the second
// (its row then zero).
// lever's model comes from its own reader (what users get; tests/compile checks that it compiles
// to MuJoCo's parameters), MuJoCo's from its compiler.
#include <catch2/catch.hpp>
#include <lever/diff/twin.hpp>

#include <lever/derivatives.hpp>
#include <lever/lever.hpp>

#include <string>

#include <lever/harness/models.hpp>
#include "step_checks.hpp"

namespace lever::test::muscle_derivatives {

using namespace lever::test::step_differences;

namespace {

State muscle_state(const Model& model, const Eigen::Vector3d& qpos, const Eigen::Vector3d& qvel,
                   double integrator_ctrl, double integrator_act) {
  State s = state_of(model);  // the file's keyframe "tense"'s controls and activations
  s.qpos = qpos;
  s.ctrl << 0.2, 0.5, -0.3, 0.8, 0.6, 0.4, 0.9;
  s.act << 0.1, 0.0, 0.3, 0.2, 0.5, 0.7;
  s.qvel = qvel;
  s.ctrl[2] = integrator_ctrl;
  s.act[1] = integrator_act;
  return s;
}

}  // namespace

TEST_CASE("derivatives through muscles and activation dynamics", "[derivatives][mujoco][actuators]") {
  diff::Twin twin(model_path("tests/models/actuators/muscles.xml"), diff::Path::kLoader);
  converge(twin);
  const Model& model = twin.model;
  REQUIRE(model.na == 6);
  const int integrator = model.actuator("wrist_integrator");
  REQUIRE(integrator == 2);
  struct Case {
    const char* name;
    State state;
    bool integrator_clamped;
  };
  const Case cases[] = {
      {"shortening and lengthening", muscle_state(model, {0.3, 2.0, -0.2}, {0.4, -0.7, 0.5}, -0.3, 0.3), false},
      {"the integrator's activation clamped",
       muscle_state(model, {-1.1, 0.2, 0.4}, {-0.2, 0.6, -0.9}, 0.8, 0.4999), true},
  };
  for (const Case& c : cases) {
    INFO(c.name);
    {  // the muscles pull, and the integrator's activation leaves its range in the step or not
      Data data(model);
      apply(c.state, data);
      forward(model, data);
      int stretched = 0, shortening = 0;  // muscles past their optimal length (passive force on)
      for (int a = 3; a < model.nu; ++a) {
        CHECK(data.actuator_force[a] < 0);
        const double passive = muscle_bias(data.actuator_length[a], model.actuator_lengthrange[a],
                                           model.actuator_acc0[a],
                                           model.actuator_biasprm[a].data());
        if (passive != 0) ++stretched;
        if (data.actuator_velocity[a] < 0) ++shortening;
      }
      CHECK(stretched > 0);
      CHECK(shortening > 0);
      CHECK(shortening < 4);
      const double next = data.act[1] + model.opt.timestep * data.act_dot[1];
      CHECK((next > model.actuator_actrange[integrator][1]) == c.integrator_clamped);
      CHECK(data.nefc == 0);
    }
    for (const Integrator integrator_kind :
         {Integrator::kEuler, Integrator::kRK4, Integrator::kImplicit}) {
      twin.set_integrator(integrator_kind);
      Derivatives deriv(model);
      REQUIRE(deriv.A.rows() == 2 * model.nv + model.na);
      REQUIRE(deriv.B.rows() == 2 * model.nv + model.na);
      const double worst = check_step_derivatives(twin, c.state);
      INFO("muscles.xml, " << c.name << ", " << integrator_name(integrator_kind) << ": worst "
                           << worst << " of the bound");
      CHECK(worst <= 1);
      WARN("muscles.xml, " << c.name << ", " << integrator_name(integrator_kind) << ": worst "
                           << worst << " of the bound");
    }
  }
}

}  // namespace lever::test::muscle_derivatives
