// The step's derivatives through actuators on sites without a reference site, whose moment turns
// with the site: tests/derivatives/site_actuators.xml (thrusters on a free body, one with its force
// clamped; an affine <general> at the tip of an arm with a ball wrist, whose velocity terms enter
// the implicit step's D), under Euler, RK4 and implicit, against centred differences of lever's
// own step (eps 1e-6) and of MuJoCo 2.2.2's mj_step (eps 1e-6 and 1e-5; step_differences.hpp),
// within 1e-6 of the matrix's scale, computed both ways here (a site with a reference site:
// refsite_actuators.cpp).
// lever's model comes from its own reader (what users get; tests/compile checks that it compiles
// to MuJoCo's parameters), MuJoCo's from its compiler.
#include <catch2/catch.hpp>
#include <lever/diff/twin.hpp>

#include <lever/derivatives.hpp>
#include <lever/lever.hpp>
#include <lever/mjcf.hpp>

#include <algorithm>
#include <string>

#include <lever/harness/models.hpp>
#include "step_checks.hpp"

namespace lever::test::site_actuator_derivatives {

using namespace lever::test::step_differences;

TEST_CASE("derivatives through site actuators (no reference site)",
          "[derivatives][mujoco][actuators]") {
  const std::string file = model_path("tests/derivatives/site_actuators.xml");
  diff::Twin twin(file, diff::Path::kLoader);
  converge(twin);
  const Model& model = twin.model;
  State s = state_of(model);
  for (int i = 0; i < model.nv; ++i) s.qvel[i] = 0.4 * ((i * 3 % 7) - 3) / 3.0;
  Eigen::VectorXd dq(model.nv);
  for (int i = 0; i < model.nv; ++i) dq[i] = 0.3 * ((i * 5 % 7) - 3) / 3.0;
  integrate_pos(model, s.qpos, dq, 1.0);
  s.ctrl << 1.2, 2.5, 0.6, 0.3;  // the second thruster's force, 2.5, is clamped at 0.5
  {
    Data data(model);
    apply(s, data);
    forward(model, data);
    CHECK(data.actuator_force[1] == 0.5);
    CHECK(data.actuator_force[0] != 0);
  }
  for (const Integrator integrator :
       {Integrator::kEuler, Integrator::kRK4, Integrator::kImplicit}) {
    twin.set_integrator(integrator);
    INFO(integrator_name(integrator));
    const double worst = check_step_derivatives(twin, s);
    INFO("site_actuators.xml, " << integrator_name(integrator) << ": worst " << worst
                                << " of the bound");
    CHECK(worst <= 1);
  }
}

}  // namespace lever::test::site_actuator_derivatives
