// The timed operations: lever, MuJoCo 2.2.2 and Orocos KDL on the same model and state.
//
// Every benchmark is named <operation>/<model>/<peer>. An operation's peers compute the same
// quantity from the same state. Where a peer needs earlier stages (MuJoCo's mj_rne needs
// mj_kinematics, mj_comPos and mj_comVel; lever's bias() needs kinematics()), they run once before
// the timing loop; the *_from_q operations time the whole chain from the state instead.
// bench/report.cpp (kOperations) says what each operation times for each peer.
#include "benchmarks.hpp"

#include <benchmark/benchmark.h>

#include <lever/batch.hpp>
#include <lever/lever.hpp>

#include <array>
#include <functional>
#include <memory>
#include <thread>

#include "pinocchio_ops.hpp"

namespace lever::bench {

namespace {

using Fn = std::function<void(benchmark::State&)>;

void add(const std::string& op, const Fixture& f, const char* peer, Fn fn) {
  benchmark::RegisterBenchmark((op + "/" + f.name + "/" + peer).c_str(), std::move(fn))
      ->Unit(benchmark::kNanosecond);
}

// ---- lever ------------------------------------------------------------------------------------

Data lever_data(const Model& m, const State& s) {
  Data d(m);
  d.qpos = s.qpos;
  d.qvel = s.qvel;
  d.qacc = s.qacc;
  d.ctrl = s.ctrl;
  return d;
}

// prepare(m, d) once, then op(m, d) timed
template <class Prepare, class Op>
Fn lever_fn(const Fixture* f, const State* s, Prepare prepare, Op op) {
  return [f, s, prepare, op](benchmark::State& st) {
    const Model& m = f->model;
    Data d = lever_data(m, *s);
    prepare(m, d);
    for (auto _ : st) {
      op(m, d);
      benchmark::ClobberMemory();
    }
  };
}

// The three kernels with targets on every model, the contact scenes included (kinematics done):
// the site Jacobian, the bias forces, M.
void register_lever_kernels(const Fixture& f) {
  const auto kin = [](const Model& m, Data& d) { kinematics(m, d); };
  const State* s = &f.state;
  const int site = f.site;
  if (site >= 0) {
    // the Jacobians live outside Data, sized once
    auto jac = std::make_shared<std::array<Eigen::MatrixXd, 2>>();
    (*jac)[0].resize(3, f.model.nv);
    (*jac)[1].resize(3, f.model.nv);
    add("jac_site", f, "lever", lever_fn(&f, s, kin, [site, jac](const Model& m, Data& d) {
          jac_site(m, d, site, (*jac)[0], (*jac)[1]);
        }));
  }
  add("bias", f, "lever", lever_fn(&f, s, kin, [](const Model& m, Data& d) { bias(m, d); }));
  add("crba", f, "lever", lever_fn(&f, s, kin, [](const Model& m, Data& d) { crba(m, d); }));
}

void register_lever(const Fixture& f) {
  const auto nothing = [](const Model&, Data&) {};
  const auto kin = [](const Model& m, Data& d) { kinematics(m, d); };
  const State* s = &f.state;
  const int site = f.site;

  add("fk", f, "lever", lever_fn(&f, s, nothing, [](const Model& m, Data& d) { poses(m, d); }));
  add("kinematics", f, "lever", lever_fn(&f, s, nothing, kin));
  if (site >= 0) {
    // the tip frame alone from q, what KDL's FK gives and an inverse-kinematics loop reads
    add("fk_tip", f, "lever",
        lever_fn(&f, s, nothing, [site](const Model& m, Data& d) { place_site(m, d, site); }));
  }
  register_lever_kernels(f);
  const auto rnea_op = [](const Model& m, Data& d) { rnea(m, d, d.qacc, d.qfrc_inverse); };
  // from q, each peer computes the quantity asked for and what it needs: lever's body_kinematics
  // is kinematics without the geom and site frames, which nothing here reads
  add("bias_from_q", f, "lever", lever_fn(&f, s, nothing, [](const Model& m, Data& d) {
        body_kinematics(m, d);
        bias(m, d);
      }));
  add("rnea", f, "lever", lever_fn(&f, s, kin, rnea_op));
  add("rnea_from_q", f, "lever", lever_fn(&f, s, nothing, [](const Model& m, Data& d) {
        body_kinematics(m, d);
        rnea(m, d, d.qacc, d.qfrc_inverse);
      }));
  add("crba_factor", f, "lever", lever_fn(&f, s, kin, [](const Model& m, Data& d) {
        crba(m, d);
        factor_mass(m, d);
      }));
  add("crba_from_q", f, "lever", lever_fn(&f, s, nothing, [](const Model& m, Data& d) {
        body_kinematics(m, d);
        crba(m, d);
      }));
  add("inverse", f, "lever",
      lever_fn(&f, s, nothing, [](const Model& m, Data& d) { inverse(m, d); }));

  const auto forward_op = [](const Model& m, Data& d) { forward(m, d); };
  // a step moves the state: put it back before each one (two copies of nv numbers, every peer)
  const auto step_op = [](const State* state) {
    return [state](const Model& m, Data& d) {
      d.qpos = state->qpos;
      d.qvel = state->qvel;
      step(m, d);
    };
  };
  add("forward", f, "lever", lever_fn(&f, s, nothing, forward_op));
  add("step", f, "lever", lever_fn(&f, s, nothing, step_op(s)));
  if (f.limit) {
    const State* l = &*f.limit;
    add("forward_limit", f, "lever", lever_fn(&f, l, nothing, forward_op));
    add("step_limit", f, "lever", lever_fn(&f, l, nothing, step_op(l)));
  }
}

// ---- MuJoCo 2.2.2 -------------------------------------------------------------------------------

template <class Prepare, class Op>
Fn mujoco_fn(const Fixture* f, const State* s, Prepare prepare, Op op) {
  return [f, s, prepare, op](benchmark::State& st) {
    const mjModel* m = f->mj.get();
    MjDataPtr data = mujoco_data(*f, *s);
    mjData* d = data.get();
    prepare(m, d);
    for (auto _ : st) {
      op(m, d);
      benchmark::ClobberMemory();
    }
  };
}

// What MuJoCo's kernels need run before them: the positions' stages, and the velocities' too.
void mujoco_positions(const mjModel* m, mjData* d) {
  mj_kinematics(m, d);
  mj_comPos(m, d);
}
void mujoco_velocities(const mjModel* m, mjData* d) {
  mujoco_positions(m, d);
  mj_comVel(m, d);
}

// register_lever_kernels' peers: mj_jacSite after mj_kinematics and mj_comPos, mj_rne (no
// acceleration) after mj_comVel too, mj_crb after mj_comPos.
// The step's Jacobians A and B at the fixture's state: lever's analytic ones (one call, the peer of
// both of MuJoCo's; its workspace lives outside Data, sized once) beside mjd_transitionFD's centred
// and forward differences of mj_step (eps 1e-6).
void register_step_jacobians(const Fixture& f) {
  const State* s = &f.state;
  auto deriv = std::make_shared<Derivatives>(f.model);
  const auto no_setup = [](const Model&, Data&) {};
  const auto jacobian_op = [deriv](const Model& m, Data& d) { step_derivatives(m, d, *deriv); };
  add("step_jacobian_centred", f, "lever", lever_fn(&f, s, no_setup, jacobian_op));
  add("step_jacobian_forward", f, "lever", lever_fn(&f, s, no_setup, jacobian_op));
  const auto nx = static_cast<std::size_t>(2 * f.mj->nv);
  auto AB =
      std::make_shared<std::vector<mjtNum>>(nx * nx + nx * static_cast<std::size_t>(f.mj->nu));
  const auto mj_no_setup = [](const mjModel*, mjData*) {};
  for (const int centred : {1, 0}) {
    add(centred ? "step_jacobian_centred" : "step_jacobian_forward", f, "mujoco",
        mujoco_fn(&f, s, mj_no_setup, [AB, nx, centred](const mjModel* m, mjData* d) {
          mjd_transitionFD(m, d, 1e-6, static_cast<mjtByte>(centred), AB->data(),
                           m->nu > 0 ? AB->data() + nx * nx : nullptr, nullptr, nullptr);
        }));
  }
}

void register_mujoco_kernels(const Fixture& f) {
  const auto kin = mujoco_positions;
  const auto kin_vel = mujoco_velocities;
  const State* s = &f.state;
  const int site = f.site;
  if (site >= 0) {
    auto jac = std::make_shared<std::vector<mjtNum>>(6 * static_cast<std::size_t>(f.mj->nv));
    add("jac_site", f, "mujoco", mujoco_fn(&f, s, kin, [site, jac](const mjModel* m, mjData* d) {
          mj_jacSite(m, d, jac->data(), jac->data() + 3 * m->nv, site);
        }));
  }
  add("bias", f, "mujoco", mujoco_fn(&f, s, kin_vel, [](const mjModel* m, mjData* d) {
        mj_rne(m, d, 0, d->qfrc_bias);
      }));
  add("crba", f, "mujoco",
      mujoco_fn(&f, s, kin, [](const mjModel* m, mjData* d) { mj_crb(m, d); }));
}

void register_mujoco(const Fixture& f) {
  const auto nothing = [](const mjModel*, mjData*) {};
  const auto kin = mujoco_positions;
  const auto kin_vel = mujoco_velocities;
  const State* s = &f.state;
  const int site = f.site;

  // lever's poses() places what mj_kinematics places, but for the quaternions xquat; its
  // kinematics() also computes them, and what mj_comPos does (subtree centres of mass, cinert,
  // cdof)
  add("fk", f, "mujoco",
      mujoco_fn(&f, s, nothing, [](const mjModel* m, mjData* d) { mj_kinematics(m, d); }));
  add("kinematics", f, "mujoco", mujoco_fn(&f, s, nothing, kin));
  // MuJoCo has no call that places one frame: its fk_tip is the whole mj_kinematics
  if (site >= 0) {
    add("fk_tip", f, "mujoco",
        mujoco_fn(&f, s, nothing, [](const mjModel* m, mjData* d) { mj_kinematics(m, d); }));
  }
  register_mujoco_kernels(f);
  add("bias_from_q", f, "mujoco", mujoco_fn(&f, s, nothing, [kin_vel](const mjModel* m, mjData* d) {
        kin_vel(m, d);
        mj_rne(m, d, 0, d->qfrc_bias);
      }));
  add("rnea", f, "mujoco", mujoco_fn(&f, s, kin_vel, [](const mjModel* m, mjData* d) {
        mj_rne(m, d, 1, d->qfrc_inverse);
      }));
  add("rnea_from_q", f, "mujoco", mujoco_fn(&f, s, nothing, [kin_vel](const mjModel* m, mjData* d) {
        kin_vel(m, d);
        mj_rne(m, d, 1, d->qfrc_inverse);
      }));
  add("crba_factor", f, "mujoco", mujoco_fn(&f, s, kin, [](const mjModel* m, mjData* d) {
        mj_crb(m, d);
        mj_factorM(m, d);
      }));
  add("crba_from_q", f, "mujoco", mujoco_fn(&f, s, nothing, [kin](const mjModel* m, mjData* d) {
        kin(m, d);
        mj_crb(m, d);
      }));
  add("inverse", f, "mujoco",
      mujoco_fn(&f, s, nothing, [](const mjModel* m, mjData* d) { mj_inverse(m, d); }));

  const auto forward_op = [](const mjModel* m, mjData* d) { mj_forward(m, d); };
  const auto step_op = [](const State* state) {
    return [state](const mjModel* m, mjData* d) {
      mju_copy(d->qpos, state->qpos.data(), m->nq);
      mju_copy(d->qvel, state->qvel.data(), m->nv);
      mj_step(m, d);
    };
  };
  add("forward", f, "mujoco", mujoco_fn(&f, s, nothing, forward_op));
  add("step", f, "mujoco", mujoco_fn(&f, s, nothing, step_op(s)));
  if (f.limit) {
    const State* l = &*f.limit;
    add("forward_limit", f, "mujoco", mujoco_fn(&f, l, nothing, forward_op));
    add("step_limit", f, "mujoco", mujoco_fn(&f, l, nothing, step_op(l)));
  }
}

// ---- contact scenes: the whole forward, step and step Jacobian, each peer with the solver its
// model file sets (MuJoCo's Newton with its tolerance; lever's exact solve), and the three kernels
// with targets on every model (free joints: quaternion qpos)

void register_scene(const Fixture& f) {
  const State* s = &f.state;
  add("forward", f, "lever",
      lever_fn(
          &f, s, [](const Model&, Data&) {}, [](const Model& m, Data& d) { forward(m, d); }));
  add("step", f, "lever",
      lever_fn(
          &f, s, [](const Model&, Data&) {},
          [s](const Model& m, Data& d) {
            d.qpos = s->qpos;
            d.qvel = s->qvel;
            step(m, d);
          }));
  const auto nothing = [](const mjModel*, mjData*) {};
  add("forward", f, "mujoco",
      mujoco_fn(&f, s, nothing, [](const mjModel* m, mjData* d) { mj_forward(m, d); }));
  add("step", f, "mujoco", mujoco_fn(&f, s, nothing, [s](const mjModel* m, mjData* d) {
        mju_copy(d->qpos, s->qpos.data(), m->nq);
        mju_copy(d->qvel, s->qvel.data(), m->nv);
        mj_step(m, d);
      }));
  // the step's Jacobians with the contacts pushing (their active set held in lever's)
  if (f.differentiable) register_step_jacobians(f);  // else a contact lever does not differentiate
}

// ---- the sensor model: the whole forward, every sensor evaluated by both peers (the sensor stages
// are part of forward and mj_forward)

void register_sensors(const Fixture& f) {
  const State* s = &f.state;
  add("forward", f, "lever",
      lever_fn(
          &f, s, [](const Model&, Data&) {}, [](const Model& m, Data& d) { forward(m, d); }));
  const auto nothing = [](const mjModel*, mjData*) {};
  add("forward", f, "mujoco",
      mujoco_fn(&f, s, nothing, [](const mjModel* m, mjData* d) { mj_forward(m, d); }));
}

// ---- Orocos KDL ---------------------------------------------------------------------------------

void register_kdl(const Fixture& f) {
  if (!f.chain) return;
  const Fixture* fp = &f;
  auto kdl_fn = [fp](int (KdlPeer::*op)()) -> Fn {
    return [fp, op](benchmark::State& st) {
      KdlPeer peer(*fp->chain);
      const State& s = fp->state;
      const std::vector<double> tau(static_cast<std::size_t>(s.qvel.size()), 0.5);
      peer.set_state(s.qpos.data(), s.qvel.data(), s.qacc.data(), tau.data());
      for (auto _ : st) benchmark::DoNotOptimize((peer.*op)());
    };
  };
  add("fk", f, "kdl", kdl_fn(&KdlPeer::fk));
  add("fk_tip", f, "kdl", kdl_fn(&KdlPeer::fk));  // the chain's tip is the fixture's site
  add("jac_site", f, "kdl", kdl_fn(&KdlPeer::jacobian));
  add("bias_from_q", f, "kdl", kdl_fn(&KdlPeer::rne_bias));
  add("rnea_from_q", f, "kdl", kdl_fn(&KdlPeer::rne));
  add("crba_from_q", f, "kdl", kdl_fn(&KdlPeer::mass));
  add("forward", f, "kdl", kdl_fn(&KdlPeer::forward_dynamics));
}

// ---- Pinocchio, and lever's side of the operations only Pinocchio's comparison has
// (bench/pinocchio_ops.hpp)

void register_pinocchio(const Fixture& f) {
  if (!f.chain) return;  // the peer is built from the serial chain
  const Fixture* fp = &f;
  for (const PinocchioOperation& op : pinocchio_operations()) {
    if (op.name.starts_with("jac_site") && f.site < 0) continue;
    if (op.lever) {
      add(op.name, f, "lever", [fp, &op](benchmark::State& st) {
        PinocchioRig rig(*fp, fp->state);
        for (auto _ : st) {
          op.lever(*fp, rig);
          benchmark::ClobberMemory();
        }
      });
    }
    if (!have_pinocchio()) continue;
    add(op.name, f, "pinocchio", [fp, &op](benchmark::State& st) {
      PinocchioRig rig(*fp, fp->state);
      for (auto _ : st) {
        run_pinocchio(op, rig);
        benchmark::ClobberMemory();
      }
    });
  }
}

// ---- batches: states per second
// ------------------------------------------------------------------

struct Batch {
  Eigen::MatrixXd qpos, qvel, ctrl;
};

void register_batch(const Fixture& f, int states) {
  const Fixture* fp = &f;
  auto batch = std::make_shared<Batch>();
  batch->qpos.resize(f.model.nq, states);
  batch->qvel.resize(f.model.nv, states);
  batch->ctrl.resize(f.model.nu, states);
  for (int k = 0; k < states; ++k) {
    const State s = random_state(f.model, 1000003ull * static_cast<unsigned long long>(k + 1));
    batch->qpos.col(k) = s.qpos;
    batch->qvel.col(k) = s.qvel;
    batch->ctrl.col(k) = s.ctrl;
  }
  for (const int threads : {1, 2}) {
    const std::string suffix = "/threads:" + std::to_string(threads);
    benchmark::RegisterBenchmark(("batch_forward/" + f.name + "/lever" + suffix).c_str(),
                                 [fp, batch, threads](benchmark::State& st) {
                                   BatchRunner runner(fp->model, threads);
                                   Eigen::MatrixXd qacc(fp->model.nv, batch->qpos.cols());
                                   for (auto _ : st) {
                                     runner.forward(batch->qpos, batch->qvel, batch->ctrl, qacc);
                                     benchmark::ClobberMemory();
                                   }
                                   st.SetItemsProcessed(st.iterations() * batch->qpos.cols());
                                 })
        ->Unit(benchmark::kMicrosecond)
        ->UseRealTime();

    // MuJoCo the same way: one mjData per thread, contiguous blocks, threads started per call
    benchmark::RegisterBenchmark(("batch_forward/" + f.name + "/mujoco" + suffix).c_str(),
                                 [fp, batch, threads](benchmark::State& st) {
                                   const mjModel* m = fp->mj.get();
                                   const auto n = static_cast<int>(batch->qpos.cols());
                                   std::vector<MjDataPtr> data;
                                   data.reserve(static_cast<std::size_t>(threads));
                                   for (int t = 0; t < threads; ++t)
                                     data.emplace_back(mj_makeData(m), mj_deleteData);
                                   Eigen::MatrixXd qacc(m->nv, n);
                                   auto block = [&](int t) {
                                     mjData* d = data[static_cast<std::size_t>(t)].get();
                                     for (int k = t * n / threads; k < (t + 1) * n / threads; ++k) {
                                       mju_copy(d->qpos, batch->qpos.col(k).data(), m->nq);
                                       mju_copy(d->qvel, batch->qvel.col(k).data(), m->nv);
                                       if (m->nu > 0)
                                         mju_copy(d->ctrl, batch->ctrl.col(k).data(), m->nu);
                                       mj_forward(m, d);
                                       mju_copy(qacc.col(k).data(), d->qacc, m->nv);
                                     }
                                   };
                                   for (auto _ : st) {
                                     std::vector<std::thread> pool;
                                     for (int t = 1; t < threads; ++t) pool.emplace_back(block, t);
                                     block(0);
                                     for (std::thread& th : pool) th.join();
                                     benchmark::ClobberMemory();
                                   }
                                   st.SetItemsProcessed(st.iterations() * n);
                                 })
        ->Unit(benchmark::kMicrosecond)
        ->UseRealTime();
  }
}

// The lessons' two batch workloads, lever alone on 1 and 2 threads (the target is the speed-up):
//   batch_workspace_map: exercise 2's map, forward() at rest on a grid over the first two joints'
//     ranges (the other joints at qpos0), as l5_1_exercise2_workspace samples arm2;
//   batch_rollout: a set of rollouts, every state advanced by 50 steps of the model's integrator.
void register_lesson_batches(const Fixture& f) {
  const Fixture* fp = &f;
  constexpr int kGrid = 64;  // 64 x 64 poses per call
  if (f.model.njnt >= 2) {
    auto grid = std::make_shared<Batch>();
    grid->qpos.resize(f.model.nq, kGrid * kGrid);
    grid->qvel.setZero(f.model.nv, kGrid * kGrid);
    grid->ctrl.resize(f.model.nu, 0);
    for (int a = 0; a < kGrid; ++a) {
      for (int b = 0; b < kGrid; ++b) {
        Eigen::VectorXd q = f.model.qpos0;
        for (int j = 0; j < 2; ++j) {
          const auto [lo, hi] =
              f.model.jnt_limited[j] ? f.model.jnt_range[j] : std::array<double, 2>{-3.14, 3.14};
          q[f.model.jnt_qposadr[j]] = lo + (hi - lo) * (j == 0 ? a : b) / (kGrid - 1);
        }
        grid->qpos.col(a * kGrid + b) = q;
      }
    }
    for (const int threads : {1, 2}) {
      benchmark::RegisterBenchmark(
          ("batch_workspace_map/" + f.name + "/lever/threads:" + std::to_string(threads)).c_str(),
          [fp, grid, threads](benchmark::State& st) {
            BatchRunner runner(fp->model, threads);
            Eigen::MatrixXd qacc(fp->model.nv, grid->qpos.cols());
            for (auto _ : st) {
              runner.forward(grid->qpos, grid->qvel, grid->ctrl, qacc);
              benchmark::ClobberMemory();
            }
            st.SetItemsProcessed(st.iterations() * grid->qpos.cols());
          })
          ->Unit(benchmark::kMicrosecond)
          ->UseRealTime();
    }
  }

  constexpr int kRollouts = 256, kSteps = 50;
  auto start = std::make_shared<Batch>();
  start->qpos.resize(f.model.nq, kRollouts);
  start->qvel.resize(f.model.nv, kRollouts);
  start->ctrl.resize(f.model.nu, kRollouts);
  for (int k = 0; k < kRollouts; ++k) {
    const State s = random_state(f.model, 7000003ull * static_cast<unsigned long long>(k + 1));
    start->qpos.col(k) = s.qpos;
    start->qvel.col(k) = s.qvel;
    start->ctrl.col(k) = s.ctrl;
  }
  for (const int threads : {1, 2}) {
    benchmark::RegisterBenchmark(
        ("batch_rollout/" + f.name + "/lever/threads:" + std::to_string(threads)).c_str(),
        [fp, start, threads](benchmark::State& st) {
          BatchRunner runner(fp->model, threads);
          Eigen::MatrixXd qpos = start->qpos, qvel = start->qvel;
          for (auto _ : st) {
            st.PauseTiming();  // every call starts from the same states
            qpos = start->qpos;
            qvel = start->qvel;
            st.ResumeTiming();
            runner.step(qpos, qvel, start->ctrl, kSteps);
            benchmark::ClobberMemory();
          }
          st.SetItemsProcessed(st.iterations() * kRollouts * kSteps);
        })
        ->Unit(benchmark::kMicrosecond)
        ->UseRealTime();
  }
}

}  // namespace

void register_benchmarks(const std::vector<std::unique_ptr<Fixture>>& fixtures, int batch_states) {
  for (const auto& f : fixtures) {
    if (f->sensors) {
      register_sensors(*f);
      continue;
    }
    if (f->scene) {
      register_scene(*f);
      register_lever_kernels(*f);
      register_mujoco_kernels(*f);
      continue;
    }
    register_lever(*f);
    register_mujoco(*f);
    register_step_jacobians(*f);
    register_kdl(*f);
    register_pinocchio(*f);
  }
  for (const auto& f : fixtures) {
    if (!f->scene && !f->sensors) register_batch(*f, batch_states);
  }
  for (const auto& f : fixtures) {
    if (f->name == "arm2" || f->name == "panda7") register_lesson_batches(*f);
  }
}

}  // namespace lever::bench
