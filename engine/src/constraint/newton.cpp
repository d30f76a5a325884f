// MuJoCo 2.2.2's primal problem solved by Newton's method with an exact line search (read in
// engine_solver.c's mj_solNewton and engine_core_constraint.c's mj_constraintUpdate; written here
// in lever's own words). Used for models with elliptic friction cones, equality constraints or
// friction loss.
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
// minimizer is unique; Newton's method with the Hessian M + J^T (d^2 s / d jar^2) J and a line
// search that finds the minimum along each step to rounding reaches it, and lever iterates until
// the cost stops decreasing (no tolerance).
#include <lever/constraint.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

#include "constraint/constraint_room.hpp"

namespace lever {

namespace {

using Local = Eigen::Matrix<double, 6, 6>;

// Most Newton steps and line-search evaluations: far above what convergence takes (a few steps,
// a few dozen evaluations), a guard against a loop that would never end.
constexpr int kMaxNewtonSteps = 200;
constexpr int kMaxLineSteps = 200;

// The rows of one block: an elliptic cone's dim rows, else one row.
int block_size(const Data& data, int r) {
  if (data.efc_type[r] != ConstraintType::kContactElliptic) return 1;
  return data.contact[data.efc_id[r]].dim;
}

// Cost, gradient (d s / d jar, into grad[0..size)) and, with hess != nullptr, Hessian of the
// block starting at row r, at the rows' values x[0..size). Returns the block's state.
ConstraintState block_cost(const Data& data, int r, int size, const double* x, double& cost,
                           double* grad, Local* hess) {
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
  double T2 = 0.0;
  for (int j = 0; j < size; ++j) {
    U[j] = scale[j] * x[j];
    if (j > 0) T2 += U[j] * U[j];
  }
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
  for (int j = 0; j < size; ++j) grad[j] = scale[j] * Dm * gap * dgap[j];
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

// Gauss term and constraint cost at qacc (work.newton_Merr, newton_x and newton_grad_x hold
// M (qacc - qacc_smooth), the rows' jar and their gradient there afterwards).
double total_cost(Data& data, const Eigen::Ref<const Eigen::VectorXd>& qacc) {
  auto& w = data.work;
  w.newton_err = qacc - data.qacc_smooth;
  w.newton_Merr.noalias() = data.M * w.newton_err;
  const double gauss = 0.5 * w.newton_err.dot(w.newton_Merr);
  rows_jar(data, qacc.data(), w.newton_x.data());
  return gauss + constraint_cost(data, w.newton_x, w.newton_grad_x, false);
}

// Slope and curvature of the cost along qacc + alpha dir: the Gauss term's (gauss1 + 2 alpha
// gauss2, 2 gauss2) plus each block's, from jar + alpha J dir.
void line_derivatives(Data& data, double gauss1, double gauss2, double alpha, double& slope,
                      double& curvature) {
  auto& w = data.work;
  slope = gauss1 + 2 * alpha * gauss2;
  curvature = 2 * gauss2;
  for (int r = 0; r < data.nefc;) {
    const int size = block_size(data, r);
    double x[6], g[6], cost;
    Local h;
    for (int j = 0; j < size; ++j) x[j] = w.newton_jar[r + j] + alpha * w.newton_jv[r + j];
    if (block_cost(data, r, size, x, cost, g, &h) != ConstraintState::kSatisfied) {
      for (int i = 0; i < size; ++i) {
        slope += g[i] * w.newton_jv[r + i];
        for (int j = 0; j < size; ++j)
          curvature += w.newton_jv[r + i] * h(i, j) * w.newton_jv[r + j];
      }
    }
    r += size;
  }
}

// The step length that minimizes the cost along dir: the slope is continuous and increasing, so
// Newton's method on it, kept inside a bracket [lo, hi] around its zero (falling back to the
// bracket's midpoint), converges; it stops when the slope is zero or the next point would not
// move (the bracket cannot shrink in floating point).
double line_search(Data& data, double gauss1, double gauss2) {
  double lo = 0.0, hi = std::numeric_limits<double>::infinity(), alpha = 1.0;
  double best = 0.0, best_slope = std::numeric_limits<double>::infinity();
  for (int k = 0; k < kMaxLineSteps; ++k) {
    double slope, curvature;
    line_derivatives(data, gauss1, gauss2, alpha, slope, curvature);
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

// efc_force, efc_state and qfrc_constraint at the rows' values x (forces -d s / d jar).
void record_forces(Data& data, const Eigen::Ref<const Eigen::VectorXd>& x) {
  auto& w = data.work;
  constraint_cost(data, x, w.newton_grad_x, true);
  data.qfrc_constraint.setZero();
  for (int r = 0; r < data.nefc; ++r) {
    data.efc_force[r] = -w.newton_grad_x[r];
    if (data.efc_force[r] == 0.0) data.efc_force[r] = 0.0;  // no -0 from a zero gradient
  }
  add_rows_transpose(data, data.efc_force.data(), data.qfrc_constraint.data());
}

}  // namespace

void constraint_forces_at(Data& data, const Eigen::Ref<const Eigen::VectorXd>& qacc) {
  auto& w = data.work;
  rows_jar(data, qacc.data(), w.newton_x.data());
  record_forces(data, w.newton_x);
}

int solve_constraint_newton([[maybe_unused]] const Model& model, Data& data) {
  auto& w = data.work;
  const int n = data.nefc;
  rows_jar(data, data.qacc_smooth.data(), data.efc_b.data());
  // start from the unconstrained acceleration (lever's forward is a function of the state alone;
  // a warm start would change only where the iterations stop, at rounding)
  data.qacc = data.qacc_smooth;
  total_cost(data, data.qacc);
  w.newton_jar.head(n) = w.newton_x.head(n);

  // The iterations stop at the minimum, to rounding: a cost of 1e5 cannot show a decrease of
  // 1e-20, so the test is on the steps. Newton's steps shrink quadratically near the minimum;
  // they stop when a step moves qacc by a few units in the last place, when a step no longer
  // shrinks once it is tiny (rounding noise, not convergence), or when a step changed no row's
  // state and no cone is in its middle zone (the cost was one quadratic there: the Newton step
  // reached its minimum, to the rounding of the solve with H). One more step is then taken, as
  // iterative refinement: stiff rows (an equality constraint's D is large) make H ill-conditioned,
  // and the second solve removes most of the first one's rounding error, as MuJoCo's further
  // iterations do.
  constexpr double kEps = std::numeric_limits<double>::epsilon();
  double previous_step = std::numeric_limits<double>::infinity();
  int step = 0;
  bool refined = false;
  for (; step < kMaxNewtonSteps; ++step) {
    // gradient M (a - a_smooth) + J^T ds/djar and Hessian M + J^T (d^2 s / d jar^2) J: per
    // row, ds/djar (w.lcp_w) and a one-sided row's d^2 s / d jar^2 (w.lcp_f); per elliptic
    // cone, its block's d^2 s / d jar^2 (w.contact_weight), in its frame's coordinates (its
    // rows are its frame's rows)
    bool changed = step == 0, cone = false;
    for (int r = 0; r < n;) {
      const int size = block_size(data, r);
      double g[6], c;
      Local h;
      const ConstraintState state = block_cost(data, r, size, w.newton_jar.data() + r, c, g, &h);
      changed = changed || state != data.efc_state[r];
      cone = cone || state == ConstraintState::kCone;
      std::fill(data.efc_state.begin() + r, data.efc_state.begin() + r + size, state);
      const bool pushing = state != ConstraintState::kSatisfied;
      for (int i = 0; i < size; ++i) w.lcp_w[r + i] = pushing ? g[i] : 0.0;
      std::fill(w.lcp_f.data() + r, w.lcp_f.data() + r + size, 0.0);
      if (data.efc_type[r] != ConstraintType::kContactElliptic) {  // a row of its own
        w.lcp_f[r] = pushing ? h(0, 0) : 0.0;
      } else {
        double* W = w.contact_weight.data() + 36 * static_cast<std::ptrdiff_t>(data.efc_id[r]);
        for (int i = 0; i < size; ++i) {
          for (int j = 0; j < size; ++j) W[i * size + j] = pushing ? h(i, j) : 0.0;
        }
      }
      r += size;
    }
    if (!changed && !cone) {
      if (refined) break;
      refined = true;
    }
    w.newton_grad = w.newton_Merr;
    add_rows_transpose(data, w.lcp_w.data(), w.newton_grad.data());
    if (w.newton_grad.lpNorm<Eigen::Infinity>() == 0.0) break;
    w.newton_dir = -w.newton_grad;
    w.newton_H = data.M;
    add_rows_hessian(data, w.lcp_f.data(), w.newton_H);  // the one-sided rows
    for (int i = 0; i < data.ncon; ++i) {
      const int first = data.contact[i].efc_address;
      if (first < 0 || data.efc_type[first] != ConstraintType::kContactElliptic) continue;
      add_frame_hessian(data, i, w.contact_weight.data() + 36 * static_cast<std::ptrdiff_t>(i),
                        w.newton_H);
    }
    solve_with_hessian(data, w.newton_H, w.newton_dir);
    if (!(w.newton_dir.dot(w.newton_grad) < 0)) break;  // no descent left, at rounding

    // the exact minimum along the Newton direction
    w.newton_Mdir.noalias() = data.M * w.newton_dir;
    const double gauss1 = w.newton_dir.dot(w.newton_Merr);
    const double gauss2 = 0.5 * w.newton_dir.dot(w.newton_Mdir);
    rows_times(data, w.newton_dir.data(), w.newton_jv.data());
    const double alpha = line_search(data, gauss1, gauss2);
    if (!(alpha > 0.0)) break;
    data.qacc += alpha * w.newton_dir;
    total_cost(data, data.qacc);
    w.newton_jar.head(n) = w.newton_x.head(n);

    const double moved = alpha * w.newton_dir.lpNorm<Eigen::Infinity>();
    const double scale = 1.0 + data.qacc.lpNorm<Eigen::Infinity>();
    if (moved <= 4 * kEps * scale) break;
    if (!changed && moved >= 0.5 * previous_step && moved <= 1e-8 * scale) break;
    previous_step = moved;
  }
  record_forces(data, w.newton_jar);
  return step;
}

}  // namespace lever
