// lever_bench_profile: the benchmarks' operations in a loop, on the benchmark's state, for a
// profiler and for instruction counts.
//
//   lever_bench_profile MODEL.xml OPERATION [ITERATIONS]   one operation
//   lever_bench_profile MODEL.xml --all [ITERATIONS]       every operation the model has, in turn
//   lever_bench_profile MODEL.xml --list                   their names
//
// Operations: lever's fk (poses) fk_tip (place_site of the tip) kinematics jac_site bias
// bias_from_q rnea rnea_from_q crba crba_factor crba_from_q inverse forward forward_limit step
// step_limit step_jacobian_forward (the analytic A and B); MuJoCo's counterparts as
// mujoco:<operation> (bias is mj_rne alone, bias_vel adds mj_comVel; step_jacobian_centred too;
// fk_tip is mj_kinematics, MuJoCo having no one-frame call), KDL's as kdl:<operation> (fk fk_tip
// jac_site bias_from_q rnea_from_q crba_from_q forward); on serial chains lever's fk_bodies
// jac_site_from_q aba rnea_derivatives aba_derivatives and Pinocchio's as pinocchio:<operation>
// (bias_from_q rnea_from_q crba_from_q and those five: bench/pinocchio_ops.hpp) where the build
// has Pinocchio. Each does what the benchmark of the same
// name times (bench/benchmarks.cpp), after the same preparation.
//
// Under callgrind only the loops are counted (loading the model, the preparation and a few
// warm-up calls are not):
//   valgrind --tool=callgrind --instr-atstart=no build-bench/bench/lever_bench_profile
//       models/arm2.xml forward 100000
//   callgrind_annotate --inclusive=yes callgrind.out.<pid>
// With --all, each operation's loop is dumped on its own (CALLGRIND_DUMP_STATS_AT, the dump's
// "desc: Trigger" line names the operation), after an empty loop that measures the loop itself;
// stdout lists "operation<TAB>iterations". bench/instructions.py reads them.
// Under perf, give it enough iterations: perf record -g lever_bench_profile models/arm7.xml
// forward 20000000
#include <lever/derivatives.hpp>
#include <lever/lever.hpp>
#include <lever/mjcf.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "fixture.hpp"
#include "kdl_peer.hpp"
#include "pinocchio_ops.hpp"

#if __has_include(<valgrind/callgrind.h>)
#include <valgrind/callgrind.h>
#else
#define CALLGRIND_START_INSTRUMENTATION
#define CALLGRIND_STOP_INSTRUMENTATION
#define CALLGRIND_DUMP_STATS_AT(label)
#endif

namespace {

using lever::bench::Fixture;
using lever::bench::State;

// Everything one operation runs on: each operation gets its own, fresh from the state, so that
// no operation sees what an earlier one left (a step moves the state).
struct Rig {
  Rig(const Fixture& f, const State& state)
      : s(state),
        d(f.model),
        jacp(3, f.model.nv),
        jacr(3, f.model.nv),
        md(lever::bench::mujoco_data(f, state)),
        mjac(6 * static_cast<std::size_t>(f.mj->nv)) {
    d.qpos = s.qpos;
    d.qvel = s.qvel;
    d.qacc = s.qacc;
    d.ctrl = s.ctrl;
    // the stages the pieces need, as the benchmarks prepare them
    lever::kinematics(f.model, d);
    mj_kinematics(f.mj.get(), md.get());
    mj_comPos(f.mj.get(), md.get());
    mj_comVel(f.mj.get(), md.get());
    if (f.chain) {
      kdl = std::make_unique<lever::bench::KdlPeer>(*f.chain);
      const std::vector<double> tau(static_cast<std::size_t>(s.qvel.size()), 0.5);
      kdl->set_state(s.qpos.data(), s.qvel.data(), s.qacc.data(), tau.data());
    }
    const auto nx = 2 * static_cast<std::size_t>(f.mj->nv);
    AB.resize(nx * nx + nx * static_cast<std::size_t>(f.mj->nu));
  }

  const State& s;
  lever::Data d;
  Eigen::MatrixXd jacp, jacr;
  std::unique_ptr<lever::Derivatives> deriv;  // made by the operation that needs it
  lever::bench::MjDataPtr md;
  std::vector<mjtNum> mjac, AB;
  std::unique_ptr<lever::bench::KdlPeer> kdl;
  std::unique_ptr<lever::bench::PinocchioRig> pin;  // made by the operation that needs it
};

enum class Needs { kNothing, kSite, kLimit, kChain };

struct Operation {
  std::string name;
  Needs needs;
  // how much dearer than a forward call (the finite-difference Jacobians run many steps): --all
  // divides its iteration count by this, the counts per call being exact anyway
  long cost;
  std::function<void(const Fixture&, Rig&)> run;
};

std::vector<Operation> operations() {
  using lever::Model;
  using N = Needs;
  const auto restore_lever = [](Rig& r) {
    r.d.qpos = r.s.qpos;
    r.d.qvel = r.s.qvel;
  };
  const auto restore_mujoco = [](const Fixture& f, Rig& r) {
    mju_copy(r.md->qpos, r.s.qpos.data(), f.mj->nq);
    mju_copy(r.md->qvel, r.s.qvel.data(), f.mj->nv);
  };
  const auto kin_vel = [](const mjModel* m, mjData* d) {
    mj_kinematics(m, d);
    mj_comPos(m, d);
    mj_comVel(m, d);
  };
  const auto transition_fd = [](const Fixture& f, Rig& r, mjtByte centred) {
    const mjModel* m = f.mj.get();
    const auto nx = 2 * static_cast<std::size_t>(m->nv);
    mjd_transitionFD(m, r.md.get(), 1e-6, centred, r.AB.data(),
                     m->nu > 0 ? r.AB.data() + nx * nx : nullptr, nullptr, nullptr);
  };
  std::vector<Operation> ops = {
      // ---- lever
      {"fk", N::kNothing, 1, [](const Fixture& f, Rig& r) { lever::poses(f.model, r.d); }},
      {"fk_tip", N::kSite, 1,
       [](const Fixture& f, Rig& r) { lever::place_site(f.model, r.d, f.site); }},
      {"kinematics", N::kNothing, 1,
       [](const Fixture& f, Rig& r) { lever::kinematics(f.model, r.d); }},
      {"jac_site", N::kSite, 1,
       [](const Fixture& f, Rig& r) { lever::jac_site(f.model, r.d, f.site, r.jacp, r.jacr); }},
      {"bias", N::kNothing, 1, [](const Fixture& f, Rig& r) { lever::bias(f.model, r.d); }},
      {"bias_from_q", N::kNothing, 1,
       [](const Fixture& f, Rig& r) {
         lever::body_kinematics(f.model, r.d);
         lever::bias(f.model, r.d);
       }},
      {"rnea", N::kNothing, 1,
       [](const Fixture& f, Rig& r) { lever::rnea(f.model, r.d, r.d.qacc, r.d.qfrc_inverse); }},
      {"rnea_from_q", N::kNothing, 1,
       [](const Fixture& f, Rig& r) {
         lever::body_kinematics(f.model, r.d);
         lever::rnea(f.model, r.d, r.d.qacc, r.d.qfrc_inverse);
       }},
      {"crba", N::kNothing, 1, [](const Fixture& f, Rig& r) { lever::crba(f.model, r.d); }},
      {"crba_factor", N::kNothing, 1,
       [](const Fixture& f, Rig& r) {
         lever::crba(f.model, r.d);
         lever::factor_mass(f.model, r.d);
       }},
      {"crba_from_q", N::kNothing, 1,
       [](const Fixture& f, Rig& r) {
         lever::body_kinematics(f.model, r.d);
         lever::crba(f.model, r.d);
       }},
      {"inverse", N::kNothing, 1, [](const Fixture& f, Rig& r) { lever::inverse(f.model, r.d); }},
      {"forward", N::kNothing, 1, [](const Fixture& f, Rig& r) { lever::forward(f.model, r.d); }},
      {"forward_limit", N::kLimit, 1,
       [](const Fixture& f, Rig& r) { lever::forward(f.model, r.d); }},
      {"step", N::kNothing, 1,
       [restore_lever](const Fixture& f, Rig& r) {
         restore_lever(r);
         lever::step(f.model, r.d);
       }},
      {"step_limit", N::kLimit, 1,
       [restore_lever](const Fixture& f, Rig& r) {
         restore_lever(r);
         lever::step(f.model, r.d);
       }},
      // the analytic A and B: the peer of both of MuJoCo's finite differences
      {"step_jacobian_forward", N::kNothing, 10,
       [](const Fixture& f, Rig& r) {
         if (!r.deriv) r.deriv = std::make_unique<lever::Derivatives>(f.model);
         lever::step_derivatives(f.model, r.d, *r.deriv);
       }},
      // ---- MuJoCo 2.2.2
      {"mujoco:fk", N::kNothing, 1,
       [](const Fixture& f, Rig& r) { mj_kinematics(f.mj.get(), r.md.get()); }},
      {"mujoco:fk_tip", N::kSite, 1,
       [](const Fixture& f, Rig& r) { mj_kinematics(f.mj.get(), r.md.get()); }},
      {"mujoco:kinematics", N::kNothing, 1,
       [](const Fixture& f, Rig& r) {
         mj_kinematics(f.mj.get(), r.md.get());
         mj_comPos(f.mj.get(), r.md.get());
       }},
      {"mujoco:jac_site", N::kSite, 1,
       [](const Fixture& f, Rig& r) {
         mj_jacSite(f.mj.get(), r.md.get(), r.mjac.data(), r.mjac.data() + 3 * f.mj->nv, f.site);
       }},
      {"mujoco:bias", N::kNothing, 1,
       [](const Fixture& f, Rig& r) { mj_rne(f.mj.get(), r.md.get(), 0, r.md->qfrc_bias); }},
      {"mujoco:bias_vel", N::kNothing, 1,
       [](const Fixture& f, Rig& r) {
         mj_comVel(f.mj.get(), r.md.get());
         mj_rne(f.mj.get(), r.md.get(), 0, r.md->qfrc_bias);
       }},
      {"mujoco:bias_from_q", N::kNothing, 1,
       [kin_vel](const Fixture& f, Rig& r) {
         kin_vel(f.mj.get(), r.md.get());
         mj_rne(f.mj.get(), r.md.get(), 0, r.md->qfrc_bias);
       }},
      {"mujoco:rnea", N::kNothing, 1,
       [](const Fixture& f, Rig& r) { mj_rne(f.mj.get(), r.md.get(), 1, r.md->qfrc_inverse); }},
      {"mujoco:rnea_from_q", N::kNothing, 1,
       [kin_vel](const Fixture& f, Rig& r) {
         kin_vel(f.mj.get(), r.md.get());
         mj_rne(f.mj.get(), r.md.get(), 1, r.md->qfrc_inverse);
       }},
      {"mujoco:crba", N::kNothing, 1,
       [](const Fixture& f, Rig& r) { mj_crb(f.mj.get(), r.md.get()); }},
      {"mujoco:crba_factor", N::kNothing, 1,
       [](const Fixture& f, Rig& r) {
         mj_crb(f.mj.get(), r.md.get());
         mj_factorM(f.mj.get(), r.md.get());
       }},
      {"mujoco:crba_from_q", N::kNothing, 1,
       [](const Fixture& f, Rig& r) {
         mj_kinematics(f.mj.get(), r.md.get());
         mj_comPos(f.mj.get(), r.md.get());
         mj_crb(f.mj.get(), r.md.get());
       }},
      {"mujoco:inverse", N::kNothing, 1,
       [](const Fixture& f, Rig& r) { mj_inverse(f.mj.get(), r.md.get()); }},
      {"mujoco:forward", N::kNothing, 1,
       [](const Fixture& f, Rig& r) { mj_forward(f.mj.get(), r.md.get()); }},
      {"mujoco:forward_limit", N::kLimit, 1,
       [](const Fixture& f, Rig& r) { mj_forward(f.mj.get(), r.md.get()); }},
      {"mujoco:step", N::kNothing, 1,
       [restore_mujoco](const Fixture& f, Rig& r) {
         restore_mujoco(f, r);
         mj_step(f.mj.get(), r.md.get());
       }},
      {"mujoco:step_limit", N::kLimit, 1,
       [restore_mujoco](const Fixture& f, Rig& r) {
         restore_mujoco(f, r);
         mj_step(f.mj.get(), r.md.get());
       }},
      // mjd_transitionFD by forward and by centred differences (2nv + nu or twice as many steps)
      {"mujoco:step_jacobian_forward", N::kNothing, 40,
       [transition_fd](const Fixture& f, Rig& r) { transition_fd(f, r, 0); }},
      {"mujoco:step_jacobian_centred", N::kNothing, 80,
       [transition_fd](const Fixture& f, Rig& r) { transition_fd(f, r, 1); }},
      // ---- Orocos KDL (every solver starts from q)
      {"kdl:fk", N::kChain, 1, [](const Fixture&, Rig& r) { r.kdl->fk(); }},
      {"kdl:fk_tip", N::kChain, 1, [](const Fixture&, Rig& r) { r.kdl->fk(); }},
      {"kdl:jac_site", N::kChain, 1, [](const Fixture&, Rig& r) { r.kdl->jacobian(); }},
      {"kdl:bias_from_q", N::kChain, 1, [](const Fixture&, Rig& r) { r.kdl->rne_bias(); }},
      {"kdl:rnea_from_q", N::kChain, 1, [](const Fixture&, Rig& r) { r.kdl->rne(); }},
      {"kdl:crba_from_q", N::kChain, 1, [](const Fixture&, Rig& r) { r.kdl->mass(); }},
      {"kdl:forward", N::kChain, 1, [](const Fixture&, Rig& r) { r.kdl->forward_dynamics(); }},
  };
  // ---- the operations compared with Pinocchio (bench/pinocchio_ops.hpp): lever's new ones, and
  // Pinocchio's as pinocchio:<operation> where this build has it
  const auto rig = [](const Fixture& f, Rig& r) -> lever::bench::PinocchioRig& {
    if (!r.pin) r.pin = std::make_unique<lever::bench::PinocchioRig>(f, r.s);
    return *r.pin;
  };
  for (const lever::bench::PinocchioOperation& op : lever::bench::pinocchio_operations()) {
    const lever::bench::PinocchioOperation* p = &op;
    if (op.lever) {
      ops.push_back({op.name, N::kChain, 1,
                     [p, rig](const Fixture& f, Rig& r) { p->lever(f, rig(f, r)); }});
    }
    if (lever::bench::have_pinocchio()) {
      ops.push_back({"pinocchio:" + op.name, N::kChain, 1, [p, rig](const Fixture& f, Rig& r) {
                       lever::bench::run_pinocchio(*p, rig(f, r));
                     }});
    }
  }
  return ops;
}

bool available(const Operation& op, const Fixture& f) {
  if (f.sensors) return op.name == "forward" || op.name == "mujoco:forward";  // the sensor model
  if (f.scene) {  // a contact scene: forward, step, the three kernels and the step's Jacobians
                  // (bench/benchmarks.cpp)
    const std::string_view name = op.name;
    if (name.starts_with("kdl:")) return false;
    const std::string_view operation = name.substr(name.find(':') + 1);  // npos + 1 = 0
    if (operation == "jac_site") return f.site >= 0;
    return op.needs == Needs::kNothing &&
           (operation == "forward" || operation == "step" || operation == "bias" ||
            operation == "crba" ||
            (operation.starts_with("step_jacobian") && f.differentiable));
  }
  switch (op.needs) {
    case Needs::kSite: return f.site >= 0 && (!op.name.starts_with("kdl:") || f.chain);
    case Needs::kLimit: return f.limit.has_value();
    case Needs::kChain: return f.chain.has_value();
    case Needs::kNothing: return true;
  }
  return false;
}

// One operation's loop, counted alone: a few calls first (the first call of a kind may do work
// the next ones do not: lazy symbol binding, the entry checks' first match, MuJoCo's warm start),
// then `iterations` calls between the instrumentation switches.
void count(const Fixture& f, const Operation& op, long iterations) {
  Rig rig(f, op.needs == Needs::kLimit ? *f.limit : f.state);
  for (int i = 0; i < 3; ++i) op.run(f, rig);
  CALLGRIND_START_INSTRUMENTATION;
  for (long i = 0; i < iterations; ++i) op.run(f, rig);
  CALLGRIND_STOP_INSTRUMENTATION;
  CALLGRIND_DUMP_STATS_AT(op.name.c_str());
  std::printf("%s\t%ld\n", op.name.c_str(), iterations);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s MODEL.xml (OPERATION | --all | --list) [ITERATIONS]\n",
                 argv[0]);
    return 2;
  }
  const std::string what = argv[2];
  long iterations = 1000000;
  if (argc > 3) {
    try {
      iterations = std::stol(argv[3]);
    } catch (const std::exception&) {
      iterations = 0;
    }
    if (iterations < 1) {
      std::fprintf(stderr, "ITERATIONS must be a positive number, not '%s'\n", argv[3]);
      return 2;
    }
  }
  std::unique_ptr<Fixture> f;
  try {
    // a scene of bench/scenes reads real model files: its copy that finds them
    const std::string path = lever::bench::robot_scene_file(argv[1]);
    const lever::Model model = lever::mjcf::load_file(path);
    f = lever::bench::is_sensor_model(model) ? lever::bench::make_sensor_fixture(path)
        : lever::bench::is_scene(model)      ? lever::bench::make_scene_fixture(path)
                                             : lever::bench::make_fixture(path);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 2;
  }
  const std::vector<Operation> ops = operations();

  if (what == "--list" || what == "--all") {
    if (what == "--all") {
      // the loop alone, to subtract: an operation that does nothing
      const Operation empty{"empty", Needs::kNothing, 1, [](const Fixture&, Rig&) {}};
      count(*f, empty, iterations);
    }
    for (const Operation& op : ops) {
      if (!available(op, *f)) continue;
      if (what == "--list") {
        std::printf("%s\n", op.name.c_str());
      } else {
        count(*f, op, std::max(1L, iterations / op.cost));
      }
    }
    return 0;
  }

  const auto it =
      std::find_if(ops.begin(), ops.end(), [&](const Operation& op) { return op.name == what; });
  if (it == ops.end()) {
    std::fprintf(stderr, "unknown operation '%s' (--list names them)\n", what.c_str());
    return 2;
  }
  if (!available(*it, *f)) {
    std::fprintf(stderr, "%s: %s needs %s\n", f->name.c_str(), what.c_str(),
                 it->needs == Needs::kLimit  ? "a limited joint"
                 : it->needs == Needs::kSite ? "a site"
                                             : "a serial chain (KDL)");
    return 2;
  }
  Rig rig(*f, it->needs == Needs::kLimit ? *f->limit : f->state);
  const auto start = std::chrono::steady_clock::now();
  CALLGRIND_START_INSTRUMENTATION;
  for (long i = 0; i < iterations; ++i) it->run(*f, rig);
  CALLGRIND_STOP_INSTRUMENTATION;
  const std::chrono::duration<double, std::nano> elapsed = std::chrono::steady_clock::now() - start;
  std::printf("%s %s (%s): %ld iterations, %.1f ns each\n", f->name.c_str(), what.c_str(),
              f->loader.c_str(), iterations, elapsed.count() / static_cast<double>(iterations));
  return 0;
}
