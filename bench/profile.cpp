// lever_bench_profile: one lever operation in a loop, on the benchmark's state, for a profiler.
//
//   lever_bench_profile MODEL.xml OPERATION [ITERATIONS]
//   operations: fk jac_site bias rnea crba crba_factor inverse forward forward_limit step
//   step_limit, and MuJoCo's counterparts as mujoco:<operation> (bias is mj_rne alone, bias_vel
//   adds mj_comVel)
//
// Under callgrind only the loop is measured (loading the model is not):
//   valgrind --tool=callgrind --instr-atstart=no build-bench/bench/lever_bench_profile
//       models/arm2.xml forward 100000
//   callgrind_annotate --inclusive=yes callgrind.out.<pid>
// Under perf, give it enough iterations: perf record -g lever_bench_profile models/arm7.xml forward
// 20000000
#include <lever/lever.hpp>

#include <chrono>
#include <cstdio>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "fixture.hpp"

#if __has_include(<valgrind/callgrind.h>)
#include <valgrind/callgrind.h>
#else
#define CALLGRIND_START_INSTRUMENTATION
#define CALLGRIND_STOP_INSTRUMENTATION
#endif

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s MODEL.xml OPERATION [ITERATIONS]\n", argv[0]);
    return 2;
  }
  const std::string op = argv[2];
  const long iterations = argc > 3 ? std::stol(argv[3]) : 1000000;
  std::unique_ptr<lever::bench::Fixture> f;
  try {
    f = lever::bench::make_fixture(argv[1]);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 2;
  }
  const lever::Model& m = f->model;
  const bool limit = op.ends_with("forward_limit") || op.ends_with("step_limit");
  if (limit && !f->limit) {
    std::fprintf(stderr, "%s has no limited joint\n", f->name.c_str());
    return 2;
  }
  const lever::bench::State& s = limit ? *f->limit : f->state;
  lever::Data d(m);
  d.qpos = s.qpos;
  d.qvel = s.qvel;
  d.qacc = s.qacc;
  d.ctrl = s.ctrl;
  lever::kinematics(m, d);
  Eigen::MatrixXd jacp(3, m.nv), jacr(3, m.nv);
  const int site = f->site;

  const std::map<std::string, std::function<void()>> ops = {
      {"fk", [&] { lever::kinematics(m, d); }},
      {"jac_site", [&] { lever::jac_site(m, d, site, jacp, jacr); }},
      {"bias", [&] { lever::bias(m, d); }},
      {"rnea", [&] { lever::rnea(m, d, d.qacc, d.qfrc_inverse); }},
      {"crba", [&] { lever::crba(m, d); }},
      {"crba_factor",
       [&] {
         lever::crba(m, d);
         lever::factor_mass(m, d);
       }},
      {"inverse", [&] { lever::inverse(m, d); }},
      {"forward", [&] { lever::forward(m, d); }},
      {"forward_limit", [&] { lever::forward(m, d); }},
      {"step",
       [&] {
         d.qpos = s.qpos;
         d.qvel = s.qvel;
         lever::step(m, d);
       }},
      {"step_limit",
       [&] {
         d.qpos = s.qpos;
         d.qvel = s.qvel;
         lever::step(m, d);
       }},
  };
  // MuJoCo's counterparts, to compare instruction counts under callgrind ("mujoco:forward")
  lever::bench::MjDataPtr md = lever::bench::mujoco_data(*f, s);
  const mjModel* mm = f->mj.get();
  mjData* mdp = md.get();
  mj_kinematics(mm, mdp);
  mj_comPos(mm, mdp);
  mj_comVel(mm, mdp);
  std::vector<mjtNum> jac(6 * static_cast<std::size_t>(mm->nv));
  auto restore = [&] {
    mju_copy(mdp->qpos, s.qpos.data(), mm->nq);
    mju_copy(mdp->qvel, s.qvel.data(), mm->nv);
  };
  const std::map<std::string, std::function<void()>> mujoco_ops = {
      {"mujoco:fk",
       [&] {
         mj_kinematics(mm, mdp);
         mj_comPos(mm, mdp);
       }},
      {"mujoco:jac_site", [&] { mj_jacSite(mm, mdp, jac.data(), jac.data() + 3 * mm->nv, site); }},
      {"mujoco:bias", [&] { mj_rne(mm, mdp, 0, mdp->qfrc_bias); }},
      {"mujoco:bias_vel",
       [&] {
         mj_comVel(mm, mdp);
         mj_rne(mm, mdp, 0, mdp->qfrc_bias);
       }},
      {"mujoco:rnea", [&] { mj_rne(mm, mdp, 1, mdp->qfrc_inverse); }},
      {"mujoco:crba", [&] { mj_crb(mm, mdp); }},
      {"mujoco:crba_factor",
       [&] {
         mj_crb(mm, mdp);
         mj_factorM(mm, mdp);
       }},
      {"mujoco:inverse", [&] { mj_inverse(mm, mdp); }},
      {"mujoco:forward", [&] { mj_forward(mm, mdp); }},
      {"mujoco:forward_limit", [&] { mj_forward(mm, mdp); }},
      {"mujoco:step",
       [&] {
         restore();
         mj_step(mm, mdp);
       }},
      {"mujoco:step_limit",
       [&] {
         restore();
         mj_step(mm, mdp);
       }},
  };
  const std::function<void()>* found = nullptr;
  if (const auto it = ops.find(op); it != ops.end()) found = &it->second;
  if (const auto it = mujoco_ops.find(op); it != mujoco_ops.end()) found = &it->second;
  if (found == nullptr || (op.ends_with("jac_site") && site < 0)) {
    std::fprintf(stderr, "unknown operation '%s'\n", op.c_str());
    return 2;
  }
  const std::function<void()>& fn = *found;

  const auto start = std::chrono::steady_clock::now();
  CALLGRIND_START_INSTRUMENTATION;
  for (long i = 0; i < iterations; ++i) fn();
  CALLGRIND_STOP_INSTRUMENTATION;
  const std::chrono::duration<double, std::nano> elapsed = std::chrono::steady_clock::now() - start;
  std::printf("%s %s (%s): %ld iterations, %.1f ns each\n", f->name.c_str(), op.c_str(),
              f->loader.c_str(), iterations, elapsed.count() / static_cast<double>(iterations));
  return 0;
}
