#include <algorithm>
#include <cmath>
#include <lever/diff/report.hpp>
#include <limits>

#include <lever/harness/tolerance.hpp>

namespace lever::diff {

namespace {
constexpr std::size_t kFailuresKept = 20;  // enough to see a pattern, short enough to read
}  // namespace

bool decided_by_solver(const std::string& q) {
  // the acceleration stage's sensors and the forces inside the tree read qacc and efc_force;
  // qacc_warmstart is the solve's qacc, kept
  return q == "qacc" || q == "qacc_warmstart" || q == "qfrc_constraint" || q == "efc_force" || q == "efc_state" ||
         q == "sensordata" || q == "cacc" || q == "cfrc_int" || q == "cfrc_ext" ||
         q == "qpos" || q == "qvel" || q == "qacc at an RK4 stage" || q.rfind("qfrc_inverse (at the forward", 0) == 0 ||
         q.find(" after one ") != std::string::npos || q.rfind("energy", 0) == 0;
}

void Report::set_solver_bound(double bound) {
  solver_bound_ = bound;
  for (Extreme& e : extremes_) e.bound = decided_by_solver(e.quantity) ? bound : 1.0;
}

Extreme& Report::entry(const std::string& quantity) {
  for (Extreme& e : extremes_) {
    if (e.quantity == quantity) return e;
  }
  Extreme fresh;
  fresh.quantity = quantity;
  fresh.bound = decided_by_solver(quantity) ? solver_bound_ : 1.0;
  extremes_.push_back(fresh);
  return extremes_.back();
}

const Extreme* Report::find(const std::string& quantity) const {
  for (const Extreme& e : extremes_) {
    if (e.quantity == quantity) return &e;
  }
  return nullptr;
}

void Report::record(Extreme& e, int state, int index, double lever, double mujoco, double magnitude,
                    const Labeler& label) {
  ++e.compared;
  const double ratio = test::excess(lever, mujoco, magnitude);
  e.max_elementwise_ratio = std::max(e.max_elementwise_ratio, test::excess(lever, mujoco));
  const double diff = std::isnan(lever) || std::isnan(mujoco)
                          ? std::numeric_limits<double>::infinity()
                          : std::abs(lever - mujoco);
  if (diff > e.max_abs_diff) e.max_abs_diff = diff;
  if (std::abs(mujoco) > e.max_abs_mujoco) e.max_abs_mujoco = std::abs(mujoco);
  const bool beyond = !(ratio <= e.bound);
  if (beyond) ++e.beyond;
  if (ratio > e.max_ratio || e.state < 0) {
    e.max_ratio = ratio;
    e.state = state;
    e.index = index;
    e.element = label ? label(index) : "";
    e.lever = lever;
    e.mujoco = mujoco;
  }
  if (beyond && failures_.size() < kFailuresKept) {
    std::string where = label ? label(index) : "";
    failures_.push_back("state " + std::to_string(state) + ": " +
                        test::describe(e.quantity, index, lever, mujoco, magnitude) +
                        (where.empty() ? "" : " [" + where + "]"));
  }
}

void Report::compare(const std::string& quantity, int state, const double* lever,
                     const double* mujoco, int n, const Labeler& label) {
  Extreme& e = entry(quantity);
  const double scale = test::magnitude(mujoco, n);  // the quantity's magnitude in this state
  for (int i = 0; i < n; ++i) record(e, state, i, lever[i], mujoco[i], scale, label);
}

void Report::compare(const std::string& quantity, int state, double lever, double mujoco,
                     const std::string& element) {
  record(entry(quantity), state, 0, lever, mujoco, mujoco, [&](int) { return element; });
}

void Report::merge(const Report& other) {
  for (const Extreme& o : other.extremes_) {
    Extreme& e = entry(o.quantity);
    e.compared += o.compared;
    e.beyond += o.beyond;
    if (o.max_abs_diff > e.max_abs_diff) e.max_abs_diff = o.max_abs_diff;
    if (o.max_abs_mujoco > e.max_abs_mujoco) e.max_abs_mujoco = o.max_abs_mujoco;
    const double elementwise = std::max(e.max_elementwise_ratio, o.max_elementwise_ratio);
    if (o.max_ratio > e.max_ratio || (e.state < 0 && o.state >= 0)) {
      const Extreme totals = e;  // counts and maxima stay merged; the location is o's
      e = o;
      e.bound = std::max(totals.bound, o.bound);
      e.compared = totals.compared;
      e.beyond = totals.beyond;
      e.max_abs_diff = totals.max_abs_diff;
      e.max_abs_mujoco = totals.max_abs_mujoco;
    }
    e.max_elementwise_ratio = elementwise;
  }
  for (const std::string& f : other.failures_) {
    if (failures_.size() < kFailuresKept) failures_.push_back(f);
  }
  if (first_skipped_.empty()) first_skipped_ = other.first_skipped_;
  skipped_ += other.skipped_;
}

void Report::skip(int state, const std::string& why) {
  if (skipped_++ == 0) first_skipped_ = "state " + std::to_string(state) + ": " + why;
}

bool Report::pass() const {
  for (const Extreme& e : extremes_) {
    if (!e.pass()) return false;
  }
  return true;
}

}  // namespace lever::diff
