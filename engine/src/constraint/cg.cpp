// MuJoCo 2.2.2's conjugate-gradient solver (engine_solver.c: mj_solCG, which is mj_solCGNewton
// without a Hessian, and its line search CGsearch), on the primal problem of primal.cpp; written
// here in lever's own words. Used for a model whose opt.solver is CG with opt.tolerance > 0.
//
// At tolerance 0 lever solves the problem exactly instead (rows.cpp, newton.cpp), as it does for
// Newton: the minimizer is what CG converges to, but MuJoCo's CG at tolerance 0 stops when
// rounding shows a rise of the cost, on stiff contact scenes 1e-8 to 1e-7 (relative, in qacc)
// short of it, at a point set by the last bits of every product (lever's CG run on from there,
// restarted where the cost stalls, stalls too). MuJoCo's CG restarted from its own answer
// reaches the minimizer where it does not stall (tests/diff/solver_cg.cpp).
//
// The cost is minimized over qacc from qacc = qacc_smooth (lever's CG never warm-starts: MuJoCo with
// <flag warmstart="disable">), with the mass matrix as preconditioner:
//   g = M (qacc - qacc_smooth) + J^T ds/djar        the cost's gradient (M qacc - qfrc_smooth -
//                                                   qfrc_constraint)
//   z = M^-1 g,  d = -z                             the first direction: steepest descent in M
// then at most opt.iterations times:
//   alpha = the line search along d (below); alpha = 0 (no decrease found): stop
//   qacc += alpha d, and g, z, the rows' forces and states at the new qacc
//   improvement = (cost_before - cost) / scale, gradient = |g| / scale, with
//     scale = meaninertia max(1, nv) (meaninertia: the mean of M's diagonal at qpos0, MuJoCo's
//     stat.meaninertia);
//   stop when either is below opt.tolerance
//   beta = max(0, g^T (z - z_before) / max(mjMINVAL, g_before^T z_before))      Polak-Ribiere,
//   d = -z + beta d                                 restarted along -z when beta is negative
// The iterations taken are data.solver_iter. The forces and states are those at the last qacc.
//
// The line search finds where the slope of the cost along d, s(alpha), is below
//   gtol = opt.tolerance * 0.01 * |d| * scale
// in magnitude, with at most 50 evaluations of the cost (each gives s and its derivative s'):
//   1. a Newton step from alpha = 0 (kept only if it lowers the cost); done if |s| < gtol there;
//   2. Newton steps onward while the slope keeps its sign (the minimum not yet passed); the
//      point before the last is the bracket's other end;
//   3. with the minimum bracketed by p1 and p2, each round evaluates the midpoint and the Newton
//      steps from both ends; a candidate with |s| < gtol ends the search (the cheapest of them),
//      else each end moves to the candidate nearest the minimum on its side (smaller |s| with
//      the same sign of slope); when neither end moves, rounding has won: the midpoint.
// Out of evaluations, the search returns the end with the lower cost if it lowers the cost, else
// 0.
#include <lever/constraint.hpp>

#include <algorithm>
#include <cmath>

#include "basics/basics.hpp"
#include "constraint/constraint_room.hpp"
#include "smooth/smooth.hpp"

namespace lever {

namespace {

using detail::kMinVal;                    // MuJoCo's mjMINVAL
constexpr int kMaxLineEvaluations = 50;   // CGsearch's LSmaxiter
constexpr double kLineToleranceScale = 0.01;  // CGsearch's LStolscl: the slope's tolerance

// The line search along work.newton_dir from the current qacc (work.newton_jar its rows' jar,
// gauss0 its Gauss term), as MuJoCo's CGsearch: the step length, 0 when none lowers the cost.
class LineSearch {
 public:
  LineSearch(Data& data, double tolerance, double scale) : data_(data) {
    auto& w = data.work;
    const double length = w.newton_dir.norm();
    too_short_ = length < kMinVal;
    gtol_ = tolerance * kLineToleranceScale * length * scale;
  }

  double run(double gauss0) {
    if (too_short_) return 0.0;
    auto& w = data_.work;
    w.newton_Mdir.noalias() = data_.M * w.newton_dir;
    rows_times(data_, w.newton_dir.data(), w.newton_jv.data());
    gauss_ = {gauss0, w.newton_dir.dot(w.newton_Merr), 0.5 * w.newton_dir.dot(w.newton_Mdir)};

    // 1. one Newton step from 0, kept if it does not raise the cost
    LinePoint p0 = at(0.0);
    LinePoint p1 = at(newton_step(p0));
    if (p0.cost < p1.cost) p1 = p0;
    if (std::abs(p1.slope) < gtol_) return p1.alpha;

    // 2. onward while the slope keeps its sign; p2 the point before
    const double sign = p1.slope < 0 ? 1.0 : -1.0;
    LinePoint p2;
    bool bracketed = false;
    while (p1.slope * sign <= -gtol_ && evaluations_ < kMaxLineEvaluations) {
      p2 = p1;
      bracketed = true;
      p1 = at(newton_step(p1));
      if (std::abs(p1.slope) < gtol_) return p1.alpha;
    }
    if (evaluations_ >= kMaxLineEvaluations || !bracketed) return p1.alpha;

    // 3. shrink the bracket [p1, p2]
    LinePoint p1_next = at(newton_step(p1)), p2_next = p1;
    while (evaluations_ < kMaxLineEvaluations) {
      const LinePoint mid = at(0.5 * (p1.alpha + p2.alpha));
      const LinePoint candidates[3] = {p1_next, p2_next, mid};
      int best = -1;
      for (int i = 0; i < 3; ++i) {
        if (std::abs(candidates[i].slope) < gtol_ &&
            (best < 0 || candidates[i].cost < candidates[best].cost)) {
          best = i;
        }
      }
      if (best >= 0) return candidates[best].alpha;
      const bool moved1 = move_end(p1, candidates, p1_next);
      const bool moved2 = move_end(p2, candidates, p2_next);
      if (!moved1 && !moved2) return mid.alpha;  // rounding: the bracket cannot shrink
    }
    if (p1.cost <= p2.cost && p1.cost < p0.cost) return p1.alpha;
    if (p2.cost <= p1.cost && p2.cost < p0.cost) return p2.alpha;
    return 0.0;
  }

 private:
  LinePoint at(double alpha) {
    LinePoint p;
    p.alpha = alpha;
    evaluate_line(data_, gauss_, p);
    if (!(p.curvature > 0)) p.curvature = kMinVal;  // the cost is convex; a guard for rounding
    ++evaluations_;
    return p;
  }

  static double newton_step(const LinePoint& p) { return p.alpha - p.slope / p.curvature; }

  // A bracket end moves to a candidate on its side of the minimum (its slope of the same sign)
  // that is nearer to it (a smaller slope in magnitude); then its Newton step is evaluated.
  bool move_end(LinePoint& end, const LinePoint (&candidates)[3], LinePoint& next) {
    bool moved = false;
    for (const LinePoint& c : candidates) {
      if ((end.slope < 0 && c.slope < 0 && end.slope < c.slope) ||
          (end.slope > 0 && c.slope > 0 && end.slope > c.slope)) {
        end = c;
        moved = true;
      }
    }
    if (moved) next = at(newton_step(end));
    return moved;
  }

  Data& data_;
  LineGauss gauss_{0.0, 0.0, 0.0};
  double gtol_ = 0.0;
  bool too_short_ = false;
  int evaluations_ = 0;
};

// The cost, the rows' forces and states, and the gradient g with z = M^-1 g at data.qacc
// (work.newton_grad, work.cg_Mgrad). Returns the cost.
double update_at_qacc(const Model& model, Data& data) {
  auto& w = data.work;
  const double cost = primal_cost(data, data.qacc);
  w.newton_jar.head(data.nefc) = w.newton_x.head(data.nefc);
  record_primal_forces(data, w.newton_jar);
  w.newton_grad = w.newton_Merr - data.qfrc_constraint;
  w.cg_Mgrad = w.newton_grad;
  unchecked::solve_mass(model, data, w.cg_Mgrad.data());
  return cost;
}

}  // namespace

int solve_constraint_cg(const Model& model, Data& data) {
  auto& w = data.work;
  rows_jar(data, data.qacc_smooth.data(), data.efc_b.data());
  data.qacc = data.qacc_smooth;
  const double scale = cost_scale(model);
  const double tolerance = model.opt.tolerance;

  double cost = update_at_qacc(model, data);
  w.newton_dir = -w.cg_Mgrad;
  int iter = 0;
  while (iter < model.opt.iterations) {
    const double alpha = LineSearch(data, tolerance, scale).run(cost);
    if (alpha == 0.0) break;
    data.qacc += alpha * w.newton_dir;
    w.cg_grad_old = w.newton_grad;
    w.cg_Mgrad_old = w.cg_Mgrad;
    const double cost_before = cost;
    cost = update_at_qacc(model, data);
    ++iter;

    const double improvement = (cost_before - cost) / scale;
    const double gradient = w.newton_grad.norm() / scale;
    if (improvement < tolerance || gradient < tolerance) break;

    // Polak-Ribiere, restarted along -z when negative
    const double beta =
        std::max(0.0, w.newton_grad.dot(w.cg_Mgrad - w.cg_Mgrad_old) /
                          std::max(kMinVal, w.cg_grad_old.dot(w.cg_Mgrad_old)));
    w.newton_dir = beta * w.newton_dir - w.cg_Mgrad;
  }
  return iter;
}

}  // namespace lever
