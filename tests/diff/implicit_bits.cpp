// MuJoCo 2.2.2's implicit step on its cloth flag (flag.xml: 340 dofs in chains 51 deep, fluid
// drag in a wind): (M - h D) qacc = f, with M^-1 entries up to 1e6, magnifies the last bits of D.
// lever forms D in mjd_smooth_vel's order (the actuators, the dampers, the fluid's rows one by
// one as mjd_inertiaBoxFluid adds them, then minus the bias force's derivative by mjd_rne_vel's
// chain rule, derivatives/bias_velocity_chain.cpp), factors M - h D as mju_factorLUSparse does
// and solves as mju_solveLUSparse does (each row's ancestors root first). So D, its factor and
// the step's qvel are MuJoCo's to the bit, at rest and in motion. (With Carpentier and Mansard's
// recursion for the bias force's derivative, the same matrix within 2e-16 element by element,
// the solve moved the flag's qvel by 1.4 times the 1e-12 bound.)
#include <mujoco/mujoco.h>
#include <catch2/catch.hpp>

#include <lever/diff/runs.hpp>
#include <lever/diff/twin.hpp>
#include <lever/forward.hpp>

#include <filesystem>
#include <random>
#include <string>

#include <lever/harness/models.hpp>
#include <lever/harness/random_state.hpp>

#include "robots.hpp"

namespace lever::test {

namespace {

// MuJoCo's sparse matrix (its D_rowadr, D_colind layout: M's non-zeros) against lever's dense
// one: how many elements differ, and the largest difference relative to max(1, |MuJoCo's|).
struct SparseApart {
  int differing = 0;
  double worst = 0.0;
};

SparseApart sparse_apart(const mjModel* m, const mjData* d, const Eigen::MatrixXd& ours,
                         const mjtNum* theirs) {
  SparseApart out;
  for (int r = 0; r < m->nv; ++r) {
    for (int j = 0; j < d->D_rownnz[r]; ++j) {
      const int adr = d->D_rowadr[r] + j, c = d->D_colind[adr];
      if (ours(r, c) == theirs[adr]) continue;
      ++out.differing;
      out.worst = std::max(out.worst, std::abs(ours(r, c) - theirs[adr]) /
                                          std::max(1.0, std::abs(theirs[adr])));
    }
  }
  return out;
}

}  // namespace

TEST_CASE("diff: the flag's implicit step is MuJoCo's to the bit, at rest and in motion",
          "[diff][robots][implicit]") {
  REQUIRE(mj_version() == 222);
  const std::string file = robots_dir() + "/mujoco-2.2.2/flag/flag.xml";
  if (!robots_present(file)) return;
  diff::Twin twin(file, diff::Path::kEngine);
  twin.set_integrator(Integrator::kImplicit);
  const mjModel* m = twin.m.get();
  mjData* d = twin.d.get();
  const int nv = m->nv;
  std::mt19937_64 rng(diff::default_seed(file));
  int at_rest = 0, moving = 0;
  double worst_D = 0.0;
  for (int k = 0; k < 4; ++k) {
    State s = random_state(twin.model, rng);
    if (k == 0) s.qvel.setZero();  // at rest: no bias derivative
    twin.set_state(s);
    step(twin.model, twin.data);
    mj_step(m, d);
    INFO("state " << k << (k == 0 ? " (at rest)" : " (moving)"));
    const SparseApart D = sparse_apart(m, d, twin.data.work.qDeriv, d->qDeriv);
    CHECK(D.differing == 0);
    worst_D = std::max(worst_D, D.worst);
    CHECK(sparse_apart(m, d, twin.data.work.qLU, d->qLU).differing == 0);
    int qvel_differing = 0;
    for (int i = 0; i < nv; ++i) qvel_differing += twin.data.qvel[i] != d->qvel[i];
    CHECK(qvel_differing == 0);
    (k == 0 ? at_rest : moving) += 1;
  }
  CHECK(moving == 3);
  WARN("flag.xml's implicit step, " << at_rest << " state at rest and " << moving
       << " moving: D, its factor and qvel are MuJoCo's to the bit (largest relative "
          "difference in D: " << worst_D << ")");
}

}  // namespace lever::test
