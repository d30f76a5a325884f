// A connect's and a weld's rows differentiated in qpos, for the held rows' solve
// (contact_rows.cpp). Their rows are two-sided and always in the quadratic state, so holding the
// active set holds nothing: the derivative is exact wherever the model is smooth.
//
// A connect (3 rows) keeps anchor p_1 (rigid in body 1) on anchor p_2 (rigid in body 2):
//   pos = p_1 - p_2,   J x = V_1(x) - V_2(x),   V_b(x) = sum_{i moves b} x_i j_i(p_b)
// with j_i(p) = u_i + w_i x (p - O) dof i's velocity at p (cdof = (w_i, u_i), O its tree's centre
// of mass). A weld adds 3 rows of orientation error, with q_1, q_2 the bodies' orientations, r
// their relative pose and W_b(x) = sum_{i moves b} x_i w_i:
//   pos = vec(q_2* q_1 r),     J x = 1/2 torquescale vec(q_2* (0, W_1(x) - W_2(x)) q_1 r).
// Moving dof c turns the axes of the dofs it carries, moves each anchor by dp_b = j_c(p_b) when c
// moves its body, and turns q_b by d q_b = 1/2 (0, w_c) q_b, so (the contacts' rule, with the
// anchors rigid in their bodies):
//   d j_i(p_b) / d q_c = [c carries i] (w_c x j_i(p_b) - w_i x j_c(p_b)) + w_i x dp_b
//   d W_b(x)  / d q_c  = w_c x W_b^c(x),   W_b^c(x) the sum over the dofs c carries
//   d (q_2* X' q_1 r)  = q_2* X q_1 r,  X = 1/2 (W . (w_2c - w_1c), W x (w_1c + w_2c)) + (0, dW)
// for X' = (0, W) (w_bc = w_c where c moves body b, else 0). The position's change is the
// Jacobian's column c (the rotational rows' without torquescale), and the impedance is taken at
// the norm of the error, |(pos_t, torquescale pos_r)|, which all the rows share: d imp =
// slope d dist with d dist = (pos_t . dpos_t + torquescale^2 pos_r . dpos_r) / dist. Then per row
//   y_r = D (d aref - dR f - dJ qacc),  d aref = -B dJ qvel - K (d imp pos_r + imp d pos_r)
// (aref's -B J d qvel is the caller's, as for every row), dR = -R d imp / (imp (1 - imp)) (0 on
// R's floor), and E's column c gains dJ^T f.
#include <lever/error.hpp>

#include <cmath>

#include "basics/basics.hpp"
#include "constraint/constraint_room.hpp"
#include "transition/transition.hpp"

namespace lever::detail {

namespace {

using Vec3 = Eigen::Vector3d;

Vec3 anchor_in_world(const Data& data, int body, const double* local) {
  return data.xpos[body] + data.xmat[body] * Vec3(local[0], local[1], local[2]);
}

Quat pure(const Vec3& v) { return Quat(0, v[0], v[1], v[2]); }

// X of the top of this file: the change of (0, W) between q_2* and q_1 r when dof c moves
// body 1 with w1c and body 2 with w2c, W's own change being dW
Quat turned_error(const Vec3& W, const Vec3& dW, const Vec3& w1c, const Vec3& w2c) {
  const Vec3 v = 0.5 * W.cross(w1c + w2c) + dW;
  return Quat(0.5 * W.dot(w2c - w1c), v[0], v[1], v[2]);
}

}  // namespace

void body_equality_rows(const Model& model, const Data& data, int e, int first_k,
                        Derivatives::Workspace& w) {
  const int nv = model.nv;
  const bool weld = model.eq_type[e] == EqualityType::kWeld;
  const int rows = weld ? 6 : 3;
  const int r0 = w.rows[static_cast<std::size_t>(first_k)];
  for (int k = 1; k < rows; ++k) {
    if (w.rows[static_cast<std::size_t>(first_k + k)] != r0 + k) {
      throw Error("derivatives: an equality constraint's rows are not all active.");
    }
  }
  const double* eq = model.eq_data[e].data();
  const int b1 = model.eq_obj1id[e], b2 = model.eq_obj2id[e];
  // a connect's anchor is given in body 1 (eq 0-2) and body 2 (3-5), a weld's in body 2 (0-2)
  // and body 1 (3-5)
  const Vec3 p1 = anchor_in_world(data, b1, weld ? eq + 3 : eq);
  const Vec3 p2 = anchor_in_world(data, b2, weld ? eq : eq + 3);
  std::vector<char>& on1 = w.moves1;
  std::vector<char>& on2 = w.moves2;
  dofs_moving(model, b1, on1);
  dofs_moving(model, b2, on2);
  Vec3* const j1 = w.equality_point_velocity.data();  // j_i(p_1), for i moving body 1
  Vec3* const j2 = j1 + nv;                           // j_i(p_2), for i moving body 2

  // V_b, W_b of qacc (s = 0) and qvel (s = 1)
  const double* const x[2] = {data.qacc.data(), data.qvel.data()};
  Vec3 V1[2], W1[2], V2[2], W2[2];
  for (int s = 0; s < 2; ++s) V1[s] = W1[s] = V2[s] = W2[s] = Vec3::Zero();
  for (int i = 0; i < nv; ++i) {
    const Vec3 wi = data.cdof[i].head<3>();
    if (on1[i]) j1[i] = point_velocity(model, data, i, p1);
    if (on2[i]) j2[i] = point_velocity(model, data, i, p2);
    for (int s = 0; s < 2; ++s) {
      if (on1[i]) {
        V1[s] += x[s][i] * j1[i];
        W1[s] += x[s][i] * wi;
      }
      if (on2[i]) {
        V2[s] += x[s][i] * j2[i];
        W2[s] += x[s][i] * wi;
      }
    }
  }

  // the weld's orientation error vec(q_2* X q_1 r) for a change X of its middle factor
  const double torquescale = weld ? eq[10] : 0.0;
  const Quat q1r = weld ? quat_mul(data.xquat[b1], Quat(eq[6], eq[7], eq[8], eq[9])) : Quat::Zero();
  const Eigen::Vector4d& q2 = data.xquat[b2];
  const Quat q2_conj(q2[0], -q2[1], -q2[2], -q2[3]);
  const auto error_change = [&](const Quat& X) -> Vec3 {
    return quat_mul(quat_mul(q2_conj, X), q1r).tail<3>();
  };

  // the rows' errors and forces, the shared distance and the impedance's slope through it
  const Vec3 pos_t(data.efc_pos[r0], data.efc_pos[r0 + 1], data.efc_pos[r0 + 2]);
  const Vec3 f_t(data.efc_force[r0], data.efc_force[r0 + 1], data.efc_force[r0 + 2]);
  Vec3 pos_r = Vec3::Zero(), f_r = Vec3::Zero();
  if (weld) {
    pos_r = Vec3(data.efc_pos[r0 + 3], data.efc_pos[r0 + 4], data.efc_pos[r0 + 5]);
    f_r = Vec3(data.efc_force[r0 + 3], data.efc_force[r0 + 4], data.efc_force[r0 + 5]);
  }
  const double dist =
      std::sqrt(pos_t.squaredNorm() + torquescale * torquescale * pos_r.squaredNorm());
  std::array<double, 2> solref = model.eq_solref[e];
  std::array<double, 5> solimp = model.eq_solimp[e];
  sanitize(model, solref, solimp);
  double slope = 0.0;
  const double imp = impedance(solimp, dist, 0.0, &slope);
  const double diag = model.body_invweight0[b1][0] + model.body_invweight0[b2][0];
  const bool floored = (1 - imp) * diag / imp < kMinVal;  // R = mjMINVAL: constant
  const double R_per_imp = floored ? 0.0 : -1 / (imp * (1 - imp));

  RowMatrix& Y = w.contact_Y;
  Eigen::MatrixXd& E = w.contact_E;
  for (int c = 0; c < nv; ++c) {
    const bool c1 = on1[c] != 0, c2 = on2[c] != 0;
    if (!c1 && !c2) continue;
    const Vec3 wc = data.cdof[c].head<3>();
    const Vec3 w1c = c1 ? wc : Vec3::Zero(), w2c = c2 ? wc : Vec3::Zero();
    const Vec3 dp1 = c1 ? j1[c] : Vec3::Zero(), dp2 = c2 ? j2[c] : Vec3::Zero();
    const Vec3 dpos_t = dp1 - dp2;
    const Vec3 dpos_r = weld ? Vec3(0.5 * error_change(pure(w1c - w2c))) : Vec3::Zero();
    const double ddist =
        dist > 0 ? (pos_t.dot(dpos_t) + torquescale * torquescale * pos_r.dot(dpos_r)) / dist
                 : 0.0;
    const double dimp = slope * ddist;

    // what the dofs c carries contribute to V_b, W_b (their axes turn with c)
    Vec3 Vc1[2], Wc1[2], Vc2[2], Wc2[2];
    for (int s = 0; s < 2; ++s) Vc1[s] = Wc1[s] = Vc2[s] = Wc2[s] = Vec3::Zero();
    const char* carried = w.carries.data() + static_cast<std::ptrdiff_t>(c) * nv;
    for (int i = 0; i < nv; ++i) {
      if (carried[i] == 0) continue;
      const Vec3 wi = data.cdof[i].head<3>();
      for (int s = 0; s < 2; ++s) {
        if (on1[i]) {
          Vc1[s] += x[s][i] * j1[i];
          Wc1[s] += x[s][i] * wi;
        }
        if (on2[i]) {
          Vc2[s] += x[s][i] * j2[i];
          Wc2[s] += x[s][i] * wi;
        }
      }
    }
    // d (J x) / d q_c for x = qacc, qvel: translational rows, then rotational
    Vec3 dJt[2], dJr[2];
    for (int s = 0; s < 2; ++s) {
      const Vec3 dV1 = c1 ? Vec3(wc.cross(Vc1[s]) - Wc1[s].cross(j1[c]) + W1[s].cross(dp1))
                          : Vec3::Zero();
      const Vec3 dV2 = c2 ? Vec3(wc.cross(Vc2[s]) - Wc2[s].cross(j2[c]) + W2[s].cross(dp2))
                          : Vec3::Zero();
      dJt[s] = dV1 - dV2;
      dJr[s] = Vec3::Zero();
      if (weld) {
        const Quat X = turned_error(W1[s] - W2[s], wc.cross(Wc1[s] - Wc2[s]), w1c, w2c);
        dJr[s] = 0.5 * torquescale * error_change(X);
      }
    }
    for (int k = 0; k < rows; ++k) {
      const int r = r0 + k;
      const int a = k < 3 ? k : k - 3;
      const double pos = k < 3 ? pos_t[a] : pos_r[a];
      const double dpos = k < 3 ? dpos_t[a] : dpos_r[a];
      const double dJa = k < 3 ? dJt[0][a] : dJr[0][a];
      const double dJv = k < 3 ? dJt[1][a] : dJr[1][a];
      const double daref =
          -data.efc_B[r] * dJv - data.efc_K[r] * (dimp * pos + data.efc_imp[r] * dpos);
      const double dR = data.efc_R[r] * R_per_imp * dimp;
      Y(first_k + k, c) = data.efc_D[r] * (daref - dR * data.efc_force[r] - dJa);
    }

    // dJ^T f's column c: f_t . d j_d(p_b) and the rotational rows' f_r . d J_r[d]
    for (int d = 0; d < nv; ++d) {
      const bool d1 = on1[d] != 0, d2 = on2[d] != 0;
      if (!d1 && !d2) continue;
      const Vec3 wd = data.cdof[d].head<3>();
      const bool turns = carried[d] != 0;
      double sum = 0.0;
      if (d1) {
        Vec3 dj = wd.cross(dp1);
        if (turns) dj += wc.cross(j1[d]) - wd.cross(j1[c]);
        sum += f_t.dot(dj);
      }
      if (d2) {
        Vec3 dj = wd.cross(dp2);
        if (turns) dj += wc.cross(j2[d]) - wd.cross(j2[c]);
        sum -= f_t.dot(dj);
      }
      if (weld && d1 != d2) {
        const double sign = d1 ? 1.0 : -1.0;
        const Vec3 W = sign * wd;
        const Vec3 dW = turns ? Vec3(sign * wc.cross(wd)) : Vec3::Zero();
        sum += 0.5 * torquescale * f_r.dot(error_change(turned_error(W, dW, w1c, w2c)));
      }
      E(d, c) += sum;
    }
  }
}

}  // namespace lever::detail
