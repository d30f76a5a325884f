// (5) Joint stops are soft constraints: for each limited joint and each stop that gravity can
// load, rest the model on it with zero torque and report how far past the stop it rests and the
// limit force against the gravity torque there.
//
// First the lesson's run: the model falls from qpos0 (arm2's shoulder lands on its lower stop,
// as in the lesson's 60 s run), and every stop it comes to rest on is reported from that run.
// Each other stop gets its own run, starting with the joint just inside the stop and the other
// joints at the first of a few poses (qpos0, all at 0, one joint at a range end, all at their
// lower or upper ends) where gravity pushes the joint into the stop.
//
// A lightly damped arm swings for a minute before it is still (arm2's elbow decays with a 4 s
// time constant), so each run has three phases that end in the same place sooner:
//   relax:  quenched dynamics without joint damping (every velocity is zeroed whenever the motion
//           runs against the net force), until every |qvel| < relax_qvel;
//   polish: Newton's method on the net joint force at rest, which is zero exactly where the model
//           can rest, from that nearby pose;
//   settle: the model itself, damping and all, until every |qvel| has stayed below settle_qvel
//           for settle_time, or time_bound passes.
// The relaxation and the polish change the path, not where the model may rest: the state reported
// is one the model's own dynamics keeps still. Runs from the same pose are simulated once, and
// runs go in parallel (one Data each, one shared Model).
#include <algorithm>
#include <atomic>
#include <cmath>
#include <thread>

#include <Eigen/Dense>

#include <lever/data.hpp>
#include <lever/forward.hpp>

#include <lever/check.hpp>
#include "reference.hpp"
#include "util.hpp"
#include "worst_pose.hpp"

namespace lever::check {

namespace {

// One simulation from a start pose, and the state it came to rest in.
struct Run {
  Eigen::VectorXd start;
  double time = 0.0, relax_time = 0.0, max_qvel = 0.0;
  bool settled = false;
  int warnings = 0, nefc = 0;
  Eigen::VectorXd qpos, qfrc_constraint, qfrc_bias, qfrc_passive;
  std::vector<int> efc_id;  ///< a limit row's joint; -1 for every other row
  std::vector<double> efc_sign, efc_force;
};

// Poses of the other joints to try, most preferred first; joint j is placed by the caller.
std::vector<Eigen::VectorXd> other_joint_poses(const Model& model, int j) {
  std::vector<Eigen::VectorXd> poses{model.qpos0, zero_pose(model)};
  Eigen::VectorXd all_low = model.qpos0, all_high = model.qpos0;
  for (int k = 0; k < model.njnt; ++k) {
    if (k == j) continue;
    const int adr = model.jnt_qposadr[k];
    const auto box = joint_box(model, k);
    for (const double end : box) {
      Eigen::VectorXd q = model.qpos0;
      q[adr] = end;
      poses.push_back(q);
    }
    all_low[adr] = box[0];
    all_high[adr] = box[1];
  }
  poses.push_back(all_low);
  poses.push_back(all_high);
  return poses;
}

// Choose where the run starts; false if gravity pushes the joint into the stop at no pose tried.
bool choose_start(const Model& model, GravityProbe& probe, int j, StopRest& rest) {
  const int adr = model.jnt_qposadr[j], dof = model.jnt_dofadr[j];
  const double width = model.jnt_range[j][1] - model.jnt_range[j][0];
  const double inside = std::min(rest.hinge ? 0.01 : 0.001, 0.1 * width);
  const double loading = rest.upper ? -1.0 : 1.0;  // sign of qfrc_bias that pushes into the stop
  for (Eigen::VectorXd q : other_joint_poses(model, j)) {
    q[adr] = rest.stop + loading * inside;  // loading is also the way into the range
    if (loading * probe(q)[dof] <= kUnloaded) continue;
    rest.start = q;
    return true;
  }
  return false;
}

// The model without joint damping, for the relaxation: quenching removes the energy instead.
Model undamped(const Model& model) {
  Model relaxed = model;
  std::fill(relaxed.dof_damping.begin(), relaxed.dof_damping.end(), 0.0);
  set_const(relaxed);
  return relaxed;
}

// Quenched dynamics: step, and stop every joint whenever the motion runs against the net force
// (it would only climb and swing back), until every |qvel| stayed below the threshold.
void relax(const Model& relaxed, Data& data, double threshold, double calm, double bound) {
  double calm_since = data.time;
  while (data.time < bound) {
    step(relaxed, data);
    if (data.qvel.dot(data.qfrc_smooth + data.qfrc_constraint) < 0) data.qvel.setZero();
    const double fastest = relaxed.nv > 0 ? data.qvel.cwiseAbs().maxCoeff() : 0.0;
    if (!(fastest < threshold)) calm_since = data.time;
    if (data.time - calm_since >= calm) return;
  }
}

// Step with zero control until every |qvel| stayed below the threshold for `calm` seconds.
bool settle(const Model& model, Data& data, double threshold, double calm, double bound) {
  const double end = data.time + bound;
  double calm_since = data.time;
  while (data.time < end) {
    step(model, data);
    const double fastest = model.nv > 0 ? data.qvel.cwiseAbs().maxCoeff() : 0.0;
    if (!(fastest < threshold)) calm_since = data.time;
    if (data.time - calm_since >= calm) return true;
  }
  return false;
}

// The net joint force at rest at q (zero velocity and control): zero where the model can rest.
Eigen::VectorXd net_force_at_rest(const Model& model, Data& data, const Eigen::VectorXd& q) {
  data.qpos = q;
  data.qvel.setZero();
  forward(model, data);
  return data.qfrc_smooth + data.qfrc_constraint;
}

// Newton's method on the net force at rest, from a pose near rest: it finishes in a few
// iterations the last slow creep of a relaxation. The Jacobian is by central differences; a
// joint nothing holds (no gravity, no spring) makes it singular, hence the least-squares solve.
void polish(const Model& model, Data& data) {
  constexpr double h = 1e-6;
  Eigen::VectorXd q = data.qpos;
  Eigen::VectorXd force = net_force_at_rest(model, data, q);
  Eigen::MatrixXd J(model.nv, model.nv);
  for (int iteration = 0; iteration < 30 && force.lpNorm<Eigen::Infinity>() > 1e-12; ++iteration) {
    for (int i = 0; i < model.nv; ++i) {
      Eigen::VectorXd dq = Eigen::VectorXd::Zero(model.nq);
      dq[i] = h;
      J.col(i) = (net_force_at_rest(model, data, q + dq) - net_force_at_rest(model, data, q - dq)) /
                 (2 * h);
    }
    const Eigen::VectorXd step_dq = J.completeOrthogonalDecomposition().solve(-force);
    bool improved = false;
    for (double alpha = 1.0; alpha > 1e-3 && !improved; alpha /= 2) {
      const Eigen::VectorXd trial = q + alpha * step_dq;
      const Eigen::VectorXd trial_force = net_force_at_rest(model, data, trial);
      if (trial_force.norm() < force.norm()) {
        q = trial;
        force = trial_force;
        improved = true;
      }
    }
    if (!improved) break;
  }
  data.qpos = q;
  data.qvel.setZero();
}

void simulate(const Model& model, const Model& relaxed, const SoftStops& rules, Run& run) {
  Data data(model);
  data.qpos = run.start;
  relax(relaxed, data, rules.relax_qvel, 0.25 * rules.settle_time, rules.relax_bound);
  run.relax_time = data.time;
  polish(model, data);
  run.settled = settle(model, data, rules.settle_qvel, rules.settle_time, rules.time_bound);
  forward(model, data);  // outputs at the final state
  run.time = data.time;
  run.max_qvel = model.nv > 0 ? data.qvel.cwiseAbs().maxCoeff() : 0.0;
  for (const WarningStat& w : data.warning) run.warnings += w.number;
  run.qpos = data.qpos;
  run.qfrc_constraint = data.qfrc_constraint;
  run.qfrc_bias = data.qfrc_bias;
  run.qfrc_passive = data.qfrc_passive;
  run.nefc = data.nefc;
  run.efc_id.assign(data.efc_id.begin(), data.efc_id.begin() + data.nefc);
  for (int r = 0; r < data.nefc; ++r) {  // only limit rows name a joint (rests_on)
    if (data.efc_type[r] != ConstraintType::kLimitJoint) run.efc_id[r] = -1;
  }
  run.efc_sign.assign(data.efc_sign.begin(), data.efc_sign.begin() + data.nefc);
  run.efc_force.assign(data.efc_force.data(), data.efc_force.data() + data.nefc);
}

void simulate_all(const Model& model, const Model& relaxed, const SoftStops& rules,
                  std::vector<Run>& runs) {
  std::atomic<size_t> next{0};
  const auto worker = [&] {
    for (size_t n = next++; n < runs.size(); n = next++) simulate(model, relaxed, rules, runs[n]);
  };
  const size_t threads =
      std::min<size_t>(runs.size(), std::max(1u, std::thread::hardware_concurrency()));
  std::vector<std::thread> pool;
  for (size_t t = 1; t < threads; ++t) pool.emplace_back(worker);
  worker();
  for (std::thread& t : pool) t.join();
}

size_t find_or_add_run(std::vector<Run>& runs, const Eigen::VectorXd& start) {
  for (size_t n = 0; n < runs.size(); ++n) {
    if (runs[n].start == start) return n;
  }
  runs.push_back({});
  runs.back().start = start;
  return runs.size() - 1;
}

// Does a limit row of joint j hold it at this stop at the end of the run?
bool rests_on(const Run& run, int j, bool upper) {
  const double side = upper ? -1.0 : 1.0;
  for (int r = 0; r < run.nefc; ++r) {
    if (run.efc_id[r] == j && run.efc_sign[r] == side && run.efc_force[r] > 0) return true;
  }
  return false;
}

void measure(const Model& model, const Run& run, int j, StopRest& rest) {
  const int dof = model.jnt_dofadr[j];
  rest.time = run.time;
  rest.relax_time = run.relax_time;
  rest.settled = run.settled;
  rest.max_qvel = run.max_qvel;
  rest.warnings = run.warnings;
  rest.q = run.qpos[model.jnt_qposadr[j]];
  rest.past = rest.upper ? rest.q - rest.stop : rest.stop - rest.q;
  rest.rows = run.nefc;
  rest.qfrc_constraint = run.qfrc_constraint[dof];
  rest.qfrc_bias = run.qfrc_bias[dof];
  rest.qfrc_passive = run.qfrc_passive[dof];
  rest.final_qpos = run.qpos;
  rest.rests_on_stop = rests_on(run, j, rest.upper);
}

}  // namespace

SoftStops check_soft_stops(const Model& model) {
  SoftStops result;
  for (int a = 0; a < model.nu; ++a) {
    if (model.actuator_kind[a] == ActuatorKind::kPositionServo && actuator_scalar_dof(model, a) >= 0) {
      const int j = model.actuator_trnid[a][0];
      result.servo_held_joints.push_back(joint_label(model, j) +
                                         (is_hinge(model, j) ? " (0 rad)" : " (0 m)"));
    }
  }
  if (std::none_of(model.jnt_limited.begin(), model.jnt_limited.end(), [](bool b) { return b; })) {
    return result;
  }
  const Model relaxed = undamped(model);
  std::vector<Run> lesson(1);  // the lesson's run: the model falls from qpos0
  lesson[0].start = model.qpos0;
  simulate_all(model, relaxed, result, lesson);

  GravityProbe probe(model);
  std::vector<Run> runs;
  std::vector<size_t> run_of_stop;
  for (int j = 0; j < model.njnt; ++j) {
    if (!model.jnt_limited[j]) continue;
    for (const bool upper : {false, true}) {
      StopRest rest;
      rest.joint = joint_label(model, j);
      rest.joint_id = j;
      rest.hinge = is_hinge(model, j);
      rest.upper = upper;
      rest.stop = model.jnt_range[j][upper ? 1 : 0];
      rest.margin = model.jnt_margin[j];
      rest.from_qpos0 = rests_on(lesson[0], j, upper);
      rest.loadable = rest.from_qpos0 || choose_start(model, probe, j, rest);
      if (rest.from_qpos0) rest.start = model.qpos0;
      run_of_stop.push_back(rest.loadable && !rest.from_qpos0 ? find_or_add_run(runs, rest.start)
                                                              : 0);
      result.stops.push_back(rest);
    }
  }
  simulate_all(model, relaxed, result, runs);
  result.runs = static_cast<int>(runs.size()) + 1;
  for (size_t s = 0; s < result.stops.size(); ++s) {
    StopRest& rest = result.stops[s];
    if (!rest.loadable) continue;
    measure(model, rest.from_qpos0 ? lesson[0] : runs[run_of_stop[s]], rest.joint_id, rest);
  }
  return result;
}

}  // namespace lever::check
