// (7) Singular poses: for every site, the singular values of its Jacobian over the joint ranges.
//
// The rows: [jacp; jacr] (6 x nv) when the arm has 6 joints or more, else jacp alone (3 x nv): a
// 2-joint planar arm cannot place and orient its site at once, so its position is the task. The
// rows' generic rank k (the largest numerical rank over the sampled poses: 2 for a planar arm's
// position, 6 for a 7-joint arm) says how many singular values count; the pose is singular where
// sigma_k, the smallest of them, vanishes. Manipulability is their product (sqrt(det(J J^T)) when
// k is the number of rows), the condition number sigma_1 / sigma_k. Mixed rows (m/rad and
// rad/rad) are used as they are, as the usual 6 x n manipulability does.
//
// The search for the most singular poses is the torque budget's (worst_pose.cpp) in spirit:
// simple poses, keyframes and samples (a grid for nv <= 3, random poses beyond), then coordinate
// descent on sigma_k from the best starts: each coordinate over a 24-point grid of its range, then
// a golden-section refinement between the grid points around the best; coordinates that lose
// nothing go back to 0, qpos0 or a range end.
#include <algorithm>
#include <cmath>
#include <random>

#include <lever/spectra.hpp>

#include <lever/data.hpp>
#include <lever/kinematics.hpp>

#include <lever/check.hpp>
#include "reference.hpp"
#include "util.hpp"

namespace lever::check {

namespace {

constexpr long kSamples = 2000;
constexpr int kStarts = 3;
constexpr int kGrid = 24;
constexpr int kGolden = 40;
constexpr int kSweeps = 20;
constexpr double kRankTolerance = 1e-9;  // relative to sigma_1: a singular value that counts

// The singular values with those that do not count set to 0. The Jacobian's entries carry
// rounding of order 1e-16 sigma_1 per joint of the chain, so near a singular pose sigma_k
// settles at 1e-15..1e-13 sigma_1 wherever the search stops: noise, not a measure of how
// singular the pose is. Zeroed, such poses print as singular (manipulability 0, condition inf)
// and rank equal, rather than ordered by their rounding. (The search itself descends on the
// values as computed, so that it ends on the singular pose rather than anywhere near it.)
Eigen::VectorXd counted(Eigen::VectorXd sigma) {
  const double floor = sigma.size() ? kRankTolerance * sigma[0] : 0.0;
  for (Eigen::Index i = 0; i < sigma.size(); ++i) {
    if (sigma[i] <= floor) sigma[i] = 0.0;
  }
  return sigma;
}

// The site Jacobian's singular values at any pose, counting evaluations.
class JacobianProbe {
 public:
  JacobianProbe(const Model& model, int site, int rows)
      : model_(model),
        data_(model),
        site_(site),
        rows_(rows),
        jacp_(3, model.nv),
        jacr_(3, model.nv),
        J_(rows, model.nv) {}

  const Eigen::MatrixXd& jacobian(const Eigen::VectorXd& q) {
    data_.qpos = q;
    kinematics(model_, data_);
    jac_site(model_, data_, site_, jacp_, jacr_);
    J_.topRows(3) = jacp_;
    if (rows_ == 6) J_.bottomRows(3) = jacr_;
    ++evaluations;
    return J_;
  }
  Eigen::VectorXd sigma(const Eigen::VectorXd& q) {
    return singular_values(jacobian(q));
  }
  const Data& data() const { return data_; }

  long evaluations = 0;

 private:
  const Model& model_;
  Data data_;
  int site_, rows_;
  Eigen::MatrixXd jacp_, jacr_, J_;
};

// sigma_k (k = rank), or 0 when there are fewer singular values.
double smallest(const Eigen::VectorXd& sigma, int rank) {
  return rank > 0 && sigma.size() >= rank ? sigma[rank - 1] : 0.0;
}

std::vector<JointAlignment> aligned_joints(const Model& model, const Data& data, double tol) {
  std::vector<JointAlignment> out;
  for (int i = 0; i < model.njnt; ++i) {
    for (int j = i + 1; j < model.njnt; ++j) {
      const Eigen::Vector3d a = data.xaxis[i], b = data.xaxis[j];
      const double angle = std::atan2(a.cross(b).norm(), std::abs(a.dot(b)));
      if (angle > tol) continue;
      JointAlignment al{joint_label(model, i), joint_label(model, j), false, angle, 0.0};
      if (is_hinge(model, i) && is_hinge(model, j)) {  // distance between the two axis lines
        al.distance = (data.xanchor[j] - data.xanchor[i]).cross(a).norm();
        al.collinear = al.distance <= tol;
      }
      out.push_back(al);
    }
  }
  return out;
}

JacobianAt evaluate(const Model& model, JacobianProbe& probe, const std::string& where,
                    const Eigen::VectorXd& q, int rank, double tol) {
  JacobianAt at;
  at.where = where;
  at.q = q;
  const SingularValueDecomposition svd = singular_value_decomposition(probe.jacobian(q));
  const Eigen::VectorXd all = counted(svd.sigma);
  at.sigma = all.head(std::min<Eigen::Index>(rank, all.size()));
  at.manipulability = at.sigma.size() ? at.sigma.prod() : 0.0;
  const double low = smallest(all, rank);
  at.condition = low > 0 ? all[0] / low : kInf;
  if (rank > 0) {
    // with more joints than task rows the Jacobian has a null space even at regular poses; the
    // motion that matters is the k-th right singular vector, the direction that moves the site
    // least
    at.null_motion = svd.V.col(rank - 1);
    Eigen::Index big = 0;
    at.null_motion.cwiseAbs().maxCoeff(&big);
    if (at.null_motion[big] < 0) at.null_motion = -at.null_motion;  // a sign to print the same
  }
  at.aligned = aligned_joints(model, probe.data(), tol);
  return at;
}

// Minimize sigma_k over coordinate j: a grid, then golden section around its best point.
double descend_coordinate(const Model& model, JacobianProbe& probe, int rank, int j,
                          Eigen::VectorXd& q, double best) {
  const int adr = model.jnt_qposadr[j];
  const auto box = joint_box(model, j);
  const double width = box[1] - box[0];
  if (!(width > 0)) return best;
  Eigen::VectorXd trial = q;
  double at = q[adr];
  for (int k = 0; k <= kGrid; ++k) {
    trial[adr] = box[0] + width * k / kGrid;
    const double v = smallest(probe.sigma(trial), rank);
    if (v < best) {
      best = v;
      at = trial[adr];
    }
  }
  // golden section on [at - cell, at + cell] within the box
  const double cell = width / kGrid;
  double lo = std::max(box[0], at - cell), hi = std::min(box[1], at + cell);
  const double r = (std::sqrt(5.0) - 1.0) / 2.0;
  double x1 = hi - r * (hi - lo), x2 = lo + r * (hi - lo);
  trial[adr] = x1;
  double f1 = smallest(probe.sigma(trial), rank);
  trial[adr] = x2;
  double f2 = smallest(probe.sigma(trial), rank);
  for (int k = 0; k < kGolden; ++k) {
    if (f1 < f2) {
      hi = x2;
      x2 = x1;
      f2 = f1;
      x1 = hi - r * (hi - lo);
      trial[adr] = x1;
      f1 = smallest(probe.sigma(trial), rank);
    } else {
      lo = x1;
      x1 = x2;
      f1 = f2;
      x2 = lo + r * (hi - lo);
      trial[adr] = x2;
      f2 = smallest(probe.sigma(trial), rank);
    }
  }
  const double x = f1 < f2 ? x1 : x2, f = std::min(f1, f2);
  if (f < best) {
    best = f;
    at = x;
  }
  q[adr] = at;
  return best;
}

double descend(const Model& model, JacobianProbe& probe, int rank, Eigen::VectorXd& q) {
  double best = smallest(probe.sigma(q), rank);
  for (int sweep = 0; sweep < kSweeps; ++sweep) {
    const double before = best;
    for (int j = 0; j < model.njnt; ++j) best = descend_coordinate(model, probe, rank, j, q, best);
    if (before - best <= 1e-12 * std::max(1.0, before)) break;
  }
  return best;
}

// Coordinates back to 0, qpos0 or a range end where sigma_k stays within 1e-9 (absolute) of best.
void simplify(const Model& model, JacobianProbe& probe, int rank, Eigen::VectorXd& q, double best) {
  for (int j = 0; j < model.njnt; ++j) {
    const int adr = model.jnt_qposadr[j];
    const auto box = joint_box(model, j);
    for (const double value : {0.0, model.qpos0[adr], box[0], box[1]}) {
      if (value < box[0] || value > box[1]) continue;
      if (value == q[adr]) break;
      Eigen::VectorXd trial = q;
      trial[adr] = value;
      if (smallest(probe.sigma(trial), rank) <= best + 1e-9) {
        q = trial;
        break;
      }
    }
  }
}

std::vector<Eigen::VectorXd> start_poses(const Model& model, std::string& how) {
  std::vector<Eigen::VectorXd> poses{zero_pose(model), model.qpos0};
  for (int k = 0; k < model.nkey; ++k) poses.push_back(model.key_qpos.row(k).transpose());
  for (int j = 0; j < model.njnt; ++j) {
    for (const double end : joint_box(model, j)) {
      Eigen::VectorXd q = zero_pose(model);
      q[model.jnt_qposadr[j]] = end;
      poses.push_back(q);
    }
  }
  std::mt19937_64 rng(1);
  for (long i = 0; i < kSamples; ++i) poses.push_back(random_pose(model, rng));
  how = "all joints at 0, qpos0, the keyframes, each range end, " + std::to_string(kSamples) +
        " random poses, then coordinate descent on sigma_min from the best " +
        std::to_string(kStarts) + " of them (" + std::to_string(kGrid) +
        "-point grid and golden section per joint)";
  return poses;
}

SiteSingularity check_site(const Model& model, int s, const std::vector<Eigen::VectorXd>& starts,
                           const std::vector<int>& keys, double tol, long& evaluations) {
  SiteSingularity site;
  site.site = site_label(model, s);
  site.rows = model.nv >= 6 ? 6 : 3;
  JacobianProbe probe(model, s, site.rows);
  // the generic rank, and sigma_k of every start
  std::vector<Eigen::VectorXd> sigmas;
  for (const Eigen::VectorXd& q : starts) {
    sigmas.push_back(probe.sigma(q));
    const Eigen::VectorXd& sv = sigmas.back();
    int r = 0;
    for (Eigen::Index i = 0; i < sv.size(); ++i)
      r += sv[i] > kRankTolerance * std::max(sv[0], 1e-300);
    site.rank = std::max(site.rank, r);
  }
  site.states.push_back(evaluate(model, probe, "qpos0", model.qpos0, site.rank, tol));
  for (const int k : keys) {
    site.states.push_back(evaluate(model, probe, "keyframe " + label(model.key_name[k], "key", k),
                                   model.key_qpos.row(k).transpose(), site.rank, tol));
  }
  if (site.rank > 0) {
    std::vector<size_t> order(starts.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
      return smallest(sigmas[a], site.rank) < smallest(sigmas[b], site.rank);
    });
    std::vector<std::pair<double, Eigen::VectorXd>> found;
    for (size_t n = 0; n < order.size() && n < static_cast<size_t>(kStarts); ++n) {
      Eigen::VectorXd q = starts[order[n]];
      const double best = descend(model, probe, site.rank, q);
      simplify(model, probe, site.rank, q, best);
      const bool seen = std::any_of(found.begin(), found.end(), [&](const auto& f) {
        return (f.second - q).cwiseAbs().maxCoeff() < 1e-6;
      });
      // ranked by the values that count: poses singular to rounding tie
      if (!seen) found.push_back({smallest(counted(probe.sigma(q)), site.rank), q});
    }
    std::stable_sort(found.begin(), found.end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });
    for (size_t n = 0; n < found.size(); ++n) {
      site.worst.push_back(evaluate(model, probe, "worst " + std::to_string(n + 1), found[n].second,
                                    site.rank, tol));
    }
  }
  evaluations += probe.evaluations;
  return site;
}

}  // namespace

SingularPoses check_singular_poses(const Model& model, const std::string& key) {
  SingularPoses result;
  std::vector<int> keys;
  if (!key.empty()) {
    Data data(model);
    reset_keyframe(model, data,
                   key);  // throws, listing the keyframes, if there is none of that name
    keys.push_back(model.key(key));
  } else {
    for (int k = 0; k < model.nkey; ++k) keys.push_back(k);
  }
  if (model.nsite == 0 || model.nv == 0) return result;
  const std::vector<Eigen::VectorXd> starts = start_poses(model, result.search);
  for (int s = 0; s < model.nsite; ++s) {
    result.sites.push_back(
        check_site(model, s, starts, keys, result.parallel_tolerance, result.evaluations));
  }
  return result;
}

}  // namespace lever::check
