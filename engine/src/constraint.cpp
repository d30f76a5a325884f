// MuJoCo 2.2.2's soft joint limits (engine_core_constraint.c), solved exactly.
//
// A row's target is the reference acceleration a_ref = -B v - K imp (pos - margin). The solve
// finds the row forces f that MuJoCo's Newton solver converges to: with A = J M^-1 J^T and R the
// regularizer, f and w = (A + R) f + (J qacc_smooth - a_ref) satisfy f >= 0, w >= 0, f.w = 0
// (a linear complementarity problem with a symmetric positive definite matrix, so its solution is
// unique). It is found by Murty's least-index principal pivoting, which is finite for such
// matrices; the usual case, one row, takes one step.
#include <lever/constraint.hpp>
#include <lever/dynamics.hpp>

#include <algorithm>
#include <cmath>

#include "internal.hpp"

namespace lever {

namespace {

constexpr double kMinVal = 1e-15;   // MuJoCo's mjMINVAL
constexpr double kMinImp = 0.0001;  // mjMINIMP
constexpr double kMaxImp = 0.9999;  // mjMAXIMP

}  // namespace

// solref and solimp of a joint's limit, sanitized as MuJoCo's getsolparam does.
void limit_parameters(const Model& model, int jnt, std::array<double, 2>& solref,
                      std::array<double, 5>& solimp) {
  solref = model.jnt_solref[jnt];
  solimp = model.jnt_solimp[jnt];
  // the standard (positive) and direct (negative) forms cannot be mixed: use the default
  if ((solref[0] > 0) != (solref[1] > 0)) solref = {0.02, 1.0};
  // refsafe: a time constant shorter than two steps would make the Euler step unstable
  if (solref[0] > 0) solref[0] = std::max(solref[0], 2 * model.opt.timestep);
  solimp[0] = std::min(kMaxImp, std::max(kMinImp, solimp[0]));
  solimp[1] = std::min(kMaxImp, std::max(kMinImp, solimp[1]));
  solimp[2] = std::max(0.0, solimp[2]);
  solimp[3] = std::min(kMaxImp, std::max(kMinImp, solimp[3]));
  solimp[4] = std::max(1.0, solimp[4]);
}

// Impedance at a violation: solimp's sigmoid from d0 (at the margin) to dmax (width past it).
// With slope != nullptr, also d imp / d pos (zero on the flat parts; one-sided at their ends).
double impedance(const std::array<double, 5>& solimp, double pos, double margin, double* slope) {
  const double d0 = solimp[0], dmax = solimp[1], width = solimp[2];
  const double mid = solimp[3], power = solimp[4];
  if (slope != nullptr) *slope = 0.0;
  if (d0 == dmax || width <= kMinVal) return 0.5 * (d0 + dmax);
  const double x = std::abs((pos - margin) / width);
  if (x >= 1) return dmax;
  if (x <= 0) return d0;
  double y, dy_dx;
  if (power == 1) {
    y = x;
    dy_dx = 1;
  } else if (power == 2) {  // the default: spare two calls to pow
    y = x <= mid ? x * x / mid : 1 - (1 - x) * (1 - x) / (1 - mid);
    dy_dx = x <= mid ? 2 * x / mid : 2 * (1 - x) / (1 - mid);
  } else if (x <= mid) {
    y = std::pow(x, power) / std::pow(mid, power - 1);
    dy_dx = power * std::pow(x, power - 1) / std::pow(mid, power - 1);
  } else {
    y = 1 - std::pow(1 - x, power) / std::pow(1 - mid, power - 1);
    dy_dx = power * std::pow(1 - x, power - 1) / std::pow(1 - mid, power - 1);
  }
  if (slope != nullptr) {
    const double dx_dpos = (pos - margin < 0 ? -1.0 : 1.0) / width;
    *slope = (dmax - d0) * dy_dx * dx_dpos;
  }
  return d0 + y * (dmax - d0);
}

namespace {

// Cholesky factor (lower, in place) of the rows/columns of A listed in idx[0..n); false if not
// positive definite. L is written into L(0..n, 0..n).
bool cholesky_subset(const Eigen::MatrixXd& A, const std::vector<int>& idx, int n,
                     Eigen::MatrixXd& L) {
  for (int c = 0; c < n; ++c) {
    for (int r = c; r < n; ++r) {
      double s = A(idx[r], idx[c]);
      for (int k = 0; k < c; ++k) s -= L(r, k) * L(c, k);
      if (r == c) {
        if (!(s > 0)) return false;
        L(c, c) = std::sqrt(s);
      } else {
        L(r, c) = s / L(c, c);
      }
    }
  }
  return true;
}

}  // namespace

void make_constraint(const Model& model, Data& data) {
  check_entry(model, data, "lever::make_constraint");
  int n = 0;
  for (int j = 0; j < model.njnt; ++j) {
    if (!model.jnt_limited[j]) continue;
    const double q = data.qpos[model.jnt_qposadr[j]];
    const double margin = model.jnt_margin[j];
    // lower stop first, then upper; dist < 0 means past the stop
    const double dist[2] = {q - model.jnt_range[j][0], model.jnt_range[j][1] - q};
    for (int side = 0; side < 2; ++side) {
      if (!(dist[side] < margin)) continue;  // strict: resting exactly at the stop makes no row
      data.efc_id[n] = j;
      data.efc_dof[n] = model.jnt_dofadr[j];
      data.efc_sign[n] = side == 0 ? 1.0 : -1.0;
      data.efc_pos[n] = dist[side];
      data.efc_margin[n] = margin;
      ++n;
    }
  }
  data.nefc = n;

  // impedance and regularizer (MuJoCo's mj_diagApprox and mj_makeImpedance)
  for (int r = 0; r < n; ++r) {
    std::array<double, 2> solref;
    std::array<double, 5> solimp;
    limit_parameters(model, data.efc_id[r], solref, solimp);
    const double imp = impedance(solimp, data.efc_pos[r], data.efc_margin[r], nullptr);
    const double dmax = solimp[1];
    // R is frozen at qpos0 through dof_invweight0, not the current inverse inertia
    const double invweight = model.dof_invweight0[data.efc_dof[r]];
    data.efc_imp[r] = imp;
    data.efc_R[r] = std::max(kMinVal, (1 - imp) * invweight / imp);
    data.efc_D[r] = 1 / data.efc_R[r];
    data.efc_diagApprox[r] = data.efc_R[r] * imp / (1 - imp);
    // K and B use dmax, not the current impedance
    if (solref[0] > 0) {
      data.efc_K[r] =
          1 / std::max(kMinVal, dmax * dmax * solref[0] * solref[0] * solref[1] * solref[1]);
    } else {
      data.efc_K[r] = -solref[0] / std::max(kMinVal, dmax * dmax);
    }
    if (solref[1] > 0) {
      data.efc_B[r] = 2 / std::max(kMinVal, dmax * solref[0]);
    } else {
      data.efc_B[r] = -solref[1] / std::max(kMinVal, dmax);
    }
  }
}

void reference_constraint(const Model& model, Data& data) {
  check_entry(model, data, "lever::reference_constraint");
  for (int r = 0; r < data.nefc; ++r) {
    data.efc_vel[r] = data.efc_sign[r] * data.qvel[data.efc_dof[r]];
    data.efc_aref[r] = -data.efc_B[r] * data.efc_vel[r] -
                       data.efc_K[r] * data.efc_imp[r] * (data.efc_pos[r] - data.efc_margin[r]);
  }
}

void solve_constraint(const Model& model, Data& data) {
  check_entry(model, data, "lever::solve_constraint");
  const int n = data.nefc;
  data.qfrc_constraint.setZero();
  data.qacc = data.qacc_smooth;
  if (n == 0) return;

  auto& w = data.work;
  // M^-1 J^T, one column per row (J's row r is sign_r e_dof_r)
  for (int r = 0; r < n; ++r) {
    auto column = w.MinvJ.col(r);
    column.setZero();
    column[data.efc_dof[r]] = data.efc_sign[r];
    solve_mass(model, data, column);
  }
  // A + R, and b = J qacc_smooth - a_ref
  for (int r = 0; r < n; ++r) {
    for (int c = 0; c < n; ++c) w.A(r, c) = data.efc_sign[r] * w.MinvJ(data.efc_dof[r], c);
    w.A(r, r) += data.efc_R[r];
    data.efc_b[r] = data.efc_sign[r] * data.qacc_smooth[data.efc_dof[r]] - data.efc_aref[r];
  }

  // Murty's least-index principal pivoting, starting from the rows that are pushed into the stop
  Eigen::VectorXd& f = w.lcp_f;
  Eigen::VectorXd& residual = w.lcp_w;
  std::vector<int>& active = w.lcp_active;
  std::vector<int>& idx = w.lcp_index;
  for (int r = 0; r < n; ++r) active[r] = data.efc_b[r] < 0;
  const int max_pivots = 64 * n + 64;
  for (int pivot = 0; pivot <= max_pivots; ++pivot) {
    // forces of the active rows: (A + R)_SS f_S = -b_S
    int m = 0;
    for (int r = 0; r < n; ++r) {
      if (active[r]) idx[m++] = r;
    }
    f.head(n).setZero();
    if (m > 0) {
      cholesky_subset(w.A, idx, m, w.L);  // (A + R)_SS is positive definite: R > 0
      for (int k = 0; k < m; ++k) {       // forward substitution
        double s = -data.efc_b[idx[k]];
        for (int c = 0; c < k; ++c) s -= w.L(k, c) * f[idx[c]];
        f[idx[k]] = s / w.L(k, k);
      }
      for (int k = m - 1; k >= 0; --k) {  // back substitution
        double s = f[idx[k]];
        for (int c = k + 1; c < m; ++c) s -= w.L(c, k) * f[idx[c]];
        f[idx[k]] = s / w.L(k, k);
      }
    }
    // the first row that breaks complementarity changes side
    int flip = -1;
    for (int r = 0; r < n && flip < 0; ++r) {
      residual[r] = data.efc_b[r];
      for (int c = 0; c < n; ++c) residual[r] += w.A(r, c) * f[c];
      if ((active[r] && f[r] < 0) || (!active[r] && residual[r] < 0)) flip = r;
    }
    if (flip < 0) break;
    active[flip] = !active[flip];
  }

  // forces, joint forces and accelerations
  for (int r = 0; r < n; ++r) {
    data.efc_force[r] = active[r] ? f[r] : 0.0;
    data.efc_state[r] = active[r] ? ConstraintState::kActive : ConstraintState::kSatisfied;
    data.qfrc_constraint[data.efc_dof[r]] += data.efc_sign[r] * data.efc_force[r];
  }
  for (int r = 0; r < n; ++r) data.qacc += w.MinvJ.col(r) * data.efc_force[r];
}

}  // namespace lever
