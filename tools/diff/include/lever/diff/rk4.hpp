// lever/diff/rk4.hpp: MuJoCo 2.2.2's RK4 step, taken along the stage states of lever's step.
//
// An RK4 step evaluates forward dynamics at three states inside the step, each made from the
// stage before's acceleration. lever's and MuJoCo's constraint solvers agree to the solver's
// bound, not bit for bit, so the two engines' later stages start from states a few ulps apart.
// Where a contact's geometry is discontinuous in the state (MPR on a deep box-mesh or mesh-mesh
// penetration: one ulp of qpos can turn its normal by 0.1 rad), MuJoCo evaluated at lever's
// stage state gives lever's answer, and differs from MuJoCo at its own stage state by as much as
// MuJoCo nudged by 1e-15 differs from itself. Comparing the two steps whole then compares the two
// roundings, magnified by MuJoCo's own discontinuity, not the two engines' dynamics. So the step
// is compared stage by stage: MuJoCo's stages are evaluated at the states lever's step went
// through (built by MuJoCo's own arithmetic from lever's stage accelerations), and its RK4 sum is
// formed from them, as a lockstep run starts each step from MuJoCo's state.
#pragma once

#include <mujoco/mujoco.h>

#include <Eigen/Core>
#include <array>
#include <lever/data.hpp>
#include <lever/diff/report.hpp>
#include <lever/model.hpp>
#include <vector>

namespace lever::diff {

/// The four stages of one of MuJoCo's RK4 steps: each stage's state and acceleration.
struct MujocoRk4Stages {
  std::array<std::vector<double>, 4> qpos, qvel, qacc;
};

/// One RK4 step of MuJoCo 2.2.2 from the state in d, as mj_step with mjINT_RK4 takes it: forward
/// at the start (mj_forward), then mj_RungeKutta's arithmetic (the classical tableau, the stage
/// states by mj_integratePos, the stage times, the weighted sums, qvel advanced before qpos), each
/// later stage evaluated by mj_forwardSkip without sensors, as mj_RungeKutta evaluates it.
/// With restart_solver, every stage's solve is converged as mujoco_forward_converged converges
/// it. Each next stage's state is made from `path_qacc[i]` if given (lever's stage accelerations,
/// Data::work.rk_qacc), else from MuJoCo's own stage acceleration: then, without restart_solver,
/// d ends bit for bit where mj_step leaves it (qpos, qvel, time, and the last stage's qacc and
/// rows). Activations ride along in MuJoCo's own act_dot at every stage.
void mujoco_rk4_step(const mjModel* m, mjData* d, bool restart_solver,
                     const ArenaVector (*path_qacc)[4], MujocoRk4Stages* stages);

/// After lever's RK4 step (data) and mujoco_rk4_step along its path (stages): each later stage's
/// velocity, built by each engine's own arithmetic from the same accelerations, so equal ("qvel
/// at an RK4 stage"); with `accelerations`, each later stage's acceleration too ("qacc at an RK4
/// stage", decided by the solver). compare_step and lockstep leave the stages' accelerations to
/// the step's sum, which weighs them by h as the comparison of a whole step always did: a stage
/// state can sit where MuJoCo's own rounding moves qacc by the bound (Cassie's achilles rods,
/// whose axial entry of M, 3.754e-6, is what is left of terms 1e4 times larger: MuJoCo against
/// itself started 1e-15 away moves that pivot by 1.6e-12), and tests/diff/rk4_stages.cpp
/// compares the stages' accelerations where they are the question.
void compare_rk4_stages(const Model& model, const Data& data, const MujocoRk4Stages& stages,
                        int k, Report& report, bool accelerations = false);

}  // namespace lever::diff
