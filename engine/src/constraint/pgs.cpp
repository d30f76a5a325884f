// MuJoCo 2.2.2's projected Gauss-Seidel solver (engine_solver.c: mj_solPGS, read there and
// written here in lever's own words), for a model whose opt.solver is PGS.
//
// PGS works on the dual problem. The unknowns are the rows' forces f; the cost is
//   1/2 f^T A f + f^T b,    A = J M^-1 J^T + R (row_space_matrix), b = J qacc_smooth - aref,
// over each block's admissible set: an equality row's force is free, a friction-loss row's lies
// in [-frictionloss, frictionloss], a limit's, a frictionless contact's and a pyramid edge's is
// non-negative, and an elliptic cone's dim rows (normal f_0, then the friction forces f_j) lie in
//   sum_j (f_j / friction_j)^2 <= f_0^2,   f_0 >= 0.
// Its minimizer gives the primal problem's qacc (primal.cpp); PGS approaches it sweep by sweep.
//
// The forces start where MuJoCo's warm start puts them: the forces the rows exert at the last
// solve's acceleration, qacc_warmstart (the primal forces there, constraint_forces_at), kept when
// their dual cost f^T b + 1/2 f^T A f is not positive, that is no worse than zero forces, else
// zero; zero too with <flag warmstart="disable">.
// Each sweep visits the blocks in row order (a row of its own; an elliptic cone's dim rows) and
// lowers the cost over the block with the other forces held, from the block's residual
// res = b + A f (the cost's gradient there):
//   a row:    f_r -= res_r / A_rr, then clamped to its set;
//   a cone:   first the normal, or the whole force along its own ray:
//               f_0 < mjMINVAL:  a row's step on the normal, clamped at 0; no friction force;
//               otherwise:       f += x f with x the minimum along the ray, kept to f_0 >= 0;
//             then the friction forces with the normal held, the small QCQP
//               min 1/2 y^T A_tt y + y^T c   s.t.  sum_j (y_j / friction_j)^2 <= f_0^2,
//             c the friction rows' residual less their own old forces' part plus the normal's
//             change's (friction_qcqp below), y put on the ellipse when the bound is active.
// A block whose change would raise the cost by more than 1e-10 gets its old forces back (the
// exact row step never does; the cone's steps are approximate). A sweep's improvement is the
// cost's decrease over the sweep divided by meaninertia max(1, nv) (cost_scale); the sweeps stop
// when it falls below opt.tolerance, or after opt.iterations. Their number is data.solver_iter.
//
// efc_state holds the dual states after the last sweep (MuJoCo's dualState): an equality row and
// a friction-loss row inside its box are quadratic (kActive), a friction-loss row at its bound
// is linear on the primal's opposite side (f <= -frictionloss: kLinearPos, f >= frictionloss:
// kLinearNeg), a one-sided row pushes (kActive) when its force is positive, and a cone is
// satisfied when its force lies strictly inside (mu N >= T, N = f_0 / mu, T the norm of
// f_j / friction_j), quadratic when N + mu T <= 0, else on its surface (kCone).
// Then qfrc_constraint = J^T f and qacc = qacc_smooth + M^-1 qfrc_constraint.
#include <algorithm>
#include <cmath>

#include "basics/basics.hpp"
#include "constraint/constraint_room.hpp"
#include "smooth/smooth.hpp"

namespace lever {

namespace {

using detail::kMinVal;  // MuJoCo's mjMINVAL

constexpr double kRaiseKept = 1e-10;  // a block's cost may rise this much before it is undone
// The friction QCQP: Newton's method on the multiplier, at most this many steps, stopped when
// the bound is met within kQcqpTolerance or the step is smaller; a shifted matrix whose
// determinant (2 and 3 forces) or Cholesky pivot (more) falls below kQcqpTolerance counts as
// singular (no friction force)
constexpr int kQcqpSteps = 20;
constexpr double kQcqpTolerance = 1e-10;

// a . b summed as MuJoCo sums a dot product (dot_as_mujoco over all n). Every product of the
// solver is summed so (and the small formulas below are MuJoCo's), so that on the same A and b
// the sweeps give MuJoCo's forces to the bit: a force on a bound (a cone's surface) has its state
// decided by its last bits.
double dot(const double* a, const double* b, int n) { return dot_as_mujoco(a, b, 0, n, n); }

// x = (S + la I)^-1 y for the small symmetric S of the friction QCQP (n x n, row-major): by the
// adjugate for 2 and 3 forces, by Cholesky for more. factor() is false when S + la I is
// (nearly) singular.
class ShiftedSolve {
 public:
  ShiftedSolve(const double* S, int n) : S_(S), n_(n) {}

  bool factor(double la) {
    if (n_ == 2) {
      const double a = S_[0] + la, d = S_[3] + la, b = S_[1];
      const double det = a * d - b * b;
      if (det < kQcqpTolerance) return false;
      const double inv = 1 / det;
      P_[0] = d * inv;
      P_[3] = a * inv;
      P_[1] = P_[2] = -b * inv;
      return true;
    }
    if (n_ == 3) {
      const double a = S_[0] + la, d = S_[4] + la, f = S_[8] + la;
      const double b = S_[1], c = S_[2], e = S_[5];
      // the adjugate's entries (cofactors), then the determinant along the first row
      double adj[6] = {d * f - e * e, a * f - c * c, a * d - b * b,
                       c * e - b * f, b * e - c * d, b * c - e * a};
      const double det = a * adj[0] + b * adj[3] + c * adj[4];
      if (det < kQcqpTolerance) return false;
      const double inv = 1 / det;
      for (double& x : adj) x *= inv;
      P_[0] = adj[0], P_[4] = adj[1], P_[8] = adj[2];
      P_[1] = P_[3] = adj[3];
      P_[2] = P_[6] = adj[4];
      P_[5] = P_[7] = adj[5];
      return true;
    }
    // Cholesky S + la I = L L^T (L row-major in L_), singular when a pivot is below the tolerance
    for (int j = 0; j < n_; ++j) {
      double pivot = S_[j * n_ + j] + la - dot(L_ + j * n_, L_ + j * n_, j);
      if (pivot < kQcqpTolerance) return false;
      L_[j * n_ + j] = std::sqrt(pivot);
      const double inv = 1 / L_[j * n_ + j];
      for (int i = j + 1; i < n_; ++i) {
        L_[i * n_ + j] = (S_[i * n_ + j] - dot(L_ + i * n_, L_ + j * n_, j)) * inv;
      }
    }
    return true;
  }

  // z^T (S + la I)^-1 z (work: n numbers): for 2 and 3 forces expanded over the inverse's
  // entries, each off-diagonal pair once, doubled
  double quadratic_form(const double* z, double* work) const {
    if (n_ == 2) {
      return P_[0] * z[0] * z[0] + 2.0 * P_[1] * z[0] * z[1] + P_[3] * z[1] * z[1];
    }
    if (n_ == 3) {
      const double diagonal = P_[0] * z[0] * z[0] + P_[4] * z[1] * z[1] + P_[8] * z[2] * z[2];
      const double off = P_[1] * z[0] * z[1] + P_[2] * z[0] * z[2] + P_[5] * z[1] * z[2];
      return diagonal + 2.0 * off;
    }
    solve(z, work);
    return dot(z, work, n_);
  }

  void solve(const double* y, double* x) const {
    if (n_ <= 3) {
      for (int i = 0; i < n_; ++i) x[i] = dot(P_ + i * n_, y, n_);
      return;
    }
    for (int i = 0; i < n_; ++i) x[i] = (y[i] - dot(L_ + i * n_, x, i)) / L_[i * n_ + i];
    for (int i = n_ - 1; i >= 0; --i) {
      for (int j = i + 1; j < n_; ++j) x[i] -= L_[j * n_ + i] * x[j];
      x[i] /= L_[i * n_ + i];
    }
  }

 private:
  const double* S_;
  int n_;
  double P_[9] = {};
  double L_[25] = {};
};

// The friction forces y (n of them, n <= 5) minimizing 1/2 y^T S y + y^T c subject to
// sum_j (y_j / mu_j)^2 <= r^2, S symmetric (n x n, row-major). In z = y / mu the bound is a
// ball, |z| <= r, and the minimizer solves (S' + la I) z = -c' (S' = diag(mu) S diag(mu),
// c' = mu c) with the multiplier la >= 0, zero when the free minimum lies inside. Newton's method
// on |z(la)|^2 - r^2 from la = 0 finds it. Returns whether the bound is active (la > 0).
bool friction_qcqp(const double* S, const double* c, const double* mu, double r, int n,
                   double* y) {
  double Ss[25], cs[5], z[5] = {}, Pz[5];
  for (int i = 0; i < n; ++i) {
    cs[i] = c[i] * mu[i];
    for (int j = 0; j < n; ++j) Ss[i * n + j] = S[i * n + j] * mu[i] * mu[j];
  }
  ShiftedSolve shifted(Ss, n);
  double la = 0.0;
  for (int step = 0; step < kQcqpSteps; ++step) {
    if (!shifted.factor(la)) {
      std::fill(y, y + n, 0.0);
      return false;
    }
    shifted.solve(cs, z);
    for (int i = 0; i < n; ++i) z[i] = -z[i];
    const double excess = dot(z, z, n) - r * r;  // |z|^2 - r^2, decreasing in la
    if (excess < kQcqpTolerance) break;          // inside the ball (la = 0) or on it
    const double slope = -2.0 * shifted.quadratic_form(z, Pz);  // d excess / d la
    const double delta = -excess / slope;
    if (delta < kQcqpTolerance) break;
    la += delta;
  }
  for (int i = 0; i < n; ++i) y[i] = z[i] * mu[i];
  return la != 0.0;
}

// The dual states of the forces (the header's list).
void set_dual_states(Data& data) {
  const double* f = data.efc_force.data();
  for (int r = 0; r < data.nefc;) {
    const ConstraintType type = data.efc_type[r];
    ConstraintState state = ConstraintState::kActive;
    int size = 1;
    if (friction_loss_row(type)) {
      const double bound = data.efc_frictionloss[r];
      if (f[r] <= -bound) state = ConstraintState::kLinearPos;
      if (f[r] >= bound) state = ConstraintState::kLinearNeg;
    } else if (type == ConstraintType::kContactElliptic) {
      const Contact& con = data.contact[data.efc_id[r]];
      size = con.dim;
      const double N = f[r] / con.mu;
      double t[5];
      for (int j = 1; j < size; ++j) t[j - 1] = f[r + j] / con.friction[j - 1];
      const double T = std::sqrt(dot(t, t, size - 1));
      state = con.mu * N >= T          ? ConstraintState::kSatisfied
              : N + con.mu * T <= 0.0 ? ConstraintState::kActive
                                      : ConstraintState::kCone;
    } else if (type != ConstraintType::kEquality && f[r] <= 0.0) {
      state = ConstraintState::kSatisfied;
    }
    std::fill(data.efc_state.begin() + r, data.efc_state.begin() + r + size, state);
    r += size;
  }
}

// An elliptic cone's step (the header's): the forces f (dim of them) from their values
// `before`, its block Ab of A (dim x dim, row-major), its residual res and A's inverse diagonal
// entry of its normal row.
void cone_step(const Contact& con, const double* Ab, const double* res, const double* before,
               double inv_normal, double* f) {
  const int dim = con.dim, nt = dim - 1;
  if (f[0] < kMinVal) {
    // the normal alone, no friction
    f[0] -= res[0] * inv_normal;
    if (f[0] < 0) f[0] = 0.0;
    std::fill(f + 1, f + dim, 0.0);
  } else {
    // along the ray through the force: f + x f, x minimizing the cost there
    double ray[6], Aray[6];
    std::copy(f, f + dim, ray);
    for (int i = 0; i < dim; ++i) Aray[i] = dot(Ab + i * dim, ray, dim);
    const double curvature = dot(ray, Aray, dim);
    if (curvature >= kMinVal) {
      double x = -dot(ray, res, dim) / curvature;
      if (f[0] + x * ray[0] < 0) x = -ray[0] / f[0];  // no further than a zero normal
      for (int i = 0; i < dim; ++i) f[i] += x * ray[i];
    }
  }

  // the friction forces with the normal held: their rows' block of A and the residual they see,
  // without their own old forces and with the normal's change
  double S[25], c[5];
  for (int j = 0; j < nt; ++j) {
    for (int k = 0; k < nt; ++k) S[j * nt + k] = Ab[(j + 1) * dim + 1 + k];
    c[j] = res[1 + j] - dot(S + j * nt, before + 1, nt) + Ab[(j + 1) * dim] * (f[0] - before[0]);
  }
  if (f[0] < kMinVal) {
    std::fill(f + 1, f + dim, 0.0);
    return;
  }
  double y[5];
  if (friction_qcqp(S, c, con.friction.data(), f[0], nt, y)) {
    // on the bound: onto the ellipse exactly (the multiplier's iterations stop near it)
    double s = 0.0;
    for (int j = 0; j < nt; ++j) s += y[j] * y[j] / (con.friction[j] * con.friction[j]);
    s = std::sqrt(f[0] * f[0] / std::max(kMinVal, s));
    for (int j = 0; j < nt; ++j) y[j] *= s;
  }
  std::copy(y, y + nt, f + 1);
}

// The cost's change from the block's forces `before` to f: 1/2 d^T Ab d + d^T res, d = f -
// before. A rise above kRaiseKept restores the old forces and counts as no change.
double block_change(const double* Ab, const double* res, const double* before, int dim,
                    double* f) {
  double change;
  if (dim == 1) {
    const double d = f[0] - before[0];
    change = 0.5 * d * d * Ab[0] + d * res[0];
  } else {
    double d[6], Ad[6];
    for (int i = 0; i < dim; ++i) d[i] = f[i] - before[i];
    for (int i = 0; i < dim; ++i) Ad[i] = dot(Ab + i * dim, d, dim);
    change = 0.5 * dot(d, Ad, dim) + dot(d, res, dim);
  }
  if (change > kRaiseKept) {
    std::copy(before, before + dim, f);
    change = 0.0;
  }
  return change;
}

// The forces the sweeps start from (the file's comment), into f = data.efc_force; work.A whole.
void start_forces(const Model& model, Data& data) {
  const int n = data.nefc;
  const auto& A = data.work.A;
  double* f = data.efc_force.data();
  if (model.opt.disabled(kDisableWarmstart)) {
    std::fill(f, f + n, 0.0);
    return;
  }
  constraint_forces_at(data, data.qacc_warmstart);
  // the dual cost, A f row by row (A is symmetric: its column r is its row r), in the
  // workspace constraint_forces_at used for the rows' jar
  double* Af = data.work.newton_x.data();
  const bool sparse = sparse_jacobian(model.opt, model.nv);
  for (int r = 0; r < n; ++r) Af[r] = row_dot_as_mujoco(sparse, A.col(r).data(), f, 0, n, n);
  const double cost = dot(f, data.efc_b.data(), n) + 0.5 * dot(f, Af, n);
  if (cost > 0) std::fill(f, f + n, 0.0);
}

}  // namespace

int solve_constraint_pgs(const Model& model, Data& data) {
  auto& w = data.work;
  const int n = data.nefc;
  // b = J qacc_smooth - aref, each row's product summed as MuJoCo sums it
  const int nv = model.nv;
  rows_jar(data, data.qacc_smooth.data(), data.efc_b.data());

  // A, whole (a row of A is then a column, contiguous), and the inverse of its diagonal
  row_space_matrix(model, data);
  auto& A = w.A;
  for (int c = 0; c < n; ++c) {
    for (int r = c + 1; r < n; ++r) A(c, r) = A(r, c);
  }
  double* inv_diag = w.lcp_w.data();
  for (int r = 0; r < n; ++r) inv_diag[r] = 1 / A(r, r);

  start_forces(model, data);
  double* f = data.efc_force.data();
  const double* b = data.efc_b.data();
  set_dual_states(data);

  const double scale = cost_scale(model);
  const bool sparse = sparse_jacobian(model.opt, nv);  // how MuJoCo sums a row of A times f
  int sweeps = 0;
  while (sweeps < model.opt.iterations) {
    double improvement = 0.0;
    for (int r = 0; r < n;) {
      const int size = block_size(data, r);
      double res[6], before[6], Ab[36];
      for (int j = 0; j < size; ++j) {
        res[j] = b[r + j] + row_dot_as_mujoco(sparse, A.col(r + j).data(), f, 0, n, n);
        before[j] = f[r + j];
      }
      const ConstraintType type = data.efc_type[r];
      if (type != ConstraintType::kContactElliptic) {
        f[r] -= res[0] * inv_diag[r];
        if (friction_loss_row(type)) {
          f[r] = std::clamp(f[r], -data.efc_frictionloss[r], data.efc_frictionloss[r]);
        } else if (type != ConstraintType::kEquality && f[r] < 0) {
          f[r] = 0.0;
        }
        Ab[0] = 1 / inv_diag[r];
      } else {
        for (int i = 0; i < size; ++i) {
          for (int j = 0; j < size; ++j) Ab[i * size + j] = A(r + i, r + j);
        }
        cone_step(data.contact[data.efc_id[r]], Ab, res, before, inv_diag[r], f + r);
      }
      improvement -= block_change(Ab, res, before, size, f + r);
      r += size;
    }
    set_dual_states(data);
    ++sweeps;
    if (improvement / scale < model.opt.tolerance) break;
  }

  // to joint space: qfrc_constraint = J^T f (row by row, as MuJoCo sums it with dense efc_J),
  // qacc = qacc_smooth + M^-1 qfrc_constraint
  double* qfrc = data.qfrc_constraint.data();
  std::fill(qfrc, qfrc + nv, 0.0);
  for (int r = 0; r < n; ++r) {
    const double* J = data.efc_J.row(r).data();
    for (int j = 0; j < nv; ++j) qfrc[j] += J[j] * f[r];
  }
  w.vec1 = data.qfrc_constraint;
  unchecked::solve_mass(model, data, w.vec1.data());
  data.qacc = data.qacc_smooth + w.vec1;
  return sweeps;
}

}  // namespace lever
