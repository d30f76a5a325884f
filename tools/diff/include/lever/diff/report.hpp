// lever/diff/report.hpp: for each compared quantity, the largest difference between lever and
// MuJoCo, its ratio to the agreement bound, and where it was seen.
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace lever::diff {

/// The worst comparison of one quantity.
struct Extreme {
  std::string quantity;
  long compared = 0;          ///< values compared
  long beyond = 0;            ///< values beyond the bound
  double max_abs_diff = 0.0;  ///< largest |lever - mujoco|
  /// largest |lever - mujoco| / (1e-12 max(1, |mujoco|)), |mujoco| the quantity's magnitude in
  /// that state (its largest element): the verdict
  double max_ratio = 0.0;
  /// the same with |mujoco| each element's own value: reported, stricter than the bound where a
  /// small element sits beside large ones (see harness/include/lever/harness/tolerance.hpp)
  double max_elementwise_ratio = 0.0;
  double max_abs_mujoco = 0.0;  ///< largest |mujoco|: the quantity's scale
  // where the largest ratio was seen (state < 0: nothing compared yet)
  int state = -1;       ///< state, or step of a trajectory
  int index = -1;       ///< element of the quantity's flattened array
  std::string element;  ///< that element in words ("body 'link2', z")
  double lever = 0.0, mujoco = 0.0;
  /// the verdict's limit on max_ratio: 1 (the 1e-12 bound), or kContactSolverBound for what the
  /// constraint solver decides in a model with contacts (decided_by_solver)
  double bound = 1.0;

  bool pass() const { return max_ratio <= bound; }
};

/// Whether MuJoCo's constraint solver decides a quantity: the constrained acceleration, the
/// constraint forces and whatever follows from them (inverse dynamics at the forward
/// acceleration, the energy and the state after a step, the sensors (sensordata holds the
/// acceleration stage's) and the forces inside the tree).
bool decided_by_solver(const std::string& quantity);

/// The bound, in units of 1e-12, on the quantities decided_by_solver in a model with
/// contacts: MuJoCo's Newton iterations, even run to convergence (tolerance 0, 1000 iterations),
/// stop ~1e-13 to 1e-12 from the unique answer lever's exact solve finds, so they are held to
/// 1e-10 relative and reported against 1e-12. Without contacts MuJoCo converges exactly.
inline constexpr double kContactSolverBound = 100.0;

/// Names element i of a quantity's flattened array; called only when it is worth printing.
using Labeler = std::function<std::string(int)>;

class Report {
 public:
  /// Compare n values of `quantity` at `state`.
  void compare(const std::string& quantity, int state, const double* lever, const double* mujoco,
               int n, const Labeler& label);
  /// Compare one value.
  void compare(const std::string& quantity, int state, double lever, double mujoco,
               const std::string& element = "");
  /// The bound (in units of 1e-12) of the quantities decided_by_solver, from now on and for
  /// those already listed: kContactSolverBound for a model with contacts, else 1.
  void set_solver_bound(double bound);
  /// List a quantity before anything is compared, so tables keep a fixed order.
  void declare(const std::string& quantity) { entry(quantity); }
  /// Fold another report in (its extremes keep their own state numbers).
  void merge(const Report& other);
  /// A state left out because lever refused it (lever::StateError: more contacts than the
  /// model's nconmax, more rows than its njmax, where MuJoCo drops the rest with a warning).
  void skip(int state, const std::string& why);
  /// How many states were left out, and the first of them with its reason ("" if none).
  int skipped() const { return skipped_; }
  const std::string& first_skipped() const { return first_skipped_; }

  const std::vector<Extreme>& quantities() const { return extremes_; }
  const Extreme* find(const std::string& quantity) const;
  bool pass() const;
  /// The first comparisons beyond the bound, each described in full (state, quantity, index,
  /// both values, ratio).
  const std::vector<std::string>& failures() const { return failures_; }

 private:
  Extreme& entry(const std::string& quantity);
  void record(Extreme& e, int state, int index, double lever, double mujoco, double magnitude,
              const Labeler& label);

  std::vector<Extreme> extremes_;
  double solver_bound_ = 1.0;
  std::vector<std::string> failures_;
  int skipped_ = 0;
  std::string first_skipped_;
};

}  // namespace lever::diff
