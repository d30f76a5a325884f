// The step's derivatives through spatial tendons of straight segments, whose Jacobian moves with
// the pose: tests/derivatives/spatial_tendons.xml (springs and dampers, pulleys, a limit row and a
// friction-loss row, a motor, a position servo, an affine <general> and a muscle on spatial
// tendons; a ball wrist). Under Euler, RK4 and implicit, against centred differences of lever's
// own step (eps 1e-6) and of MuJoCo 2.2.2's mj_step at tolerance 0 (eps 1e-6 and 1e-5;
// step_differences.hpp), within 1e-6 of the matrix's scale, computed both ways here; and the same
// on tests/models/constraints/spatial_tendons.xml, whose tendons wrap around cylinders and a
// sphere (side sites outside and inside them) and are coupled by an equality constraint.
// lever's model comes from its own reader (what users get; tests/compile checks that it compiles
// to MuJoCo's parameters), MuJoCo's from its compiler.
#include <catch2/catch.hpp>
#include <lever/diff/twin.hpp>

#include <lever/derivatives.hpp>
#include <lever/lever.hpp>

#include <string>

#include <lever/harness/models.hpp>
#include "step_checks.hpp"

namespace lever::test::spatial_tendon_derivatives {

using namespace lever::test::step_differences;

TEST_CASE("derivatives through spatial tendons of straight segments",
          "[derivatives][mujoco][tendons]") {
  diff::Twin twin(model_path("tests/derivatives/spatial_tendons.xml"), diff::Path::kLoader);
  converge(twin);
  const Model& model = twin.model;
  REQUIRE(model.nv == 6);
  State s = state_of(model);
  for (int i = 0; i < model.nv; ++i) s.qvel[i] = 0.5 * ((i * 3 % 7) - 3) / 3.0 + 0.1;
  Eigen::VectorXd dq(model.nv);
  for (int i = 0; i < model.nv; ++i) dq[i] = 0.4 * ((i * 5 % 7) - 3) / 3.0 + 0.05;
  integrate_pos(model, s.qpos, dq, 1.0);
  s.ctrl << 0.3, -0.5, 0.6, 0.7;
  s.act << 0.4;
  {  // the rows that push at the state: the limit's and the friction loss's
    Data data(model);
    apply(s, data);
    forward(model, data);
    int limits = 0, friction = 0;
    for (int r = 0; r < data.nefc; ++r) {
      INFO("row " << r << " state " << static_cast<int>(data.efc_state[r]));
      if (data.efc_type[r] == ConstraintType::kLimitTendon) {
        limits += data.efc_state[r] == ConstraintState::kActive;
      }
      if (data.efc_type[r] == ConstraintType::kFrictionTendon) {
        friction += data.efc_state[r] == ConstraintState::kActive;
      }
    }
    WARN("lengths " << data.ten_length.transpose() << "; limit rows pushing " << limits
                    << ", friction rows inside their box " << friction);
    CHECK(limits == 1);
    for (int a = 0; a < model.nu; ++a) CHECK(data.actuator_force[a] != 0);
  }
  for (const Integrator integrator :
       {Integrator::kEuler, Integrator::kRK4, Integrator::kImplicit}) {
    twin.set_integrator(integrator);
    const double worst = check_step_derivatives(twin, s);
    INFO("spatial_tendons.xml, " << integrator_name(integrator) << ": worst " << worst
                                 << " of the bound");
    CHECK(worst <= 1);
    WARN("spatial_tendons.xml, " << integrator_name(integrator) << ": worst " << worst
                                 << " of the bound");
  }
}

TEST_CASE("derivatives through spatial tendons wrapping spheres and cylinders",
          "[derivatives][mujoco][tendons]") {
  // tests/models/constraints/spatial_tendons.xml: arm26's cylinder wraps and more (side sites
  // outside and inside the geoms, a sphere, two geoms in one tendon, pulleys, a coupling of two
  // spatial tendons, limits, friction loss, springs, dampers, tendon actuators)
  diff::Twin twin(model_path("tests/models/constraints/spatial_tendons.xml"), diff::Path::kLoader);
  converge(twin);
  const Model& model = twin.model;
  State s = state_of(model);
  s.qpos << 0.5, 0.9, 0.3, 0.05;
  s.qvel << 0.4, -0.6, 0.3, 0.2;
  s.ctrl << 0.5, 0.8, -0.3;
  {  // the wraps that are on at the state: every kind the file has
    Data data(model);
    apply(s, data);
    forward(model, data);
    int wrapped = 0;
    for (int t = 0; t < model.ntendon; ++t) {
      for (int p = data.ten_wrapadr[t]; p < data.ten_wrapadr[t] + data.ten_wrapnum[t]; ++p) {
        if (data.wrap_obj[p / 2][p % 2] >= 0) ++wrapped;
      }
    }
    WARN("tangent points " << wrapped << ", rows " << data.nefc);
    CHECK(wrapped >= 10);
  }
  for (const Integrator integrator :
       {Integrator::kEuler, Integrator::kRK4, Integrator::kImplicit}) {
    twin.set_integrator(integrator);
    const double worst = check_step_derivatives(twin, s);
    INFO("constraints/spatial_tendons.xml, " << integrator_name(integrator) << ": worst " << worst
                                             << " of the bound");
    CHECK(worst <= 1);
    WARN("constraints/spatial_tendons.xml, " << integrator_name(integrator) << ": worst " << worst
                                             << " of the bound");
  }
}

}  // namespace lever::test::spatial_tendon_derivatives
