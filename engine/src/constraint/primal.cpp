// MuJoCo 2.2.2's primal problem, the pieces its Newton and CG solvers share (read in
// engine_solver.c and engine_core_constraint.c's mj_constraintUpdate; written here in lever's own
// words): the cost, its gradient and Hessian per block of rows, the cost along a line and the
// exact line search, the forces at a solution.
//
// The unknown is the acceleration a. The cost is the Gauss term 1/2 (a - a_smooth)^T M (a -
// a_smooth) plus, for each block of rows, a convex function s of jar = J a - a_ref:
//   an equality row: 1/2 D jar^2;
//   a friction-loss row of bound f: 1/2 D jar^2 while |jar| < R f, else f |jar| - 1/2 R f^2
//     (Huber's: its force -D jar inside the box, +-f at its sides, states linear neg / pos);
//   a one-sided row (limit, frictionless contact, pyramid edge): 1/2 D jar^2 when jar < 0, else 0;
//   an elliptic cone of dim rows: with the rows scaled to a circular cone, N = mu jar_0 and
//     t_j = friction_j jar_j (j >= 1), T = |t|,
//       N >= mu T          inside the dual cone: no force, no cost (satisfied);
//       mu N + T <= 0      inside the primal cone: every row quadratic, sum 1/2 D_j jar_j^2;
//       otherwise          the middle zone: 1/2 Dm (N - mu T)^2, Dm = D_0 / (mu^2 (1 + mu^2)),
//                          a force on the cone's surface.
// The force of a row is -d s / d jar. The problem is strictly convex (M > 0, R > 0), so the
// minimizer is unique. Newton's method (newton.cpp) with the Hessian M + J^T (d^2 s / d jar^2) J
// and the exact line search below reaches it to rounding; MuJoCo's conjugate gradients (cg.cpp)
// reach it as their tolerance and iterations allow.
#include <algorithm>
#include <cmath>
#include <limits>

#include "constraint/constraint_room.hpp"

namespace lever {

namespace {

// Most line-search evaluations: far above what convergence takes (a few dozen evaluations), a
// guard against a loop that would never end.
constexpr int kMaxLineSteps = 200;


}  // namespace

double cost_scale(const Model& model) {
  if (model.nv == 0) return 1.0;
  double sum = 0.0;
  for (int i = 0; i < model.nv; ++i) sum += model.dof_M0[i];
  const double meaninertia = sum / model.nv;
  return meaninertia * std::max(1, model.nv);
}

int block_size(const Data& data, int r) {
  if (data.efc_type[r] != ConstraintType::kContactElliptic) return 1;
  return data.contact[data.efc_id[r]].dim;
}

ConstraintState block_cost(const Data& data, int r, int size, const double* x, double& cost,
                           double* grad, BlockHessian* hess) {
  const double* D = data.efc_D.data() + r;
  cost = 0.0;
  std::fill(grad, grad + size, 0.0);
  if (hess != nullptr) hess->topLeftCorner(size, size).setZero();
  const ConstraintType type = data.efc_type[r];
  if (friction_loss_row(type)) {
    // Huber's cost: linear beyond |jar| = R f, where the force reaches the box's side +-f
    const double f = data.efc_frictionloss[r], Rf = data.efc_R[r] * f;
    if (x[0] <= -Rf || x[0] >= Rf) {
      const double side = x[0] >= Rf ? 1.0 : -1.0;
      cost = -0.5 * Rf * f + side * f * x[0];
      grad[0] = side * f;
      return side > 0 ? ConstraintState::kLinearPos : ConstraintState::kLinearNeg;
    }
  }
  if (type != ConstraintType::kContactElliptic) {
    // an equality row pulls both ways; a friction-loss row inside its box is quadratic too
    const bool two_sided =
        type == ConstraintType::kEquality || friction_loss_row(type);
    if (!two_sided && x[0] >= 0) return ConstraintState::kSatisfied;
    cost = 0.5 * D[0] * x[0] * x[0];
    grad[0] = D[0] * x[0];
    if (hess != nullptr) (*hess)(0, 0) = D[0];
    return ConstraintState::kActive;
  }

  // the cone scaled to a circular one: U = diag(mu, friction) x
  const Contact& con = data.contact[data.efc_id[r]];
  const double mu = con.mu;
  double scale[6] = {}, U[6] = {};
  scale[0] = mu;
  for (int j = 1; j < size; ++j) scale[j] = con.friction[j - 1];
  for (int j = 0; j < size; ++j) U[j] = scale[j] * x[j];
  const double T2 = dot_as_mujoco(U + 1, U + 1, 0, size - 1, size - 1);
  const double N = U[0], T = std::sqrt(T2);
  if (N >= mu * T || (T <= 0 && N >= 0)) return ConstraintState::kSatisfied;
  if (mu * N + T <= 0 || (T <= 0 && N < 0)) {
    for (int j = 0; j < size; ++j) {
      cost += 0.5 * D[j] * x[j] * x[j];
      grad[j] = D[j] * x[j];
      if (hess != nullptr) (*hess)(j, j) = D[j];
    }
    return ConstraintState::kActive;
  }
  // middle zone: s = 1/2 Dm gap^2 with gap = N - mu T; d gap / dU = (1, -mu t / T)
  const double Dm = D[0] / (mu * mu * (1 + mu * mu));
  const double gap = N - mu * T;
  cost = 0.5 * Dm * gap * gap;
  double dgap[6];
  dgap[0] = 1.0;
  for (int j = 1; j < size; ++j) dgap[j] = -mu * U[j] / T;
  // the gradient in MuJoCo's order of products (its forces are these negated): the normal's
  // Dm gap mu, each friction row's -(that / T) U_j friction_j
  grad[0] = Dm * gap * mu;
  for (int j = 1; j < size; ++j) grad[j] = -(grad[0] / T * U[j] * scale[j]);
  if (hess != nullptr) {
    // d^2 s / dU^2 = Dm (dgap dgap^T + gap d^2 gap / dU^2), d^2 gap / dt^2 = -mu (I - t t^T/T^2)/T
    for (int i = 0; i < size; ++i) {
      for (int j = 0; j < size; ++j) {
        double h = dgap[i] * dgap[j];
        if (i > 0 && j > 0) h += gap * -mu * ((i == j ? 1.0 : 0.0) - U[i] * U[j] / T2) / T;
        (*hess)(i, j) = scale[i] * Dm * h * scale[j];
      }
    }
  }
  return ConstraintState::kCone;
}

namespace {

// The constraint cost at the rows' values x (nefc), its gradient d s / d jar into grad_x; the
// states into data.efc_state when `record`.
double constraint_cost(Data& data, const Eigen::Ref<const Eigen::VectorXd>& x,
                       Eigen::Ref<Eigen::VectorXd> grad_x, bool record) {
  double total = 0.0;
  for (int r = 0; r < data.nefc;) {
    const int size = block_size(data, r);
    double cost;
    const ConstraintState state =
        block_cost(data, r, size, x.data() + r, cost, grad_x.data() + r, nullptr);
    total += cost;
    if (record) std::fill(data.efc_state.begin() + r, data.efc_state.begin() + r + size, state);
    r += size;
  }
  return total;
}

}  // namespace

double primal_cost(Data& data, const Eigen::Ref<const Eigen::VectorXd>& qacc) {
  auto& w = data.work;
  w.newton_err = qacc - data.qacc_smooth;
  w.newton_Merr.noalias() = data.M * w.newton_err;
  const double gauss = 0.5 * w.newton_err.dot(w.newton_Merr);
  rows_jar(data, qacc.data(), w.newton_x.data());
  return gauss + constraint_cost(data, w.newton_x, w.newton_grad_x, false);
}

void evaluate_line(Data& data, const LineGauss& gauss, LinePoint& p) {
  auto& w = data.work;
  const double alpha = p.alpha;
  p.cost = gauss.cost + alpha * (gauss.slope + alpha * gauss.curvature);
  p.slope = gauss.slope + 2 * alpha * gauss.curvature;
  p.curvature = 2 * gauss.curvature;
  for (int r = 0; r < data.nefc;) {
    const int size = block_size(data, r);
    double x[6], g[6], cost;
    BlockHessian h;
    for (int j = 0; j < size; ++j) x[j] = w.newton_jar[r + j] + alpha * w.newton_jv[r + j];
    if (block_cost(data, r, size, x, cost, g, &h) != ConstraintState::kSatisfied) {
      p.cost += cost;
      for (int i = 0; i < size; ++i) {
        p.slope += g[i] * w.newton_jv[r + i];
        for (int j = 0; j < size; ++j)
          p.curvature += w.newton_jv[r + i] * h(i, j) * w.newton_jv[r + j];
      }
    }
    r += size;
  }
}

// The step length that minimizes the cost along dir: the slope is continuous and increasing, so
// Newton's method on it, kept inside a bracket [lo, hi] around its zero (falling back to the
// bracket's midpoint), converges; it stops when the slope is zero or the next point would not
// move (the bracket cannot shrink in floating point).
double exact_line_search(Data& data, const LineGauss& gauss) {
  double lo = 0.0, hi = std::numeric_limits<double>::infinity(), alpha = 1.0;
  double best = 0.0, best_slope = std::numeric_limits<double>::infinity();
  for (int k = 0; k < kMaxLineSteps; ++k) {
    LinePoint point;
    point.alpha = alpha;
    evaluate_line(data, gauss, point);
    const double slope = point.slope, curvature = point.curvature;
    if (std::abs(slope) < best_slope) {
      best = alpha;
      best_slope = std::abs(slope);
    }
    if (slope == 0) return alpha;
    if (slope < 0) {
      lo = alpha;
    } else {
      hi = alpha;
    }
    double next = alpha - slope / curvature;
    if (!(next > lo && next < hi)) next = std::isfinite(hi) ? 0.5 * (lo + hi) : 2 * alpha;
    if (next == alpha || next <= lo || next >= hi) break;  // the bracket is as small as it gets
    alpha = next;
  }
  return best;
}

void record_primal_forces(Data& data, const Eigen::Ref<const Eigen::VectorXd>& x) {
  auto& w = data.work;
  constraint_cost(data, x, w.newton_grad_x, true);
  data.qfrc_constraint.setZero();
  for (int r = 0; r < data.nefc; ++r) {
    data.efc_force[r] = -w.newton_grad_x[r];
    if (data.efc_force[r] == 0.0) data.efc_force[r] = 0.0;  // no -0 from a zero gradient
  }
  add_rows_transpose(data, data.efc_force.data(), data.qfrc_constraint.data());
}

void constraint_forces_at(Data& data, const Eigen::Ref<const Eigen::VectorXd>& qacc) {
  auto& w = data.work;
  rows_jar(data, qacc.data(), w.newton_x.data());
  record_primal_forces(data, w.newton_x);
}

}  // namespace lever
