// The harness's convergence of MuJoCo's solver (diff::mujoco_forward_converged): with elliptic
// cones MuJoCo's Newton solver can stop short of the minimizer even at tolerance 0, and the
// comparison needs the minimizer, the one lever's solve finds. Here MuJoCo's solver is cut short
// on purpose, on tests/diff/contact_scenes/free_objects.xml with elliptic cones:
//   one iteration per forward: a single mj_forward stops beyond the solver's bound from lever's
//     answer; restarted from its own answer, MuJoCo reaches it, never farther from the minimizer
//     by its own gradient than where it started;
//   no iterations (a solver that cannot move, as at a stall, where every restart stays put): the
//     answer it is stuck at, near the minimizer, is kept rather than the cold start's, which is
//     farther; mujoco_distance_to_minimizer tells the two apart.
#include <mujoco/mujoco.h>
#include <catch2/catch.hpp>

#include <lever/diff/report.hpp>
#include <lever/diff/twin.hpp>
#include <lever/lever.hpp>

#include <algorithm>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include <lever/harness/models.hpp>
#include <lever/harness/random_state.hpp>

namespace lever::test {

namespace {

constexpr const char* kRestartScene = "tests/diff/contact_scenes/free_objects.xml";

// |lever - mujoco| in qacc relative to max(1, |mujoco|).
// The contact solver's bound on qacc, relative (report.hpp's kContactSolverBound, in units of 1e-12).
constexpr double kSolverBound = diff::kContactSolverBound * 1e-12;

double qacc_gap(const Data& data, const mjData* d, int nv) {
  double gap = 0, scale = 1;
  for (int i = 0; i < nv; ++i) {
    gap = std::max(gap, std::abs(data.qacc[i] - d->qacc[i]));
    scale = std::max(scale, std::abs(d->qacc[i]));
  }
  return gap / scale;
}

}  // namespace

TEST_CASE("diff: MuJoCo's solver, one iteration per forward, is restarted to the minimizer",
          "[diff][elliptic][restart]") {
  REQUIRE(mj_version() == 222);
  diff::Twin twin(model_path(kRestartScene), diff::Path::kEngine);
  twin.set_cone(Cone::kElliptic, 1.0);
  REQUIRE(twin.restart_mujoco_solver);
  twin.m->opt.iterations = 1;
  const mjModel* m = twin.m.get();
  mjData* d = twin.d.get();
  std::mt19937_64 rng(seed_for(kRestartScene));
  int short_of_it = 0, with_rows = 0;
  for (int k = 0; k < 40; ++k) {
    State s = random_state(twin.model, rng);
    if (k % 4 == 0) s.qvel.setZero();
    twin.set_state(s);
    forward(twin.model, twin.data);
    mj_forward(m, d);  // one Newton iteration from qacc_smooth
    if (d->nefc == 0) continue;
    ++with_rows;
    const double one_forward = qacc_gap(twin.data, d, m->nv);
    const double one_distance = diff::mujoco_distance_to_minimizer(m, d);
    short_of_it += one_forward > kSolverBound;
    diff::set_mujoco_state(m, d, s);
    diff::mujoco_forward_converged(m, d, true);
    INFO("state " << k << ": one forward " << one_forward << " from lever's qacc, converged "
                  << qacc_gap(twin.data, d, m->nv));
    CHECK(qacc_gap(twin.data, d, m->nv) <= kSolverBound);
    CHECK(diff::mujoco_distance_to_minimizer(m, d) <= std::max(diff::kStalled, one_distance));
  }
  CHECK(with_rows > 20);
  CHECK(short_of_it > 10);  // one iteration stopped short: the restarts had work to do
}

TEST_CASE("diff: a stuck MuJoCo answer nearer the minimizer than a cold start's is kept",
          "[diff][elliptic][restart]") {
  REQUIRE(mj_version() == 222);
  diff::Twin twin(model_path(kRestartScene), diff::Path::kEngine);
  twin.set_cone(Cone::kElliptic, 1.0);
  const mjModel* m = twin.m.get();
  mjData* d = twin.d.get();
  std::mt19937_64 rng(seed_for(kRestartScene));
  int tried = 0;
  for (int k = 0; k < 40 && tried < 5; ++k) {
    State s = random_state(twin.model, rng);
    if (k % 4 == 0) s.qvel.setZero();
    twin.set_state(s);
    forward(twin.model, twin.data);
    if (twin.data.nefc == 0) continue;
    ++tried;
    // MuJoCo warm-started 1e-6 (relative) off lever's answer, its solver unable to move
    twin.m->opt.iterations = 0;
    std::vector<double> stuck(twin.data.qacc.data(), twin.data.qacc.data() + m->nv);
    double scale = 1;
    for (double a : stuck) scale = std::max(scale, std::abs(a));
    stuck[0] += 1e-6 * scale;
    std::copy(stuck.begin(), stuck.end(), d->qacc_warmstart);
    const diff::ForwardInputs given(m, d);
    mj_forward(m, d);
    INFO("state " << k);
    REQUIRE(std::memcmp(d->qacc, stuck.data(), sizeof(double) * stuck.size()) == 0);
    const double at_stuck = diff::mujoco_distance_to_minimizer(m, d);
    CHECK(at_stuck > diff::kStalled);  // the gradient sees it is short of the minimizer
    diff::converge_mujoco_solver(m, d, given);  // restarts stay put; the cold start is qacc_smooth
    CHECK(std::memcmp(d->qacc, stuck.data(), sizeof(double) * stuck.size()) == 0);
    CHECK(diff::mujoco_distance_to_minimizer(m, d) == at_stuck);
    // and at lever's answer MuJoCo's gradient is rounding
    std::copy(twin.data.qacc.data(), twin.data.qacc.data() + m->nv, d->qacc);
    CHECK(diff::mujoco_distance_to_minimizer(m, d) <= diff::kStalled);
    twin.m->opt.iterations = 1000;
  }
  CHECK(tried == 5);
}

}  // namespace lever::test
