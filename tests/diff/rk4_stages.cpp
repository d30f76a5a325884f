// RK4 steps against MuJoCo 2.2.2, stage by stage (lever/diff/rk4.hpp). The harness's RK4 step
// is MuJoCo's own arithmetic: along MuJoCo's own stages it ends where mj_step does, bit for bit.
// Along lever's stages (MuJoCo evaluated at the states lever's step went through) every stage's
// acceleration and the step agree within the bound on the Robotiq 2F-85 with its mesh contacts,
// connects and tendon, where the two steps taken whole part by up to 1e-2 relative: the later
// stages start a few ulps apart (the solvers agree to their bound, not bit for bit), and the
// gripper's deep box-mesh contacts (MPR) are discontinuous there. MuJoCo against itself started
// 1e-15 away parts as far at those states: the test measures it.
#include <mujoco/mujoco.h>
#include <catch2/catch.hpp>

#include <lever/diff/compare.hpp>
#include <lever/diff/report.hpp>
#include <lever/diff/rk4.hpp>
#include <lever/diff/runs.hpp>
#include <lever/diff/twin.hpp>
#include <lever/lever.hpp>

#include <cstring>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include <lever/harness/models.hpp>
#include <lever/harness/random_state.hpp>
#include <lever/harness/tolerance.hpp>
#include "diff_checks.hpp"
#include "robots.hpp"

namespace lever::test {

namespace {

bool same_bits(const double* a, const double* b, int n) {
  return n == 0 || std::memcmp(a, b, sizeof(double) * static_cast<std::size_t>(n)) == 0;
}

// The largest |a - b| over the state (qpos, qvel) in units of the 1e-12 bound of b's magnitude.
double rk4_state_excess(const mjModel* m, const mjData* a, const mjData* b) {
  double worst = 0;
  const double qpos_scale = std::max(1.0, Eigen::Map<const Eigen::VectorXd>(b->qpos, m->nq)
                                              .lpNorm<Eigen::Infinity>());
  const double qvel_scale = std::max(1.0, Eigen::Map<const Eigen::VectorXd>(b->qvel, m->nv)
                                              .lpNorm<Eigen::Infinity>());
  for (int i = 0; i < m->nq; ++i) {
    worst = std::max(worst, std::abs(a->qpos[i] - b->qpos[i]) / (1e-12 * qpos_scale));
  }
  for (int i = 0; i < m->nv; ++i) {
    worst = std::max(worst, std::abs(a->qvel[i] - b->qvel[i]) / (1e-12 * qvel_scale));
  }
  return worst;
}

}  // namespace

TEST_CASE("diff: the harness's RK4 step is MuJoCo's mj_step bit for bit", "[diff][rk4]") {
  REQUIRE(mj_version() == 222);
  std::vector<std::string> files = {model_path("tests/diff/contact_scenes/legged_elliptic.xml")};
  const std::string gripper = robots_dir() + "/menagerie-2022/robotiq_2f85/2f85.xml";
  if (std::filesystem::exists(gripper)) files.push_back(gripper);
  for (const std::string& file : files) {
    INFO(file);
    diff::Twin twin(file, diff::Path::kEngine);
    const mjModel* m = twin.m.get();
    twin.m->opt.integrator = mjINT_RK4;
    std::mt19937_64 rng(seed_for(file));
    int with_rows = 0;
    for (int k = 0; k < 10; ++k) {
      const State s = random_state(twin.model, rng);
      MjDataPtr own = mujoco_data(m), replica = mujoco_data(m);
      diff::set_mujoco_state(m, own.get(), s);
      diff::set_mujoco_state(m, replica.get(), s);
      mj_step(m, own.get());
      diff::mujoco_rk4_step(m, replica.get(), false, nullptr, nullptr);
      INFO("state " << k);
      CHECK(own->time == replica->time);
      CHECK(same_bits(own->qpos, replica->qpos, m->nq));
      CHECK(same_bits(own->qvel, replica->qvel, m->nv));
      CHECK(same_bits(own->qacc, replica->qacc, m->nv));  // the last stage's
      CHECK(same_bits(own->qacc_warmstart, replica->qacc_warmstart, m->nv));
      REQUIRE(own->nefc == replica->nefc);
      CHECK(same_bits(own->efc_force, replica->efc_force, own->nefc));
      with_rows += own->nefc > 0;
    }
    CHECK(with_rows > 0);  // the stages had constraint rows to solve
  }
}

TEST_CASE("diff: an RK4 step with mesh contacts agrees with MuJoCo stage by stage",
          "[diff][rk4][robots]") {
  REQUIRE(mj_version() == 222);
  const std::string file = robots_dir() + "/menagerie-2022/robotiq_2f85/2f85.xml";
  if (!robots_present(file)) return;
  diff::Twin twin(file, diff::Path::kEngine);
  REQUIRE(twin.model.contacts_possible);
  twin.set_integrator(Integrator::kRK4);
  const mjModel* m = twin.m.get();
  diff::Report report;
  report.set_solver_bound(diff::kContactSolverBound);
  std::mt19937_64 rng(diff::default_seed(file));
  int with_contacts = 0, parted = 0;
  double worst_whole = 0, worst_nudged = 0;
  for (int k = 0; k < 20; ++k) {
    const State s = random_state(twin.model, rng);
    random_qacc(twin.model, rng);  // the states `lever diff` draws
    // lever's step, and MuJoCo's along its stages: each stage's velocity and acceleration
    twin.set_state(s);
    step(twin.model, twin.data);
    diff::MujocoRk4Stages stages;
    diff::mujoco_rk4_step(m, twin.d.get(), twin.restart_mujoco_solver, &twin.data.work.rk_qacc,
                          &stages);
    diff::compare_rk4_stages(twin.model, twin.data, stages, k, report, true);
    report.compare("qpos after one RK4 step", k, twin.data.qpos.data(), twin.d->qpos, m->nq,
                   diff::per_coordinate(twin.model));
    report.compare("qvel after one RK4 step", k, twin.data.qvel.data(), twin.d->qvel, m->nv,
                   [](int i) { return "dof " + std::to_string(i); });
    with_contacts += twin.d->ncon > 0;
    // MuJoCo's own RK4 step (its own stages), and the same from qpos + 1e-15
    MjDataPtr own = mujoco_data(m), nudged = mujoco_data(m);
    diff::set_mujoco_state(m, own.get(), s);
    diff::set_mujoco_state(m, nudged.get(), s);
    for (int i = 0; i < m->nq; ++i) nudged->qpos[i] += 1e-15;
    mj_step(m, own.get());
    mj_step(m, nudged.get());
    // the steps taken whole part where MuJoCo's own step parts from itself started 1e-15 away
    const double whole = rk4_state_excess(m, own.get(), twin.d.get());
    if (whole > diff::kContactSolverBound) {
      ++parted;
      const double nudge = rk4_state_excess(m, nudged.get(), own.get());
      INFO("state " << k << ": MuJoCo's own RK4 step " << whole
                    << " x 1e-12 from its step along lever's stages; from qpos + 1e-15, " << nudge
                    << " x 1e-12 from itself");
      CHECK(nudge > diff::kContactSolverBound);
      worst_whole = std::max(worst_whole, whole);
      worst_nudged = std::max(worst_nudged, nudge);
    }
  }
  CHECK(with_contacts > 10);
  CHECK(parted > 0);  // the states reach the discontinuity, or this test has not shown it
  INFO(file);
  check_within_bound(report);
  REQUIRE(report.find("qacc at an RK4 stage") != nullptr);
  CHECK(report.find("qacc at an RK4 stage")->compared == 20 * 3 * m->nv);
  WARN("2F-85, 20 random states: RK4 steps within the bound stage by stage; taken whole "
       << parted << " part by up to " << worst_whole << " x 1e-12, where MuJoCo from qpos + 1e-15 "
       << "parts from itself by up to " << worst_nudged << " x 1e-12");
}

}  // namespace lever::test
