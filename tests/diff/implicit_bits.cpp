// MuJoCo 2.2.2's implicit step on its cloth flag (flag.xml: 340 dofs in chains 51 deep, fluid
// drag in a wind): (M - h D) qacc = f, with M^-1 entries up to 1e6, magnifies the last bits of D.
// lever forms D in mjd_smooth_vel's order (the actuators, the dampers, the fluid's rows one by
// one as mjd_inertiaBoxFluid adds them, then minus the bias force's derivative), factors M - h D
// as mju_factorLUSparse does and solves as mju_solveLUSparse does (each row's ancestors root
// first). So at rest, where the bias force's derivative is zero, D, the factor and the step's
// qvel are MuJoCo's to the bit; in motion, lever's factor and solve given MuJoCo's own D give
// MuJoCo's qvel to the bit. What remains is the bias force's velocity derivative: lever's
// (Carpentier and Mansard's recursion, derivatives/inverse_dynamics.cpp) and MuJoCo's
// (mjd_rne_vel, the chain rule through dense 6 x nv matrices of every body) are different
// algorithms, within 2e-16 of each other element by element, and the solve magnifies that to
// 1.4 times the 1e-12 bound in the flag's qvel (tests/diff/composites.cpp).
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

#include "pipeline/pipeline.hpp"
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

TEST_CASE("diff: the flag's implicit step is MuJoCo's but for the bias force's derivative",
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
    INFO("state " << k);
    const SparseApart D = sparse_apart(m, d, twin.data.work.qDeriv, d->qDeriv);
    if (k == 0) {
      ++at_rest;
      CHECK(D.differing == 0);
      CHECK(sparse_apart(m, d, twin.data.work.qLU, d->qLU).differing == 0);
      for (int i = 0; i < nv; ++i) CHECK(twin.data.qvel[i] == d->qvel[i]);
      continue;
    }
    ++moving;
    worst_D = std::max(worst_D, D.worst);
    CHECK(D.worst <= 1e-15);
    // MuJoCo's D through lever's factor and solve, from the same start
    const Eigen::VectorXd mujoco_qvel = Eigen::Map<const Eigen::VectorXd>(d->qvel, nv);
    Eigen::MatrixXd K = Eigen::MatrixXd::Zero(nv, nv);
    for (int r = 0; r < nv; ++r) {
      for (int j = 0; j < d->D_rownnz[r]; ++j) {
        const int adr = d->D_rowadr[r] + j;
        K(r, d->D_colind[adr]) = d->qDeriv[adr];
      }
    }
    twin.set_state(s);
    forward(twin.model, twin.data);
    K = twin.data.M - twin.model.opt.timestep * K;
    factor_lu_tree(twin.model, K);
    CHECK(sparse_apart(m, d, K, d->qLU).differing == 0);
    Eigen::VectorXd qacc = twin.data.qfrc_smooth + twin.data.qfrc_constraint;
    solve_lu_tree(twin.model, K, qacc.data(), twin.data.work.dof_chain.data());
    const Eigen::VectorXd qvel = twin.data.qvel + twin.model.opt.timestep * qacc;
    for (int i = 0; i < nv; ++i) CHECK(qvel[i] == mujoco_qvel[i]);
  }
  WARN("flag.xml's implicit step: at rest D, its factor and qvel are MuJoCo's to the bit; in "
       << moving << " moving states D within " << worst_D
       << " of MuJoCo's (relative), and MuJoCo's D through lever's factor and solve gives "
          "MuJoCo's qvel to the bit");
}

}  // namespace lever::test
