// The constraint rows differentiated with their active set S held, when a row other than a joint
// limit's exerts a force (a contact's, a fixed tendon's limit or friction loss, a dof's friction
// loss, a joint or tendon coupling, a connect or weld; joint limits alone take
// step_derivatives.cpp's row-space path). forward() converged to
//   M qacc = f_smooth - bias + J_S^T f_S,   f_S = D_S (aref_S - J_S qacc)   (D = 1 / R)
// which is the pyramid's and frictionless rows' complementarity solution, an elliptic cone's
// while every row of it is in its quadratic zone, and a friction-loss row's inside its box (a
// friction-loss row at the box's side exerts +-frictionloss along a constant Jacobian: nothing
// to differentiate). Differentiating, with G = M^-1 (d f_smooth - d ID)
// (the unconstrained part, one column per input) and H = M + J_S^T D_S J_S:
//   d qacc = G + H^-1 (dJ^T f + J_S^T (y - D_S J_S G)),   y_r = D_r (d aref_r - dR_r f_r - dJ_r qacc)
//   d qfrc_constraint = dJ^T f + J_S^T (y - D_S J_S d qacc)
// computed without G: H G - J_S^T D_S J_S G = M G = d f_smooth - d ID, so
//   d qacc = H^-1 (d f_smooth - d ID + dJ^T f + J_S^T y),
//   d qfrc_constraint = M d qacc - (d f_smooth - d ID).
// A connect's and a weld's rows are differentiated in equality_rows.cpp, on the same lines.
// The terms a contact adds to a limit row's: its Jacobian moves with qpos (dJ qacc, dJ qvel in
// aref's velocity, dJ^T f), and its distance (aref's position term, the impedance in aref and R)
// moves with the contact geometry (contact_geometry.cpp).
//
// A contact row is C_k = frame_k . (j_2(p) - j_1(p)) over the dofs of one body's path only, with
// j_i(p) = u_i + w_i x (p - O) the velocity of the contact point p per unit rate of dof i (w_i, u_i
// = cdof, O its tree's centre of mass), and frame_k . (w_2 - w_1) for a rotational row (spin, roll).
// Moving dof c turns the axis of every dof i it carries (a strict ancestor, or a dof of the same
// ball) rigidly, and moves p by dp (the geometry's answer, not a rigid motion), so
//   d j_i(p) / d q_c = [c carries i] (w_c x j_i(p) - w_i x j_c(p)) + w_i x dp
//   d w_i / d q_c    = [c carries i] w_c x w_i
// and the frame's rows move by d frame (the geometry's answer).
#include <lever/collision.hpp>
#include <lever/error.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "basics/basics.hpp"
#include "constraint/constraint_room.hpp"
#include "derivatives/derivatives_room.hpp"
#include "transition/transition.hpp"

namespace lever::detail {

namespace {

using Vec3 = Eigen::Vector3d;

// solimp clamped to the bounds MuJoCo's getsolparam gives it (the impedance's slope reads it)
std::array<double, 5> bounded_solimp(std::array<double, 5> solimp) {
  bound_solimp(solimp);
  return solimp;
}

// Whether moving dof c turns the axis of dof i: c a strict ancestor of i, or both in one ball (or
// one free joint's rotation), whose three dofs turn one another (docs/derivatives.md).
bool carries(const Model& model, int c, int i) {
  const int j = model.dof_jntid[c];
  if (j == model.dof_jntid[i]) {
    const int r = rotation_block(model, j);
    if (r >= 0 && c >= r && i >= r) return true;
  }
  for (int k = model.dof_parentid[i]; k >= 0; k = model.dof_parentid[k]) {
    if (k == c) return true;
  }
  return false;
}

Vec3 angular(const Motion& S) { return S.head<3>(); }

struct SoftSlopes {
  double aref_per_dist;  // d aref / d dist without the velocity term, over K: -(slope (d - m) + imp)
  double R_per_dist;     // d R / d dist over R
};

// A row's impedance's slope through its distance, and what it does to aref and R.
SoftSlopes soft_slopes(const std::array<double, 5>& solimp, double dist, double margin,
                       double diag) {
  double slope = 0.0;
  const double imp = impedance(solimp, dist, margin, &slope);
  const bool floored = (1 - imp) * diag / imp < kMinVal;  // R = mjMINVAL: constant
  return {-(slope * (dist - margin) + imp), floored ? 0.0 : -slope / (imp * (1 - imp))};
}

// Row r (the k-th held) whose Jacobian holds scale ten_J(t) of spatial tendon t, which moves with
// the pose (T = d ten_J / d q, spatial_tendons.cpp): dJ_c = scale T_c, so
// Y(k, c) += D (-B dJ_c . qvel - dJ_c . qacc) (aref's velocity term and -dJ qacc) and
// E(., c) += dJ_c f.
void add_moving_tendon_terms(const Model& model, const Data& data, int r, int k, int t,
                             double scale, Derivatives::Workspace& w) {
  if (!is_spatial_tendon(model, t) || scale == 0.0) return;
  spatial_tendon_change(model, data, t, w);
  const Eigen::MatrixXd& T = w.tendon_change;
  const double f = data.efc_force[r];
  for (int c = 0; c < model.nv; ++c) {
    const double T_qvel = T.col(c).dot(data.qvel), T_qacc = T.col(c).dot(data.qacc);
    w.contact_Y(k, c) += data.efc_D[r] * scale * (-data.efc_B[r] * T_qvel - T_qacc);
    w.contact_E.col(c) += (scale * f) * T.col(c);
  }
}

// A tendon's limit or friction-loss row (J = s ten_J, s = +-1) or a tendon coupling's
// (J = ten_J(t1) - poly'(x_2) ten_J(t2)): the terms of its spatial tendons' moving Jacobians.
void spatial_tendon_row(const Model& model, const Data& data, int r, int k,
                        Derivatives::Workspace& w) {
  const int id = data.efc_id[r];
  if (data.efc_type[r] == ConstraintType::kEquality) {
    if (model.eq_type[id] != EqualityType::kTendon) return;
    const int t1 = model.eq_obj1id[id], t2 = model.eq_obj2id[id];
    add_moving_tendon_terms(model, data, r, k, t1, 1.0, w);
    if (t2 < 0) return;
    const double* c = model.eq_data[id].data();
    const double x = data.ten_length[t2] - model.tendon_length0[t2];
    const double slope = c[1] + 2 * c[2] * x + 3 * c[3] * x * x + 4 * c[4] * x * x * x;
    add_moving_tendon_terms(model, data, r, k, t2, -slope, w);
    return;
  }
  const double* J = data.efc_J.row(r).data();
  const double* ten_J = data.ten_J.row(id).data();
  double along = 0.0;  // efc_J . ten_J: the row's sign
  for (int i = 0; i < model.nv; ++i) along += J[i] * ten_J[i];
  add_moving_tendon_terms(model, data, r, k, id, along < 0 ? -1.0 : 1.0, w);
}

// A row whose Jacobian is the gradient of its distance in the coordinates: a fixed tendon's limit
// (distance +-(L - stop), J = +-ten_J, constant) and a joint's or tendon's coupling (distance
// x_1 - poly(x_2) about qpos0, J = J_1 - poly'(x_2) J_2 with J_1, J_2 the joints' unit rows or the
// tendons' constant Jacobians). So d dist / d q = J, and the coupling's J moves only through
// poly': dJ / d q_c = -poly''(x_2) J_2[c] J_2. Writes Y(k, .) = D (d aref - dR f - dJ qacc) and
// E += dJ^T f.
void coordinate_row(const Model& model, const Data& data, int r, int k, RowMatrix& Y,
                    Eigen::MatrixXd& E) {
  const int nv = model.nv;
  const int id = data.efc_id[r];
  std::array<double, 2> solref;
  std::array<double, 5> solimp;
  double diag = 0.0;
  const double* J2 = nullptr;  // a coupling's second object's row (joint: a unit row, at dof2)
  int dof2 = -1;
  double curvature = 0.0;  // poly''(x_2)
  if (data.efc_type[r] == ConstraintType::kLimitTendon) {
    solref = model.tendon_solref_lim[id];
    solimp = model.tendon_solimp_lim[id];
    diag = model.tendon_invweight0[id];
  } else {
    solref = model.eq_solref[id];
    solimp = model.eq_solimp[id];
    const bool tendons = model.eq_type[id] == EqualityType::kTendon;
    const int o1 = model.eq_obj1id[id], o2 = model.eq_obj2id[id];
    diag = tendons ? model.tendon_invweight0[o1] : model.dof_invweight0[model.jnt_dofadr[o1]];
    if (o2 >= 0) {
      double x;
      if (tendons) {
        diag += model.tendon_invweight0[o2];
        J2 = data.ten_J.row(o2).data();
        x = data.ten_length[o2] - model.tendon_length0[o2];
      } else {
        diag += model.dof_invweight0[model.jnt_dofadr[o2]];
        dof2 = model.jnt_dofadr[o2];
        const int a2 = model.jnt_qposadr[o2];
        x = data.qpos[a2] - model.qpos0[a2];
      }
      const double* c = model.eq_data[id].data();
      curvature = 2 * c[2] + 6 * c[3] * x + 12 * c[4] * x * x;
    }
  }
  sanitize(model, solref, solimp);
  const SoftSlopes s = soft_slopes(solimp, data.efc_pos[r], data.efc_margin[r], diag);
  const double* J = data.efc_J.row(r).data();
  const double position = data.efc_D[r] * (data.efc_K[r] * s.aref_per_dist -
                                           data.efc_R[r] * s.R_per_dist * data.efc_force[r]);
  for (int c = 0; c < nv; ++c) Y(k, c) = position * J[c];
  if (curvature == 0.0) return;
  // dJ_c x = -poly'' J_2[c] (J_2 . x): in d aref (-B dJ qvel), in -dJ qacc, and dJ^T f
  const auto row2 = [&](int i) { return J2 != nullptr ? J2[i] : (i == dof2 ? 1.0 : 0.0); };
  double J2_qacc = 0.0, J2_qvel = 0.0;
  for (int i = 0; i < nv; ++i) {
    J2_qacc += row2(i) * data.qacc[i];
    J2_qvel += row2(i) * data.qvel[i];
  }
  const double f = data.efc_force[r];
  for (int c = 0; c < nv; ++c) {
    const double turn = -curvature * row2(c);  // dJ_c = turn J_2
    if (turn == 0.0) continue;
    Y(k, c) += data.efc_D[r] * (-data.efc_B[r] * turn * J2_qvel - turn * J2_qacc);
    for (int i = 0; i < nv; ++i) E(i, c) += turn * row2(i) * f;
  }
}

}  // namespace

void dofs_moving(const Model& model, int body, std::vector<char>& moves) {
  std::fill(moves.begin(), moves.end(), 0);
  while (body > 0 && model.body_dofnum[body] == 0) body = model.body_parentid[body];
  if (body == 0) return;
  for (int i = model.body_dofadr[body] + model.body_dofnum[body] - 1; i >= 0;
       i = model.dof_parentid[i]) {
    moves[static_cast<std::size_t>(i)] = 1;
  }
}

Vec3 point_velocity(const Model& model, const Data& data, int c, const Vec3& p) {
  const Motion& S = data.cdof[c];
  const Vec3 origin = data.subtree_com[model.body_rootid[model.dof_bodyid[c]]];
  return S.tail<3>() + S.head<3>().cross(p - origin);
}

void carry_table(const Model& model, std::vector<char>& table) {
  const auto nv = static_cast<std::size_t>(model.nv);
  table.assign(nv * nv, 0);
  for (int c = 0; c < model.nv; ++c) {
    for (int i = 0; i < model.nv; ++i) {
      table[static_cast<std::size_t>(c) * nv + static_cast<std::size_t>(i)] = carries(model, c, i);
    }
  }
}

void branch_table(const Model& model, std::vector<int>& first, std::vector<int>& dofs) {
  const int nv = model.nv;
  // whether dof a is dof b or one of its ancestors
  const auto above = [&](int a, int b) {
    for (int k = b; k >= 0; k = model.dof_parentid[k]) {
      if (k == a) return true;
    }
    return false;
  };
  first.assign(static_cast<std::size_t>(nv) + 1, 0);
  dofs.clear();
  for (int i = 0; i < nv; ++i) {
    first[static_cast<std::size_t>(i)] = static_cast<int>(dofs.size());
    for (int j = 0; j < nv; ++j) {
      if (above(j, i) || above(i, j)) dofs.push_back(j);
    }
  }
  first[static_cast<std::size_t>(nv)] = static_cast<int>(dofs.size());
}

int held_active_rows(const Data& data, std::vector<int>& rows) {
  int n = 0;
  for (int r = 0; r < data.nefc; ++r) {
    if (data.efc_state[r] == ConstraintState::kCone) {
      throw Error(
          "derivatives: an elliptic cone's force is on the cone's surface (its middle zone); lever "
          "differentiates elliptic cones inside their quadratic zone and pyramidal and frictionless "
          "contacts so far.");
    }
    if (data.efc_state[r] == ConstraintState::kActive) rows[static_cast<std::size_t>(n++)] = r;
  }
  return n;
}

RowSpan row_span(const Data& data, int r) {
  switch (data.efc_type[r]) {
    case ConstraintType::kContactFrictionless:
    case ConstraintType::kContactPyramidal:
    case ConstraintType::kContactElliptic: {
      const int i = data.efc_id[r];
      return {data.work.contact_span[2 * i], data.work.contact_span[2 * i + 1]};
    }
    default: break;
  }
  if (data.efc_dof[r] >= 0) return {data.efc_dof[r], 1};  // a joint's limit or friction loss
  return {0, static_cast<int>(data.efc_J.cols())};
}

namespace {

// w J^T J over a row's span of N dofs, J = J_span (its first N numbers): for each b with
// J_b != 0, dst_b += (J_b w) J, dst_b the N numbers at base + b stride (H's column b, or X's row
// b). A fixed N is unrolled in SSE2 pairs with J held in registers.
template <int N>
void add_span_outer_fixed(double* base, Eigen::Index stride, const double* J, double w) {
  using Span = Eigen::Matrix<double, N, 1>;
  const Span j = Eigen::Map<const Span>(J);
  for (int b = 0; b < N; ++b) {
    if (j[b] == 0.0) continue;
    Eigen::Map<Span>(base + b * stride) += (j[b] * w) * j;
  }
}

void add_span_outer(double* base, Eigen::Index stride, const double* J, int count, double w) {
  switch (count) {
    case 1: add_span_outer_fixed<1>(base, stride, J, w); return;
    case 2: add_span_outer_fixed<2>(base, stride, J, w); return;
    case 3: add_span_outer_fixed<3>(base, stride, J, w); return;
    case 4: add_span_outer_fixed<4>(base, stride, J, w); return;
    case 5: add_span_outer_fixed<5>(base, stride, J, w); return;
    case 6: add_span_outer_fixed<6>(base, stride, J, w); return;  // a free body on the world
    case 7: add_span_outer_fixed<7>(base, stride, J, w); return;
    case 8: add_span_outer_fixed<8>(base, stride, J, w); return;
    default: break;
  }
  for (int b = 0; b < count; ++b) {
    if (J[b] != 0.0) add_scaled_row(base + b * stride, J[b] * w, J, count);
  }
}

// G = J_S^T D_S J_S over the rows rows[0..n): factor_held_rows()' G.
void held_rows_weight(const Data& data, const int* rows, int n, Eigen::MatrixXd& G) {
  // nv is small, so each row's span of dofs on its own (Eigen's dynamic outer products cost more
  // in setup than in arithmetic here); the span's whole block, symmetric
  const auto nv = static_cast<int>(data.M.rows());
  G.setZero();
  for (int k = 0; k < n; ++k) {
    const int r = rows[k];
    const RowSpan s = row_span(data, r);
    add_span_outer(G.data() + s.lo * (nv + 1), nv, data.efc_J.row(r).data() + s.lo, s.count,
                   data.efc_D[r]);
  }
}

}  // namespace

void factor_held_rows(const Data& data, const int* rows, int n, Eigen::MatrixXd& G,
                      Eigen::MatrixXd& H, std::vector<int>& first) {
  const auto nv = static_cast<int>(data.M.rows());
  held_rows_weight(data, rows, n, G);
  H = data.M + G;
  // H's profile: the first column of each row's lower part that is not zero (M's is the row's
  // tree's first dof; the rows join the trees they couple). L L^T keeps it, so the factor and
  // the solves read nothing to its left.
  for (int i = 0; i < nv; ++i) {
    int j = 0;
    while (j < i && H(i, j) == 0.0) ++j;
    first[static_cast<std::size_t>(i)] = j;
  }
  for (int i = 0; i < nv; ++i) {  // H = L L^T in place, row by row, L in the lower triangle
    const int fi = first[static_cast<std::size_t>(i)];
    for (int j = fi; j <= i; ++j) {
      double sum = H(i, j);
      for (int k = std::max(fi, first[static_cast<std::size_t>(j)]); k < j; ++k) {
        sum -= H(i, k) * H(j, k);
      }
      H(i, j) = j < i ? sum / H(j, j) : std::sqrt(sum);
    }
  }
}

void solve_held_rows(const Eigen::MatrixXd& L, const std::vector<int>& first,
                     Eigen::Ref<RowMatrix> X, double* diagonal_inverse) {
  const auto nv = static_cast<int>(L.rows());
  const Eigen::Index cols = X.cols();
  // one row operation over every column: y_i -= L(i, k) y_k
  const auto subtract = [&](int i, double a, int k) {  // -a x_k added is a x_k taken, to the bit
    add_scaled_row(X.row(i).data(), -a, X.row(k).data(), cols);
  };
  // each row scaled by 1 / L(i, i), once per row: tens of columns a row, where a division costs
  // several multiplications' time
  for (int i = 0; i < nv; ++i) diagonal_inverse[i] = 1.0 / L(i, i);
  for (int i = 0; i < nv; ++i) {  // L y = x
    for (int k = first[static_cast<std::size_t>(i)]; k < i; ++k) subtract(i, L(i, k), k);
    scale_row(X.row(i).data(), diagonal_inverse[i], cols);
  }
  for (int i = nv - 1; i >= 0; --i) {  // L^T x = y: x_i final, it leaves the rows it reaches
    scale_row(X.row(i).data(), diagonal_inverse[i], cols);
    for (int k = first[static_cast<std::size_t>(i)]; k < i; ++k) subtract(k, L(i, k), i);
  }
}

void solve_settled_factor(const Data& data, Eigen::Ref<RowMatrix> X, double* diagonal_inverse) {
  const Eigen::MatrixXd::ConstMapType L(data.work.newton_H.data(), data.work.newton_H.rows(),
                                        data.work.newton_H.cols());
  const int* const end = data.work.hessian_envelope.data();  // one past column j's last nonzero
  const auto nv = static_cast<int>(L.rows());
  const Eigen::Index cols = X.cols();
  for (int j = 0; j < nv; ++j) diagonal_inverse[j] = 1.0 / L(j, j);  // as solve_held_rows()
  for (int j = 0; j < nv; ++j) {  // L y = x: y_j, once final, leaves the rows below
    scale_row(X.row(j).data(), diagonal_inverse[j], cols);
    for (int i = j + 1; i < end[j]; ++i) {
      if (L(i, j) != 0.0) add_scaled_row(X.row(i).data(), -L(i, j), X.row(j).data(), cols);
    }
  }
  for (int i = nv - 1; i >= 0; --i) {  // L^T x = y
    for (int k = i + 1; k < end[i]; ++k) {
      if (L(k, i) != 0.0) add_scaled_row(X.row(i).data(), -L(k, i), X.row(k).data(), cols);
    }
    scale_row(X.row(i).data(), diagonal_inverse[i], cols);
  }
}

bool rows_beyond_joint_limits(const Data& data) {
  for (int r = 0; r < data.nefc; ++r) {
    if (data.efc_type[r] != ConstraintType::kLimitJoint &&
        data.efc_state[r] != ConstraintState::kSatisfied) {
      return true;
    }
  }
  return false;
}

namespace {

// A geom pair's contact rows are C_k = frame_k . (sum_d s_d j_d(p)) over the dofs d on one of its
// bodies' paths (s_d = +1 on body 2's, -1 on body 1's), with j_d(p) = v_d + w_d x p, v_d dof d's
// velocity at the world origin (w.contact_point_velocity). So a sum over d at any contact point
// follows from two sums made once for the pair: sum x_d j_d(p) = sum x_d v_d + (sum x_d w_d) x p.
// Likewise column c of dJ^T f and of the pair's rows' J^T Y, summed over the pair's contacts as a
// ColumnWrench, adds s_d (force . v_d + torque . w_d) to E(d, c) for every d on one path, and
// s_d (carried_force . v_d + carried_torque . w_d) where c turns d's axis.
using PathSums = Derivatives::Workspace::PathSums;
using ColumnWrench = Derivatives::Workspace::ColumnWrench;

// A contact's row held active, as the directions' loop reads it: J = C_t, or a pyramid's
// C_0 + mu C_t, and y = D (K_per_dist d dist - R_per_dist d dist f - dJ (qacc + B qvel)) (aref's
// velocity term -B dJ qvel beside -dJ qacc), the two slopes through the distance (aref's position
// term, R) made once for all directions.
struct HeldContactRow {
  int t;
  double mu, D, K_per_dist, R_per_dist, f;
};
constexpr int kMaxContactRows = 10;  // a pyramid of condim 6

bool is_contact(ConstraintType type) {
  return type == ConstraintType::kContactFrictionless ||
         type == ConstraintType::kContactPyramidal || type == ConstraintType::kContactElliptic;
}

// Sets up a pair whose bodies w.moves1, w.moves2 hold: each dof's velocity at the world origin,
// the path sums of the motion x = qacc + B qvel (B its rows'), the dofs that move the pair
// (w.pair_dofs), its motion along each (w.pair_motions) and the sums over the dofs each turns
// (w.pair_turned), its columns of dJ^T f zeroed (w.pair_columns); returns the dofs' count.
int begin_pair(const Model& model, const Data& data, const Contact& con, double B, PathSums& path,
               Derivatives::Workspace& w) {
  const int nv = model.nv;
  path = PathSums{};
  const auto x = [&](int d) { return data.qacc[d] + B * data.qvel[d]; };
  int directions = 0;
  for (int d = 0; d < nv; ++d) {
    if (!w.moves1[d] && !w.moves2[d]) continue;
    w.pair_dofs[static_cast<std::size_t>(directions++)] = d;
    const Vec3 v = point_velocity(model, data, d, Vec3::Zero());
    w.contact_point_velocity[static_cast<std::size_t>(d)] = v;
    if (w.moves1[d] == w.moves2[d]) continue;
    const double sx = (w.moves2[d] ? 1.0 : -1.0) * x(d);
    path.V += sx * v;
    path.W += sx * angular(data.cdof[d]);
  }
  for (int m = 0; m < directions; ++m) {
    const int c = w.pair_dofs[static_cast<std::size_t>(m)];
    const Vec3 wc = angular(data.cdof[c]);
    GeomPairMotion& motion = w.pair_motions[static_cast<std::size_t>(m)];
    motion = GeomPairMotion{};
    if (w.moves1[c]) {
      motion.w1 = wc;
      motion.v1 = point_velocity(model, data, c, data.geom_xpos[con.geom1]);
    }
    if (w.moves2[c]) {
      motion.w2 = wc;
      motion.v2 = point_velocity(model, data, c, data.geom_xpos[con.geom2]);
    }
    PathSums& turned = w.pair_turned[static_cast<std::size_t>(m)];
    turned = PathSums{};
    w.pair_columns[static_cast<std::size_t>(m)] = ColumnWrench{};
    const char* carried = w.carries.data() + static_cast<std::ptrdiff_t>(c) * nv;
    for (int j = 0; j < directions; ++j) {  // the dofs c turns are among the pair's
      const int d = w.pair_dofs[static_cast<std::size_t>(j)];
      if (!carried[d] || w.moves1[d] == w.moves2[d]) continue;
      const double sx = (w.moves2[d] ? 1.0 : -1.0) * x(d);
      turned.V += sx * w.contact_point_velocity[static_cast<std::size_t>(d)];
      turned.W += sx * angular(data.cdof[d]);
    }
  }
  return directions;
}

// Adds the pair's summed columns of dJ^T f to E, over the dofs on one path.
void spread_pair_columns(const Model& model, const Data& data, const Derivatives::Workspace& w,
                         int directions, Eigen::MatrixXd& E) {
  const int nv = model.nv;
  for (int m = 0; m < directions; ++m) {
    const int c = w.pair_dofs[static_cast<std::size_t>(m)];
    const ColumnWrench& column = w.pair_columns[static_cast<std::size_t>(m)];
    const char* carried = w.carries.data() + static_cast<std::ptrdiff_t>(c) * nv;
    for (int j = 0; j < directions; ++j) {
      const int d = w.pair_dofs[static_cast<std::size_t>(j)];
      if (w.moves1[d] == w.moves2[d]) continue;
      const double s = w.moves2[d] ? 1.0 : -1.0;
      const Vec3& v = w.contact_point_velocity[static_cast<std::size_t>(d)];
      const Vec3 wd = angular(data.cdof[d]);
      double e = column.force.dot(v) + column.torque.dot(wd);
      if (carried[d]) e += column.carried_force.dot(v) + column.carried_torque.dot(wd);
      E(d, c) += s * e;
    }
  }
}

}  // namespace

void constraint_rows_held(const Model& model, Data& data, Derivatives& deriv) {
  auto& w = deriv.work;
  const int nv = model.nv, nu = model.nu;
  const int n = held_active_rows(data, w.rows);
  w.active_rows = n;
  // (nefc_max x nv) y's qpos columns, a row per active row (a contact's rows' go straight into E)
  RowMatrix& Y = w.contact_Y;
  Eigen::MatrixXd& E = w.contact_E;  // (nv x nv) dJ^T f, and the contact rows' J^T Y
  for (int k = 0; k < n; ++k) {  // a contact row's y is never read: only the others' zeroed
    if (!is_contact(data.efc_type[w.rows[k]])) Y.row(k).setZero();
  }
  E.setZero();

  // the rows of joints and fixed tendons (limits, friction loss, joint and tendon couplings)
  std::array<double, 2> solref;
  std::array<double, 5> solimp;
  for (int k = 0; k < n; ++k) {
    const int r = w.rows[k];
    if (data.efc_type[r] == ConstraintType::kLimitJoint) {
      // distance sign (q - stop) on one dof
      limit_parameters(model, data.efc_id[r], solref, solimp);
      const SoftSlopes s = soft_slopes(solimp, data.efc_pos[r], data.efc_margin[r],
                                       model.dof_invweight0[data.efc_dof[r]]);
      const double sign = data.efc_sign[r];
      const double daref = data.efc_K[r] * s.aref_per_dist * sign;
      const double dR = data.efc_R[r] * s.R_per_dist * sign;
      Y(k, data.efc_dof[r]) = data.efc_D[r] * (daref - dR * data.efc_force[r]);
    } else if (data.efc_type[r] == ConstraintType::kEquality &&
               (model.eq_type[data.efc_id[r]] == EqualityType::kConnect ||
                model.eq_type[data.efc_id[r]] == EqualityType::kWeld)) {
      // a connect's or weld's rows, all at once at the first (equality_rows.cpp)
      if (r == 0 || data.efc_type[r - 1] != ConstraintType::kEquality ||
          data.efc_id[r - 1] != data.efc_id[r]) {
        body_equality_rows(model, data, data.efc_id[r], k, w);
      }
    } else if (data.efc_type[r] == ConstraintType::kLimitTendon ||
               data.efc_type[r] == ConstraintType::kEquality) {
      coordinate_row(model, data, r, k, Y, E);
    }
    if (data.efc_type[r] == ConstraintType::kLimitTendon ||
        data.efc_type[r] == ConstraintType::kFrictionTendon ||
        data.efc_type[r] == ConstraintType::kEquality) {
      spatial_tendon_row(model, data, r, k, w);
    }
    // a friction-loss row has no distance (pos 0, K 0) and, but for a spatial tendon's, a
    // constant Jacobian: its terms are aref's velocity part alone, below
  }
  // a spatial tendon's friction-loss row at its bound passes on a constant force along a Jacobian
  // that moves: dJ^T f
  for (int r = 0; r < data.nefc; ++r) {
    const ConstraintState state = data.efc_state[r];
    if (data.efc_type[r] != ConstraintType::kFrictionTendon ||
        (state != ConstraintState::kLinearNeg && state != ConstraintState::kLinearPos) ||
        !is_spatial_tendon(model, data.efc_id[r])) {
      continue;
    }
    spatial_tendon_change(model, data, data.efc_id[r], w);
    E += data.efc_force[r] * w.tendon_change;
  }

  // the contacts with an active row, a geom pair at a time: the pair's sums over its dofs are
  // made once, each contact's terms follow from them at its point, and dJ^T f's columns are
  // summed over the pair's contacts before they are spread over the dofs
  std::vector<char>& moves1 = w.moves1;
  std::vector<char>& moves2 = w.moves2;
  PathSums path;  // the pair's
  int cached_pair = -1;  // the first contact of the pair whose terms w holds
  double cached_B = 0;   // the B of its rows, which its path sums weigh qvel by
  int directions = 0;    // the dofs that move that pair
  for (int i = 0; i < data.ncon; ++i) {
    const Contact& con = data.contact[static_cast<std::size_t>(i)];
    const int first = con.efc_address;
    if (first < 0) continue;
    const bool pyramid = data.efc_type[first] == ConstraintType::kContactPyramidal;
    const int dim = con.dim;
    const int rows = pyramid ? 2 * (dim - 1) : (dim > 1 ? dim : 1);
    int first_k = -1;  // where the contact's active rows start in w.rows
    for (int k = 0; k < n && first_k < 0; ++k) {
      if (w.rows[k] >= first && w.rows[k] < first + rows) first_k = k;
    }
    if (first_k < 0) continue;
    if (!contact_geometry_supported(model.geom_type[con.geom1], model.geom_type[con.geom2])) {
      ContactChange unused;  // names the pair in its message
      contact_change(model, data, i, Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero(),
                     unused);
    }
    int pair_count = 0;
    const int pair_first = pair_first_contact(data, i, pair_count);
    // -dJ qacc and aref's velocity term -B dJ qvel enter each row's y together, as -dJ x for the
    // motion x = qacc + B qvel (dJ is linear in it, and a contact's rows share one B: MuJoCo makes
    // them from one solref, as it does a pair's contacts)
    const double B = data.efc_B[first];
    // the pair's first contact with a pushing row (or one whose B is not the pair's)
    if (pair_first != cached_pair || B != cached_B) {
      if (cached_pair >= 0) spread_pair_columns(model, data, w, directions, E);
      cached_pair = pair_first;
      cached_B = B;
      dofs_moving(model, model.geom_bodyid[con.geom1], moves1);
      dofs_moving(model, model.geom_bodyid[con.geom2], moves2);
      directions = begin_pair(model, data, con, B, path, w);
      // all of the pair's contacts, along each dof that moves the pair, at once
      pair_contact_changes(model, data, pair_first, pair_count, w.pair_motions.data(), directions,
                           w.pair_changes.data());
    }
    const Vec3 p = con.pos;

    // the frame force (normal, tangents, spin, rolls) of the rows' forces
    double F[6] = {0, 0, 0, 0, 0, 0};
    const double* f = data.efc_force.data() + first;
    if (pyramid) {
      for (int k = 1; k < dim; ++k) {
        F[0] += f[2 * (k - 1)] + f[2 * (k - 1) + 1];
        F[k] = con.friction[static_cast<std::size_t>(k - 1)] * (f[2 * (k - 1)] - f[2 * (k - 1) + 1]);
      }
    } else {
      for (int k = 0; k < rows; ++k) F[k] = f[k];
    }
    Vec3 phi = Vec3::Zero(), tau = Vec3::Zero();  // the force and torque at p, world axes
    for (int k = 0; k < 3 && k < dim; ++k) phi += F[k] * con.frame.row(k).transpose();
    for (int k = 3; k < dim; ++k) tau += F[k] * con.frame.row(k - 3).transpose();

    // x's relative point and angular velocities at p
    const Vec3 Wx = path.W;
    const Vec3 Vx = path.V + Wx.cross(p);

    // the soft parameters' slopes through the contact's distance (every row of it shares them)
    const int b_sum1 = model.geom_bodyid[con.geom1], b_sum2 = model.geom_bodyid[con.geom2];
    const double translation = model.body_invweight0[b_sum1][0] + model.body_invweight0[b_sum2][0];
    const double mu0 = con.friction[0];
    const double diag = pyramid ? translation + mu0 * mu0 * translation : translation;
    const SoftSlopes soft = soft_slopes(bounded_solimp(con.solimp), con.dist, con.includemargin, diag);

    // each held row's constants, once for every direction: which frame rows it combines (C_t, and
    // a pyramid's C_0 + mu C_t) and its soft parameters' factors
    HeldContactRow held[kMaxContactRows];
    int nheld = 0;
    for (int k = first_k; k < n && w.rows[k] < first + rows; ++k) {
      const int r = w.rows[k], q = r - first;
      HeldContactRow& h = held[nheld++];
      h.t = pyramid ? q / 2 + 1 : q;
      h.mu = pyramid ? con.friction[static_cast<std::size_t>(h.t - 1)] * (q % 2 ? -1.0 : 1.0) : 0.0;
      h.D = data.efc_D[r];
      h.K_per_dist = data.efc_K[r] * soft.aref_per_dist;
      h.R_per_dist = data.efc_R[r] * soft.R_per_dist;
      h.f = data.efc_force[r];
    }

    for (int m = 0; m < directions; ++m) {
      const int c = w.pair_dofs[static_cast<std::size_t>(m)];
      const Vec3 wc = angular(data.cdof[c]);
      // a slide's or a free joint's translation turns nothing: its terms in w_c vanish
      const bool turns = (wc[0] != 0.0) | (wc[1] != 0.0) | (wc[2] != 0.0);  // one branch
      const ContactChange& change =
          w.pair_changes[static_cast<std::size_t>(m * pair_count + (i - pair_first))];
      const Vec3 jc = w.contact_point_velocity[static_cast<std::size_t>(c)] + wc.cross(p);
      const PathSums& turned = w.pair_turned[static_cast<std::size_t>(m)];
      ColumnWrench& column = w.pair_columns[static_cast<std::size_t>(m)];

      // dJ^T f's column c: phi . d j_d + tau . d w_d over the dofs d on one path, with
      // d j_d = w_d x dp (+ w_c x j_d - w_d x j_c where c turns d's axis) and d w_d = w_c x w_d
      // where it does; phi . d j_d + tau . d w_d = j_d . (phi x w_c) + w_d . (tau x w_c - j_c x
      // phi) there. With j_d = v_d + w_d x p each is force . v_d + torque . w_d.
      // (a frame that c does not turn, a plane's normal say, adds no terms in d frame)
      const bool frame_turns = (change.frame.array() != 0.0).any();
      if (frame_turns) {
        Vec3 dphi = Vec3::Zero(), dtau = Vec3::Zero();
        for (int k = 0; k < 3 && k < dim; ++k) dphi += F[k] * change.frame.row(k).transpose();
        for (int k = 3; k < dim; ++k) dtau += F[k] * change.frame.row(k - 3).transpose();
        column.force += dphi;
        column.torque += p.cross(dphi) + change.pos.cross(phi) + dtau;
      } else {
        column.torque += change.pos.cross(phi);
      }

      // dV, dW for x: the moved point, and the axes c turns
      const Vec3& turned_W = turned.W;
      Vec3 dV, dW = Vec3::Zero();
      if (turns) {
        const Vec3 turn_j = phi.cross(wc), turn_w = tau.cross(wc) - jc.cross(phi);
        column.carried_force += turn_j;
        column.carried_torque += p.cross(turn_j) + turn_w;
        const Vec3 turned_V = turned.V + turned_W.cross(p);
        dV = Wx.cross(change.pos) + wc.cross(turned_V) - turned_W.cross(jc);
        dW = wc.cross(turned_W);
      } else {
        column.carried_torque -= jc.cross(phi);
        dV = Wx.cross(change.pos) - turned_W.cross(jc);
      }
      // d (C_k x)
      double dC[6];
      for (int k = 0; k < 3 && k < dim; ++k) {
        dC[k] = con.frame.row(k).dot(dV);
        if (frame_turns) dC[k] = change.frame.row(k).dot(Vx) + dC[k];
      }
      for (int k = 3; k < dim; ++k) {
        dC[k] = con.frame.row(k - 3).dot(dW);
        if (frame_turns) dC[k] = change.frame.row(k - 3).dot(Wx) + dC[k];
      }
      // each row's y, and J_r^T y_r's column c: J_r is a combination of the frame's rows C_k
      // (a pyramid's C_0 +- mu C_t), so sum_r J_r^T y_r = sum_k C_k^T z_k, a force and a torque
      // at p, summed with dJ^T f's column and spread with it
      double z[6] = {0, 0, 0, 0, 0, 0};
      const double dist = change.dist;
      for (int j = 0; j < nheld; ++j) {
        const HeldContactRow& h = held[j];
        const double dJ = pyramid ? dC[0] + h.mu * dC[h.t] : dC[h.t];
        const double y = h.D * (h.K_per_dist * dist - h.R_per_dist * dist * h.f - dJ);
        if (pyramid) {
          z[0] += y;
          z[h.t] += h.mu * y;
        } else {
          z[h.t] += y;
        }
      }
      Vec3 row_force = Vec3::Zero(), row_torque = Vec3::Zero();
      for (int k = 0; k < 3 && k < dim; ++k) row_force += z[k] * con.frame.row(k).transpose();
      for (int k = 3; k < dim; ++k) row_torque += z[k] * con.frame.row(k - 3).transpose();
      column.force += row_force;
      column.torque += p.cross(row_force) + row_torque;
    }
  }
  if (cached_pair >= 0) spread_pair_columns(model, data, w, directions, E);

  // d qacc = G + H^-1 (E + J_S^T (Y - D J_S G)) = H^-1 (rhs + E + J_S^T Y), because
  // H G - J_S^T D J_S G = M G = rhs, the right-hand side smooth_rhs() left in w.rhs_* (before
  // M^-1): one solve with H for the qpos, qvel and ctrl columns side by side (row-major, each
  // substitution one row operation), and no product with G. Y's qvel columns are aref's
  // velocity term, -D B J_r.
  // H's factor: the forward solve's where its active-set rounds settled on these rows (the same
  // matrix, its pyramids' edges summed in pairs), else made here
  Eigen::MatrixXd& H = w.contact_H;
  Eigen::MatrixXd& G = w.contact_G;  // J_S^T D_S J_S
  const bool solver_factor = settled_active_set_factor(model, data);
  RowMatrix& X = w.right_hand_sides;
  // aref's velocity term: J_S^T (-D_S B_S J_S), which is -B G where the held rows share one B
  // (one solref's: every row of a scene that sets none). With the solver's factor, G is not
  // formed: H^-1 (-B G) = -B H^-1 (H - M) = H^-1 (B M) - B I, so the qvel columns' right-hand
  // side takes + B M and the solve's answer - B on its diagonal.
  bool one_B = true;
  for (int k = 1; k < n; ++k) one_B = one_B && data.efc_B[w.rows[k]] == data.efc_B[w.rows[0]];
  const bool velocity_term = n > 0 && one_B;
  const double B = velocity_term ? data.efc_B[w.rows[0]] : 0.0;
  if (!solver_factor) factor_held_rows(data, w.rows.data(), n, G, H, w.contact_H_first);
  // the qvel columns' B-weighted matrix: + B M with the solver's factor, else - B G
  const double* weight = solver_factor ? data.M.data() : G.data();
  const double Bs = solver_factor ? B : -B;
  // [rhs_q + E, rhs_v +- B (M or G), rhs_u] into X's rows in one pass down the inputs' columns
  const Eigen::Index stride = X.cols();
  for (int c = 0; c < nv; ++c) {
    const double* q = w.rhs_q.col(c).data();
    const double* e = E.col(c).data();
    const double* v = w.rhs_v.col(c).data();
    const double* g = weight + static_cast<std::ptrdiff_t>(c) * nv;  // both nv x nv, by columns
    double* x = X.data() + c;
    if (velocity_term) {
      for (int i = 0; i < nv; ++i, x += stride) {
        x[0] = q[i] + e[i];
        x[nv] = v[i] + Bs * g[i];
      }
    } else {
      for (int i = 0; i < nv; ++i, x += stride) {
        x[0] = q[i] + e[i];
        x[nv] = v[i];
      }
    }
  }
  X.rightCols(nu + model.na) = w.rhs_u;  // ctrl, then act
  for (int k = 0; k < n; ++k) {  // J_r's non-zeros lie in its span; y_r's wherever dofs move it
    const int r = w.rows[k];
    if (one_B && is_contact(data.efc_type[r])) continue;  // nothing more to add
    const double* J = data.efc_J.row(r).data();
    const RowSpan span = row_span(data, r);
    const double* y = Y.row(k).data();
    const int end = span.lo + span.count;
    if (!is_contact(data.efc_type[r])) {  // a contact's J_r^T y_r is in E already
      for (int i = span.lo; i < end; ++i) {
        if (J[i] == 0.0) continue;
        double* x = X.row(i).data();
        for (int c = 0; c < nv; ++c) x[c] += J[i] * y[c];
      }
    }
    if (one_B) continue;
    add_span_outer(X.row(span.lo).data() + nv + span.lo, X.cols(), J + span.lo, span.count,
                   -data.efc_D[r] * data.efc_B[r]);
  }
  if (solver_factor) {
    solve_settled_factor(data, X, w.col.data());
    if (velocity_term) {
      for (int i = 0; i < nv; ++i) X(i, nv + i) -= B;
    }
  } else {
    solve_held_rows(H, w.contact_H_first, X, w.col.data());
  }
  deriv.dqacc_dq = X.leftCols(nv);
  deriv.dqacc_dv = X.middleCols(nv, nv);
  deriv.dqacc_du = X.middleCols(2 * nv, nu);
  deriv.dqacc_dact = X.rightCols(model.na);
  // M d qacc = rhs + d qfrc_constraint, M's zeros (dofs on different branches) skipped
  // (crba writes M's entries off the branches as zeros, so row i's columns are read along its
  // branch alone; each entry of d qfrc_constraint starts as -rhs, then adds M(i, j) x_j in turn)
  const int na = model.na;
  for (int i = 0; i < nv; ++i) {
    bool started = false;
    for (int b = w.branch_first[i]; b < w.branch_first[i + 1]; ++b) {
      const int j = w.branch_dofs[static_cast<std::size_t>(b)];
      const double a = data.M(i, j);
      if (a == 0.0) continue;
      const double* x = X.row(j).data();
      if (!started) {
        for (int c = 0; c < nv; ++c) deriv.dconstraint_dq(i, c) = -w.rhs_q(i, c) + a * x[c];
        for (int c = 0; c < nv; ++c) deriv.dconstraint_dv(i, c) = -w.rhs_v(i, c) + a * x[nv + c];
        for (int c = 0; c < nu; ++c) {
          deriv.dconstraint_du(i, c) = -w.rhs_u(i, c) + a * x[2 * nv + c];
        }
        for (int c = 0; c < na; ++c) {
          deriv.dconstraint_dact(i, c) = -w.rhs_u(i, nu + c) + a * x[2 * nv + nu + c];
        }
        started = true;
        continue;
      }
      for (int c = 0; c < nv; ++c) deriv.dconstraint_dq(i, c) += a * x[c];
      for (int c = 0; c < nv; ++c) deriv.dconstraint_dv(i, c) += a * x[nv + c];
      for (int c = 0; c < nu; ++c) deriv.dconstraint_du(i, c) += a * x[2 * nv + c];
      for (int c = 0; c < na; ++c) deriv.dconstraint_dact(i, c) += a * x[2 * nv + nu + c];
    }
    if (started) continue;  // else a row of M all zero: -rhs alone
    for (int c = 0; c < nv; ++c) deriv.dconstraint_dq(i, c) = -w.rhs_q(i, c);
    for (int c = 0; c < nv; ++c) deriv.dconstraint_dv(i, c) = -w.rhs_v(i, c);
    for (int c = 0; c < nu; ++c) deriv.dconstraint_du(i, c) = -w.rhs_u(i, c);
    for (int c = 0; c < na; ++c) deriv.dconstraint_dact(i, c) = -w.rhs_u(i, nu + c);
  }
}

}  // namespace lever::detail
