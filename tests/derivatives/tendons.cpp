// The step's derivatives through fixed tendons (their Jacobian is constant in qpos): the tendons'
// springs and dampers, tendon actuators (a motor, a position servo, an affine general actuator,
// whose moment is gear ten_J), the rows of tendon limits, tendon and dof friction loss (inside
// their box), joint and tendon couplings (a polynomial whose Jacobian moves with qpos), and the
// implicit step's tendon terms. Against centred differences of lever's own step (eps 1e-6) and of
// MuJoCo 2.2.2's mj_step at tolerance 0 (eps 1e-6 and 1e-5; step_differences.hpp), within 1e-6 of
// the matrix's scale, under Euler, RK4 and implicit, at states whose rows keep their active set
// inside every difference: tests/models/constraints/tendons.xml and friction_loss.xml, and
// Menagerie 2022's Franka Panda hand (a tendon actuator and a joint coupling), computed both ways
// here.
#include <catch2/catch.hpp>
#include <lever/diff/twin.hpp>

#include <lever/derivatives.hpp>
#include <lever/lever.hpp>
#include <lever/mjcf.hpp>

#include <filesystem>
#include <string>

#include <lever/harness/models.hpp>
#include "step_checks.hpp"
#include "robots.hpp"

namespace lever::test::tendon_derivatives {

namespace {

using namespace lever::test::step_differences;

constexpr Integrator kTendonIntegrators[] = {Integrator::kEuler, Integrator::kRK4,
                                             Integrator::kImplicit};

// How many rows of each kind exert a force at the state (friction loss inside its box).
struct RowKinds {
  int tendon_limit = 0, tendon_friction = 0, dof_friction = 0, equality = 0, friction_at_bound = 0;
};

RowKinds row_kinds(const Model& model, const State& s) {
  Data data(model);
  apply(s, data);
  forward(model, data);
  RowKinds k;
  for (int r = 0; r < data.nefc; ++r) {
    const ConstraintState state = data.efc_state[r];
    if (state == ConstraintState::kLinearNeg || state == ConstraintState::kLinearPos) {
      ++k.friction_at_bound;
      continue;
    }
    if (state != ConstraintState::kActive) continue;
    switch (data.efc_type[r]) {
      case ConstraintType::kLimitTendon: ++k.tendon_limit; break;
      case ConstraintType::kFrictionTendon: ++k.tendon_friction; break;
      case ConstraintType::kFrictionDof: ++k.dof_friction; break;
      case ConstraintType::kEquality: ++k.equality; break;
      default: break;
    }
  }
  return k;
}

}  // namespace

TEST_CASE("derivatives through fixed tendons: springs, actuators, limits, friction loss, couplings",
          "[derivatives][mujoco][tendons]") {
  const std::string file = model_path("tests/models/constraints/tendons.xml");
  for (const Integrator integrator : kTendonIntegrators) {
    diff::Twin twin(file, diff::Path::kEngine);
    twin.set_integrator(integrator);
    converge(twin);
    State s = state_of(twin.model);
    reset_keyframe(twin.model, twin.data, "bent");
    s.qpos = twin.data.qpos;
    s.qvel = twin.data.qvel;
    s.ctrl = twin.data.ctrl;
    {  // the keyframe: the arm's flexion past its limit, the couplings pulling
      const RowKinds k = row_kinds(twin.model, s);
      CHECK(k.tendon_limit >= 1);
      CHECK(k.equality == 2);
      INFO("tendons.xml at 'bent'");
      const double worst = check_step_derivatives(twin, s);
      UNSCOPED_INFO("tendons.xml at 'bent': worst " << worst << " of the bound");
    }
    {  // slow, the tendons' friction loss raised to 1000 on both sides: inside its box (a
       // quadratic row, its force -D (J qacc + B J qvel))
      for (int t = 0; t < twin.model.ntendon; ++t) {
        if (twin.model.tendon_frictionloss[t] > 0) {
          twin.model.tendon_frictionloss[t] = 1000;
          twin.m->tendon_frictionloss[t] = 1000;
        }
      }
      State slow = s;
      slow.qvel *= 1e-3;
      const RowKinds k = row_kinds(twin.model, slow);
      CHECK(k.tendon_friction >= 1);
      CHECK(k.tendon_limit >= 1);
      INFO("tendons.xml slow");
      const double worst = check_step_derivatives(twin, slow);
      UNSCOPED_INFO("tendons.xml slow: worst " << worst << " of the bound");
    }
  }
}

TEST_CASE("derivatives through dof friction loss", "[derivatives][mujoco][tendons]") {
  const std::string file = model_path("tests/models/constraints/friction_loss.xml");
  for (const Integrator integrator : kTendonIntegrators) {
    diff::Twin twin(file, diff::Path::kEngine);
    twin.set_integrator(integrator);
    converge(twin);
    State s = state_of(twin.model);
    for (int i = 0; i < twin.model.nv; ++i) s.qvel[i] = 1e-3 * (i % 2 ? 1 : -1) * (1 + i);
    const RowKinds k = row_kinds(twin.model, s);
    CHECK(k.dof_friction >= 1);
    INFO("friction_loss.xml");
    const double worst = check_step_derivatives(twin, s);
    UNSCOPED_INFO("friction_loss.xml: worst " << worst << " of the bound");
  }
}

TEST_CASE("derivatives through fixed tendons: Menagerie's Franka Panda hand",
          "[derivatives][mujoco][tendons][robots]") {
  const std::string folder = robots_dir();
  if (!robots_present(folder)) return;
  const std::string file = folder + "/menagerie-2022/franka_emika_panda/hand.xml";
  for (const Integrator integrator : kTendonIntegrators) {
    diff::Twin twin(file, diff::Path::kEngine);
    twin.set_integrator(integrator);
    converge(twin);
    State s = state_of(twin.model);
    s.qpos << 0.02, 0.025;
    s.qvel << 0.05, -0.03;
    s.ctrl << 120;
    const RowKinds k = row_kinds(twin.model, s);
    CHECK(k.equality == 1);
    INFO("Panda hand");
    const double worst = check_step_derivatives(twin, s);
    UNSCOPED_INFO("Panda hand: worst " << worst << " of the bound");
  }
}

}  // namespace lever::test::tendon_derivatives

namespace lever::test::tendon_derivatives {

}  // namespace lever::test::tendon_derivatives
