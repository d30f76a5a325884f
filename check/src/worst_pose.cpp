#include "worst_pose.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include <lever/dynamics.hpp>
#include <lever/kinematics.hpp>

#include "reference.hpp"
#include "util.hpp"

namespace lever::check {

namespace {

constexpr long kSampleBudget = 2000;  // grid points or random samples
constexpr int kStartsPerJoint = 3;
constexpr int kMaxSweeps = 100;
constexpr double kTie = 1e-12;  // relative: a pose this close to the best counts as a tie

struct Candidate {
  Eigen::VectorXd q;
  Eigen::VectorXd tau;
  bool simple = false;  // all zero, qpos0 or a range end: preferred on ties
};

// The simple poses: every joint at 0, qpos0, and each joint at each end of its box.
std::vector<Eigen::VectorXd> simple_poses(const Model& model) {
  const Eigen::VectorXd zero = zero_pose(model);
  std::vector<Eigen::VectorXd> poses{zero, model.qpos0};
  for (int j = 0; j < model.njnt; ++j) {
    for (const double end : joint_box(model, j)) {
      Eigen::VectorXd q = zero;
      q[model.jnt_qposadr[j]] = end;
      poses.push_back(q);
    }
  }
  return poses;
}

// A grid of n points per joint over the boxes (nv <= 3), or random samples.
std::vector<Eigen::VectorXd> sample_poses(const Model& model, std::string& how) {
  std::vector<Eigen::VectorXd> poses;
  if (model.njnt == 0) return poses;
  if (model.njnt <= 3) {
    const int n = static_cast<int>(std::floor(std::pow(double(kSampleBudget), 1.0 / model.njnt)));
    long total = 1;
    for (int j = 0; j < model.njnt; ++j) total *= n;
    for (long index = 0; index < total; ++index) {
      Eigen::VectorXd q = model.qpos0;
      long rest = index;
      for (int j = 0; j < model.njnt; ++j) {
        const auto box = joint_box(model, j);
        q[model.jnt_qposadr[j]] = box[0] + (box[1] - box[0]) * double(rest % n) / (n - 1);
        rest /= n;
      }
      poses.push_back(q);
    }
    how = std::to_string(total) + "-pose grid";
  } else {
    std::mt19937_64 rng(1);
    for (long i = 0; i < kSampleBudget; ++i) poses.push_back(random_pose(model, rng));
    how = std::to_string(kSampleBudget) + " random poses";
  }
  return poses;
}

// Does joint j move joint i's load or axis? (j is i, or on i's path to the world, or beyond i)
bool related(const Model& model, int i, int j) {
  const int di = model.jnt_dofadr[i], dj = model.jnt_dofadr[j];
  for (int d = di; d >= 0; d = model.dof_parentid[d]) {
    if (d == dj) return true;
  }
  for (int d = dj; d >= 0; d = model.dof_parentid[d]) {
    if (d == di) return true;
  }
  return false;
}

// Angles where A cos t + B sin t + C is extreme, fitted from three evaluations at t0 + 2 pi k / 3.
std::vector<double> sinusoid_extremes(GravityProbe& probe, Eigen::VectorXd q, int adr, int dof) {
  const double t0 = q[adr];
  double A = 0.0, B = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double phase = 2.0 * std::numbers::pi * k / 3.0;
    q[adr] = t0 + phase;
    const double f = probe(q)[dof];
    A += 2.0 / 3.0 * f * std::cos(phase);
    B += 2.0 / 3.0 * f * std::sin(phase);
  }
  const double peak = t0 + std::atan2(B, A);
  return {peak, peak + std::numbers::pi};
}

// Every angle congruent to t (mod 2 pi) inside [lo, hi].
void add_wrapped(double t, const std::array<double, 2>& box, std::vector<double>& out) {
  const double two_pi = 2.0 * std::numbers::pi;
  double first = t + two_pi * std::ceil((box[0] - t) / two_pi);
  for (double x = first; x <= box[1]; x += two_pi) out.push_back(x);
}

// Maximize |tau_i| over coordinate j exactly; returns the new |tau_i|.
double maximize_coordinate(const Model& model, GravityProbe& probe, int i, int j,
                           Eigen::VectorXd& q, double best) {
  const int adr = model.jnt_qposadr[j], dof = model.jnt_dofadr[i];
  const auto box = joint_box(model, j);
  std::vector<double> trials{box[0], box[1]};
  if (is_hinge(model, j)) {
    for (const double t : sinusoid_extremes(probe, q, adr, dof)) add_wrapped(t, box, trials);
  }
  Eigen::VectorXd trial = q;
  for (const double t : trials) {
    trial[adr] = t;
    const double value = std::abs(probe(trial)[dof]);
    if (value > best) {
      best = value;
      q[adr] = t;
    }
  }
  return best;
}

// Coordinate ascent on |tau_i| from q.
double ascend(const Model& model, GravityProbe& probe, int i, Eigen::VectorXd& q) {
  double best = std::abs(probe(q)[model.jnt_dofadr[i]]);
  for (int sweep = 0; sweep < kMaxSweeps; ++sweep) {
    const double before = best;
    for (int j = 0; j < model.njnt; ++j) {
      if (related(model, i, j)) best = maximize_coordinate(model, probe, i, j, q, best);
    }
    if (best - before <= 1e-15 * std::max(1.0, best)) break;
  }
  return best;
}

// Put coordinates back to 0, qpos0 or a range end (in that order of preference) wherever that
// loses nothing; a coordinate never moves to a less preferred one.
void simplify(const Model& model, GravityProbe& probe, int i, Eigen::VectorXd& q, double best) {
  const int dof = model.jnt_dofadr[i];
  const double keep = best * (1.0 - kTie);
  for (int j = 0; j < model.njnt; ++j) {
    const int adr = model.jnt_qposadr[j];
    const auto box = joint_box(model, j);
    for (const double value : {0.0, model.qpos0[adr], box[0], box[1]}) {
      if (value < box[0] || value > box[1]) continue;
      if (value == q[adr]) break;
      Eigen::VectorXd trial = q;
      trial[adr] = value;
      if (std::abs(probe(trial)[dof]) >= keep) {
        q = trial;
        break;
      }
    }
  }
}

// The indices of the k candidates with the largest |tau_i|.
std::vector<size_t> best_candidates(const std::vector<Candidate>& all, int dof, int k) {
  std::vector<size_t> order(all.size());
  for (size_t n = 0; n < order.size(); ++n) order[n] = n;
  const size_t count = std::min<size_t>(k, order.size());
  std::partial_sort(order.begin(), order.begin() + count, order.end(), [&](size_t a, size_t b) {
    return std::abs(all[a].tau[dof]) > std::abs(all[b].tau[dof]);
  });
  order.resize(count);
  return order;
}

WorstPose worst_for_joint(const Model& model, GravityProbe& probe,
                          const std::vector<Candidate>& candidates, int i) {
  const int dof = model.jnt_dofadr[i];
  Eigen::VectorXd best_q = candidates.front().q;
  double best = -1.0;
  for (const size_t start : best_candidates(candidates, dof, kStartsPerJoint)) {
    Eigen::VectorXd q = candidates[start].q;
    const double value = ascend(model, probe, i, q);
    if (value > best) {
      best = value;
      best_q = q;
    }
  }
  if (best <= kUnloaded) {  // gravity never loads this joint: any pose is worst; take all zero
    const Eigen::VectorXd zero = zero_pose(model);
    return {probe(zero)[dof], zero};
  }
  for (const Candidate& c : candidates) {  // a simple pose that ties wins
    if (c.simple && std::abs(c.tau[dof]) >= best * (1.0 - kTie)) {
      best_q = c.q;
      break;
    }
  }
  simplify(model, probe, i, best_q, best);
  return {probe(best_q)[dof], best_q};
}

}  // namespace

GravityProbe::GravityProbe(const Model& model) : model_(model), data_(model) {}

const ArenaVector& GravityProbe::operator()(const Eigen::VectorXd& qpos) {
  data_.qpos = qpos;
  data_.qvel.setZero();
  kinematics(model_, data_);
  bias(model_, data_);
  ++evaluations_;
  return data_.qfrc_bias;
}

std::vector<WorstPose> worst_gravity_poses(const Model& model, GravityProbe& probe,
                                           std::string& how) {
  std::vector<Candidate> candidates;
  for (const Eigen::VectorXd& q : simple_poses(model)) candidates.push_back({q, probe(q), true});
  for (const Eigen::VectorXd& q : sample_poses(model, how)) {
    candidates.push_back({q, probe(q), false});
  }
  how = "all joints at 0, qpos0, each range end, " + how +
        ", then coordinate ascent from the best " + std::to_string(kStartsPerJoint) + " of them";
  std::vector<WorstPose> worst;
  worst.reserve(static_cast<size_t>(model.njnt));
  for (int i = 0; i < model.njnt; ++i)
    worst.push_back(worst_for_joint(model, probe, candidates, i));
  return worst;
}

}  // namespace lever::check
