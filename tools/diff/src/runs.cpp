#include <cmath>
#include <lever/diff/compare.hpp>
#include <lever/diff/rk4.hpp>
#include <lever/diff/runs.hpp>
#include <lever/error.hpp>
#include <lever/forward.hpp>
#include <random>

#include <lever/harness/models.hpp>

namespace lever::diff {

namespace {

int steps_for(const Model& model, double seconds) {
  return static_cast<int>(std::lround(seconds / model.opt.timestep));
}

void apply_control(const Model& model, Control control, double time, mjData* d) {
  Eigen::Map<Eigen::VectorXd> ctrl(d->ctrl, model.nu);
  if (control == Control::kSmooth) {
    test::smooth_control(model, time, ctrl);
  } else if (control == Control::kZero) {
    ctrl.setZero();
  }
}

// What mj_forward reads, from one mjData into another of the same model: the state, the inputs
// and the warm start (a whole mj_copyData copies MuJoCo's arena, megabytes, at every step).
void copy_mujoco_inputs(const mjModel* m, const mjData* from, mjData* to) {
  to->time = from->time;
  mju_copy(to->qpos, from->qpos, m->nq);
  mju_copy(to->qvel, from->qvel, m->nv);
  mju_copy(to->act, from->act, m->na);
  mju_copy(to->ctrl, from->ctrl, m->nu);
  mju_copy(to->qfrc_applied, from->qfrc_applied, m->nv);
  mju_copy(to->xfrc_applied, from->xfrc_applied, 6 * m->nbody);
  mju_copy(to->mocap_pos, from->mocap_pos, 3 * m->nmocap);
  mju_copy(to->mocap_quat, from->mocap_quat, 4 * m->nmocap);
  mju_copy(to->qacc_warmstart, from->qacc_warmstart, m->nv);
}

void count(RunStats& stats, int nefc) {
  ++stats.steps;
  if (nefc > 0) ++stats.constrained_steps;
  if (nefc > stats.max_rows) stats.max_rows = nefc;
}

// qpos, qvel (state after the step) and qacc, qfrc_constraint, actuator_force (its forward pass)
// of `ours` against MuJoCo's `d`.
void compare_trajectory_point(const Model& model, int k, const double* qpos, const double* qvel,
                              const double* qacc, const double* qfrc_constraint,
                              const double* actuator_force, const mjData* d, Report& r,
                              bool with_actuators) {
  const Labeler dof = [&model](int i) {
    return "dof " + std::to_string(i) + " (joint '" + model.jnt_name[model.dof_jntid[i]] + "')";
  };
  r.compare("qpos", k, qpos, d->qpos, model.nq, per_coordinate(model));
  r.compare("qvel", k, qvel, d->qvel, model.nv, dof);
  r.compare("qacc", k, qacc, d->qacc, model.nv, dof);
  r.compare("qfrc_constraint", k, qfrc_constraint, d->qfrc_constraint, model.nv, dof);
  if (with_actuators) {
    r.compare("actuator_force", k, actuator_force, d->actuator_force, model.nu,
              [&model](int a) { return "actuator '" + model.actuator_name[a] + "'"; });
  }
}

}  // namespace

std::uint64_t default_seed(const std::string& file) { return test::seed_for(file); }

Report random_states(Twin& twin, int states, std::uint64_t seed) {
  Report report;
  report.set_solver_bound(twin.model.contacts_possible ? kContactSolverBound : 1.0);
  compare_model_constants(twin, report);
  std::mt19937_64 rng(seed);
  for (int k = 0; k < states; ++k) {
    const test::State s = test::random_state(twin.model, rng);
    const Eigen::VectorXd qacc = test::random_qacc(twin.model, rng);
    try {
      compare_state(twin, s, qacc, k, report);
    } catch (const StateError& e) {
      // lever refuses the state (it would need more contacts or rows than the model has room
      // for) where MuJoCo keeps what fits and warns: there is no common answer to compare
      report.skip(k, e.what());
    }
  }
  return report;
}

namespace {

// compare_state's name for it
const char* const kInverseAtForward = "qfrc_inverse (at the forward qacc)";

std::vector<double> full_mass_matrix(const mjModel* m, const mjData* d) {
  std::vector<double> M(static_cast<std::size_t>(m->nv) * m->nv);
  mj_fullM(m, M.data(), d->qM);
  return M;
}

}  // namespace

const std::vector<std::string>& self_noise_quantities() {
  static const std::vector<std::string> names{
      "M",         "qfrc_bias", "qacc_smooth", "qacc", "qfrc_constraint", "efc_force",
      kInverseAtForward};
  return names;
}

Report mujoco_self_noise(const Twin& twin, int states, std::uint64_t seed) {
  const mjModel* m = twin.m.get();
  test::MjModelPtr moved(mj_copyModel(nullptr, m), mj_deleteModel);
  const double offset[3] = {0.37, 0.21, 0.3};  // any offset will do: it only changes the rounding
  for (int b = 1; b < m->nbody; ++b) {
    if (m->body_parentid[b] != 0) continue;
    for (int c = 0; c < 3; ++c) moved->body_pos[3 * b + c] += offset[c];
  }
  test::MjDataPtr d = test::mujoco_data(m), e = test::mujoco_data(moved.get());
  const Labeler none;
  Report report;
  for (const std::string& q : self_noise_quantities()) report.declare(q);
  std::mt19937_64 rng(seed);  // the same draws as random_states()
  for (int k = 0; k < states; ++k) {
    const test::State s = test::random_state(twin.model, rng);
    test::random_qacc(twin.model, rng);
    set_mujoco_state(m, d.get(), s);
    set_mujoco_state(moved.get(), e.get(), s);
    mujoco_forward_converged(m, d.get(), twin.restart_mujoco_solver);
    mujoco_forward_converged(moved.get(), e.get(), twin.restart_mujoco_solver);
    const int nv = m->nv;
    report.compare("M", k, full_mass_matrix(moved.get(), e.get()).data(),
                   full_mass_matrix(m, d.get()).data(), nv * nv, none);
    report.compare("qfrc_bias", k, e->qfrc_bias, d->qfrc_bias, nv, none);
    report.compare("qacc_smooth", k, e->qacc_smooth, d->qacc_smooth, nv, none);
    report.compare("qacc", k, e->qacc, d->qacc, nv, none);
    report.compare("qfrc_constraint", k, e->qfrc_constraint, d->qfrc_constraint, nv, none);
    if (e->nefc == d->nefc)
      report.compare("efc_force", k, e->efc_force, d->efc_force, d->nefc, none);
    // the inverse dynamics at the forward acceleration, against itself at that acceleration
    // moved by one ulp: its constraint forces are D (J qacc - aref), and where D reaches 1e6
    // (elliptic cones with impratio 100) qacc's last bit shows in them
    const std::vector<double> qacc(d->qacc, d->qacc + nv);
    const ForwardInputs given(m, d.get());
    mj_inverse(m, d.get());
    const std::vector<double> inverse(d->qfrc_inverse, d->qfrc_inverse + nv);
    given.restore(d.get());
    for (int i = 0; i < nv; ++i) d->qacc[i] = std::nextafter(qacc[i], HUGE_VAL);
    mj_inverse(m, d.get());
    report.compare(kInverseAtForward, k, d->qfrc_inverse, inverse.data(), nv, none);
  }
  return report;
}

Report lockstep(Twin& twin, Integrator integrator, double seconds, Control control,
                RunStats* stats) {
  Report report;
  report.set_solver_bound(twin.model.contacts_possible ? kContactSolverBound : 1.0);
  RunStats local;
  const Integrator own = twin.model.opt.integrator;
  twin.set_integrator(integrator);
  twin.reset();
  const int steps = steps_for(twin.model, seconds);
  const Labeler dof = [&twin](int i) {
    return "dof " + std::to_string(i) + " (joint '" + twin.model.jnt_name[twin.model.dof_jntid[i]] +
           "')";
  };
  const int nv = twin.model.nv;
  // an RK4 step's MuJoCo side along lever's stages, beside MuJoCo's own
  test::MjDataPtr along_lever(nullptr, mj_deleteData);
  if (integrator == Integrator::kRK4) along_lever = test::mujoco_data(twin.m.get());
  MujocoRk4Stages stages;
  for (int k = 0; k < steps; ++k) {
    apply_control(twin.model, control, twin.d->time, twin.d.get());
    twin.follow_mujoco();
    // the step's forward pass, from the shared start state: its acceleration and limit forces
    // (after an RK4 step MuJoCo's qacc belongs to the last stage, at a state the two engines
    // reach by different roundings, so the start state's evaluation is the one compared)
    forward(twin.model, twin.data);
    twin.mujoco_forward();
    count(local, twin.d->nefc);
    report.compare("qacc", k, twin.data.qacc.data(), twin.d->qacc, nv, dof);
    report.compare("qfrc_constraint", k, twin.data.qfrc_constraint.data(), twin.d->qfrc_constraint,
                   nv, dof);
    // the transition: the state after one step
    step(twin.model, twin.data);
    const mjData* after = twin.d.get();  // MuJoCo's state after the step, compared
    if (integrator == Integrator::kRK4) {
      // lever's step against MuJoCo's along the stages lever's step went through (lever/diff/
      // rk4.hpp says why); the run goes on from MuJoCo's own step, each stage converged
      copy_mujoco_inputs(twin.m.get(), twin.d.get(), along_lever.get());
      mujoco_rk4_step(twin.m.get(), along_lever.get(), twin.restart_mujoco_solver,
                      &twin.data.work.rk_qacc, &stages);
      compare_rk4_stages(twin.model, twin.data, stages, k, report);
      after = along_lever.get();
      mujoco_rk4_step(twin.m.get(), twin.d.get(), twin.restart_mujoco_solver, nullptr, nullptr);
    } else {
      mujoco_step_converged(twin.m.get(), twin.d.get(), twin.restart_mujoco_solver);
    }
    report.compare("qpos", k, twin.data.qpos.data(), after->qpos, twin.model.nq,
                   per_coordinate(twin.model));
    report.compare("qvel", k, twin.data.qvel.data(), after->qvel, nv, dof);
  }
  twin.set_integrator(own);
  if (stats) *stats = local;
  return report;
}

FreeRun free_run(Twin& twin, double seconds, Control control, double nudge) {
  FreeRun run;
  twin.reset();
  test::MjDataPtr nudged = test::mujoco_data(twin.m.get());
  mj_copyData(nudged.get(), twin.m.get(), twin.d.get());  // the same start, a keyframe's too
  for (int i = 0; i < twin.model.nq; ++i) nudged->qpos[i] += nudge;
  const int steps = steps_for(twin.model, seconds);
  for (int k = 0; k < steps; ++k) {
    Eigen::Map<Eigen::VectorXd> ctrl(twin.data.ctrl.data(), twin.model.nu);
    apply_control(twin.model, control, twin.d->time, twin.d.get());
    apply_control(twin.model, control, nudged->time, nudged.get());
    if (control == Control::kSmooth) test::smooth_control(twin.model, twin.data.time, ctrl);
    if (control == Control::kZero) ctrl.setZero();
    step(twin.model, twin.data);
    mujoco_step_converged(twin.m.get(), twin.d.get(), twin.restart_mujoco_solver);
    count(run.stats, twin.d->nefc);
    const Data& data = twin.data;
    compare_trajectory_point(twin.model, k, data.qpos.data(), data.qvel.data(), data.qacc.data(),
                             data.qfrc_constraint.data(), data.actuator_force.data(), twin.d.get(),
                             run.lever_vs_mujoco, true);
    if (nudge == 0.0) continue;
    mujoco_step_converged(twin.m.get(), nudged.get(), twin.restart_mujoco_solver);
    compare_trajectory_point(twin.model, k, nudged->qpos, nudged->qvel, nudged->qacc,
                             nudged->qfrc_constraint, nudged->actuator_force, twin.d.get(),
                             run.nudged_vs_mujoco, true);
  }
  return run;
}

const std::vector<std::string>& free_run_quantities() {
  static const std::vector<std::string> names{"qpos", "qvel", "qacc", "qfrc_constraint",
                                              "actuator_force"};
  return names;
}

}  // namespace lever::diff
