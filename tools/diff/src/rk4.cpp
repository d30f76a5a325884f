#include <lever/diff/rk4.hpp>
#include <lever/diff/twin.hpp>
#include <stdexcept>
#include <string>

namespace lever::diff {

namespace {

// The classical tableau, as mj_RungeKutta holds it: a_{i,i-1} (the rest of the lower triangle is
// zero) and the weights b.
constexpr double kStageA[3] = {0.5, 0.5, 1.0};
constexpr double kWeightB[4] = {1.0 / 6.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0};

// mj_forwardSkip from the start without sensors, as mj_RungeKutta evaluates a stage.
void evaluate_stage(const mjModel* m, mjData* d, bool restart_solver) {
  const ForwardInputs given(m, d);
  mj_forwardSkip(m, d, mjSTAGE_NONE, 1);
  if (restart_solver) converge_mujoco_solver(m, d, given);
}

}  // namespace

void mujoco_rk4_step(const mjModel* m, mjData* d, bool restart_solver,
                     const ArenaVector (*path_qacc)[4], MujocoRk4Stages* stages) {
  const int nq = m->nq, nv = m->nv, na = m->na;
  const double h = m->opt.timestep, time = d->time;
  MujocoRk4Stages local;
  MujocoRk4Stages& x = stages ? *stages : local;

  // stage 0: mj_step's own forward at the start of the step
  mj_checkPos(m, d);
  mj_checkVel(m, d);
  mujoco_forward_converged(m, d, restart_solver);
  mj_checkAcc(m, d);
  x.qpos[0].assign(d->qpos, d->qpos + nq);
  x.qvel[0].assign(d->qvel, d->qvel + nv);
  x.qacc[0].assign(d->qacc, d->qacc + nv);
  // the activations ride along as mj_RungeKutta's X and F carry them (MuJoCo's own act_dot at
  // every stage: lever's path is followed in qacc, where contacts make the stages sensitive)
  std::array<std::vector<double>, 4> act, act_dot;
  act[0].assign(d->act, d->act + na);
  act_dot[0].assign(d->act_dot, d->act_dot + na);

  std::vector<double> dq(nv), dv(nv), da(na);
  for (int i = 1; i < 4; ++i) {
    // the acceleration this stage's state is made from: lever's stage i-1 or MuJoCo's
    const double* qacc_before = path_qacc ? (*path_qacc)[i - 1].data() : x.qacc[i - 1].data();
    // mj_RungeKutta's dX (0 + a v, 0 + a f) and X[i] = X[0] '+' h dX
    for (int j = 0; j < nv; ++j) {
      dq[j] = 0.0 + kStageA[i - 1] * x.qvel[i - 1][j];
      dv[j] = 0.0 + kStageA[i - 1] * qacc_before[j];
    }
    x.qpos[i] = x.qpos[0];
    mj_integratePos(m, x.qpos[i].data(), dq.data(), h);
    x.qvel[i] = x.qvel[0];
    for (int j = 0; j < nv; ++j) x.qvel[i][j] += dv[j] * h;
    act[i] = act[0];
    for (int j = 0; j < na; ++j) act[i][j] += (0.0 + kStageA[i - 1] * act_dot[i - 1][j]) * h;
    mju_copy(d->qpos, x.qpos[i].data(), nq);
    mju_copy(d->qvel, x.qvel[i].data(), nv);
    if (na > 0) mju_copy(d->act, act[i].data(), na);
    d->time = time + (0.0 + kStageA[i - 1]) * h;
    evaluate_stage(m, d, restart_solver);
    x.qacc[i].assign(d->qacc, d->qacc + nv);
    act_dot[i].assign(d->act_dot, d->act_dot + na);
  }

  // the weighted sums (MuJoCo's accelerations, the stages' velocities), then mj_advance: qvel
  // first, qpos with the summed velocity
  for (int j = 0; j < nv; ++j) dq[j] = dv[j] = 0.0;
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < nv; ++j) {
      dq[j] += x.qvel[i][j] * kWeightB[i];
      dv[j] += x.qacc[i][j] * kWeightB[i];
    }
    for (int j = 0; j < na; ++j) da[j] += act_dot[i][j] * kWeightB[i];
  }
  d->time = time;
  mju_copy(d->qpos, x.qpos[0].data(), nq);
  mju_copy(d->qvel, x.qvel[0].data(), nv);
  // mj_advance: the activations first, clamped to actrange where limited
  for (int j = 0; j < na; ++j) {
    d->act[j] = act[0][j] + da[j] * h;
    const int u = j + m->nu - na;
    if (m->actuator_actlimited[u]) {
      d->act[j] = mju_clip(d->act[j], m->actuator_actrange[2 * u], m->actuator_actrange[2 * u + 1]);
    }
  }
  for (int j = 0; j < nv; ++j) d->qvel[j] += dv[j] * h;
  mj_integratePos(m, d->qpos, dq.data(), h);
  d->time += h;
}

void compare_rk4_stages(const Model& model, const Data& data, const MujocoRk4Stages& stages,
                        int k, Report& report, bool accelerations) {
  const Labeler stage_dof = [&model](int i) {
    const int stage = 1 + i / model.nv, dof = i % model.nv;
    return "stage " + std::to_string(stage) + ", dof " + std::to_string(dof) + " (joint '" +
           model.jnt_name[model.dof_jntid[dof]] + "')";
  };
  // the three later stages side by side: one comparison per step, each stage's magnitude its own
  for (int i = 1; i < 4; ++i) {
    const Labeler label = [&stage_dof, &model, i](int j) {
      return stage_dof((i - 1) * model.nv + j);
    };
    report.compare("qvel at an RK4 stage", k, data.work.rk_qvel[i].data(),
                   stages.qvel[i].data(), model.nv, label);
    if (!accelerations) continue;
    report.compare("qacc at an RK4 stage", k, data.work.rk_qacc[i].data(),
                   stages.qacc[i].data(), model.nv, label);
  }
}

}  // namespace lever::diff
