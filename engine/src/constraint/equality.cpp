// Equality constraints as MuJoCo 2.2.2's rows (mj_instantiateEquality, the equality cases of
// mj_diagApprox and of getposdim in mj_makeImpedance), and the anchors mj_setConst completes.
//
// Each active constraint gives rows that are first in MuJoCo's order; every row is two-sided (its
// force pulls as well as pushes), always in the quadratic state of the primal problem.
//   connect (3 rows): the anchor on body 1 minus the same point on body 2, world frame;
//                     J = J_1(p_1) - J_2(p_2), the points' translational Jacobians.
//   weld (6 rows):    the same for the anchor, then the orientation error, the vector part of
//                     conj(q_2) q_1 relpose (zero when body 2 holds relpose in body 1's frame);
//                     its Jacobian 1/2 vec(conj(q_2) (0, w_1 - w_2) q_1 relpose) per dof, w the
//                     rotational Jacobians' columns, scaled by torquescale.
//   joint (1 row):    q_1 - q_1(qpos0) - poly(q_2 - q_2(qpos0)), poly(x) = c_0 + c_1 x + ... +
//                     c_4 x^4 (without a second joint, poly = c_0); J = e_1 - poly'(x) e_2.
//   tendon (1 row):   the same polynomial in the tendons' lengths about tendon_length0;
//                     J = J_1 - poly'(x) J_2 with the tendons' Jacobians.
// A constraint whose Jacobian is zero throughout (two bodies fixed to the world) makes no rows, as
// in MuJoCo. Impedance: the connect's and weld's rows share one, at the norm of their error (the
// weld's rotational part scaled by torquescale), a joint's at its error; no margin. diagApprox:
// the two bodies' translational invweight0 for every row of a connect, and also for every row of
// a weld: MuJoCo 2.2.2 means its rotational rows to take the rotational weights, but its counter
// of weld rows is reset on every row (it compares the row's type with mjEQ_WELD), so it never
// gets past the first; the joints' dof_invweight0 summed for a coupling.
#include <lever/kinematics.hpp>

#include <cmath>

#include "basics/basics.hpp"
#include "constraint/constraint_room.hpp"

namespace lever {

namespace {

// p = xpos + xmat v: a point given in a body's frame, in the world frame
Eigen::Vector3d world_point(const Data& data, int body, const double* v) {
  const Mat3& R = data.xmat[body];
  Eigen::Vector3d p;
  for (int k = 0; k < 3; ++k) p[k] = R(k, 0) * v[0] + R(k, 1) * v[1] + R(k, 2) * v[2];
  return p + data.xpos[body];
}

// q (w, x, y, z) * (0, v): a quaternion times a pure vector
Quat quat_mul_vector(const Quat& q, const double* v) {
  return Quat(-q[1] * v[0] - q[2] * v[1] - q[3] * v[2], q[0] * v[0] + q[2] * v[2] - q[3] * v[1],
              q[0] * v[1] + q[3] * v[0] - q[1] * v[2], q[0] * v[2] + q[1] * v[1] - q[2] * v[0]);
}

Quat conjugate(const Eigen::Vector4d& q) { return Quat(q[0], -q[1], -q[2], -q[3]); }

// The rows of connect or weld e from row n: their position errors into efc_pos, their Jacobian
// into efc_J. Returns the rows' count, 0 when the Jacobian is zero.
int body_rows(const Model& model, Data& data, int e, int n) {
  const int nv = model.nv;
  const bool weld = model.eq_type[e] == EqualityType::kWeld;
  const double* eq = model.eq_data[e].data();
  const int b1 = model.eq_obj1id[e], b2 = model.eq_obj2id[e];
  // the anchor: a connect's is given in body 1 (0-2) and body 2 (3-5); a weld's in body 2 (0-2)
  // and body 1 (3-5)
  const Eigen::Vector3d p1 = world_point(data, b1, weld ? eq + 3 : eq);
  const Eigen::Vector3d p2 = world_point(data, b2, weld ? eq : eq + 3);
  auto& jac = data.work.equality_jac;  // rows: J_1 translation, rotation, J_2 translation, rotation
  jac_point(model, data, b1, p1, jac.middleRows(0, 3), jac.middleRows(3, 3));
  jac_point(model, data, b2, p2, jac.middleRows(6, 3), jac.middleRows(9, 3));
  const int rows = weld ? 6 : 3;
  for (int k = 0; k < 3; ++k) {
    data.efc_pos[n + k] = p1[k] - p2[k];
    for (int j = 0; j < nv; ++j) data.efc_J(n + k, j) = jac(k, j) - jac(6 + k, j);
  }
  if (weld) {
    const Quat relative = quat_mul(data.xquat[b1], Quat(eq[6], eq[7], eq[8], eq[9]));
    const Quat conj2 = conjugate(data.xquat[b2]);
    const Quat error = quat_mul(conj2, relative);
    const double torquescale = eq[10];
    for (int k = 0; k < 3; ++k) data.efc_pos[n + 3 + k] = error[1 + k];
    for (int j = 0; j < nv; ++j) {
      const double w[3] = {jac(3, j) - jac(9, j), jac(4, j) - jac(10, j), jac(5, j) - jac(11, j)};
      const Quat turn = quat_mul(quat_mul_vector(conj2, w), relative);
      for (int k = 0; k < 3; ++k) data.efc_J(n + 3 + k, j) = 0.5 * turn[1 + k] * torquescale;
    }
  }
  for (int k = 0; k < rows; ++k) {
    for (int j = 0; j < nv; ++j) {
      if (data.efc_J(n + k, j) != 0.0) return rows;
    }
  }
  return 0;
}

// The row of joint coupling e at row n. Returns 1.
int joint_row(const Model& model, Data& data, int e, int n) {
  const double* c = model.eq_data[e].data();
  const int j1 = model.eq_obj1id[e], j2 = model.eq_obj2id[e];
  const int a1 = model.jnt_qposadr[j1];
  data.efc_J.row(n).setZero();
  data.efc_J(n, model.jnt_dofadr[j1]) = 1.0;
  const double offset = data.qpos[a1] - model.qpos0[a1] - c[0];
  if (j2 < 0) {
    data.efc_pos[n] = offset;
    return 1;
  }
  const int a2 = model.jnt_qposadr[j2];
  const double x = data.qpos[a2] - model.qpos0[a2];
  data.efc_pos[n] = offset - (c[1] * x + c[2] * x * x + c[3] * x * x * x + c[4] * x * x * x * x);
  const double slope = c[1] + 2 * c[2] * x + 3 * c[3] * x * x + 4 * c[4] * x * x * x;
  data.efc_J(n, model.jnt_dofadr[j2]) = -slope;
  return 1;
}

// The row of tendon coupling e at row n, as a joint coupling's with the tendons' lengths against
// their lengths at qpos0 (tendon_length0): J = J_1 - poly'(x) J_2, the tendons' Jacobians.
// Returns 1.
int tendon_row(const Model& model, Data& data, int e, int n) {
  const double* c = model.eq_data[e].data();
  const int t1 = model.eq_obj1id[e], t2 = model.eq_obj2id[e];
  const int nv = model.nv;
  const double* const J1 = data.ten_J.data() + static_cast<std::ptrdiff_t>(t1) * nv;
  for (int j = 0; j < nv; ++j) data.efc_J(n, j) = J1[j];
  const double offset = data.ten_length[t1] - model.tendon_length0[t1] - c[0];
  if (t2 < 0) {
    data.efc_pos[n] = offset;
    return 1;
  }
  const double x = data.ten_length[t2] - model.tendon_length0[t2];
  data.efc_pos[n] = offset - (c[1] * x + c[2] * x * x + c[3] * x * x * x + c[4] * x * x * x * x);
  const double slope = c[1] + 2 * c[2] * x + 3 * c[3] * x * x + 4 * c[4] * x * x * x;
  const double* const J2 = data.ten_J.data() + static_cast<std::ptrdiff_t>(t2) * nv;
  for (int j = 0; j < nv; ++j) data.efc_J(n, j) += J2[j] * -slope;
  return 1;
}

// The soft parameters of constraint e's rows n..n + rows.
void set_equality_soft_rows(const Model& model, Data& data, int e, int n, int rows) {
  std::array<double, 2> solref = model.eq_solref[e];
  std::array<double, 5> solimp = model.eq_solimp[e];
  sanitize(model, solref, solimp);
  // the rows' distance from satisfied: the norm of the error (a weld's rotation scaled)
  double distance = data.efc_pos[n];
  if (rows > 1) {
    const double torquescale = model.eq_data[e][10];
    double sum = 0.0;
    for (int k = 0; k < rows; ++k) {
      const double x = k < 3 ? data.efc_pos[n + k] : torquescale * data.efc_pos[n + k];
      sum += x * x;
    }
    distance = std::sqrt(sum);
  }
  const SoftParameters soft = soft_parameters(solref, solimp, distance, 0.0);
  double diag;
  if (model.eq_type[e] == EqualityType::kJoint) {
    diag = model.dof_invweight0[model.jnt_dofadr[model.eq_obj1id[e]]];
    const int j2 = model.eq_obj2id[e];
    if (j2 >= 0) diag += model.dof_invweight0[model.jnt_dofadr[j2]];
  } else if (model.eq_type[e] == EqualityType::kTendon) {
    diag = model.tendon_invweight0[model.eq_obj1id[e]];
    const int t2 = model.eq_obj2id[e];
    if (t2 >= 0) diag += model.tendon_invweight0[t2];
  } else {  // translational, for a weld's rotational rows too (see the top of this file)
    diag =
        model.body_invweight0[model.eq_obj1id[e]][0] + model.body_invweight0[model.eq_obj2id[e]][0];
  }
  const double R = regularizer(soft, diag);
  set_soft_rows(data, n, rows, soft, soft.K, R);
}

}  // namespace

int add_equality_rows(const Model& model, Data& data, int n) {
  for (int e = 0; e < model.neq; ++e) {
    if (!model.eq_active[e]) continue;
    const EqualityType type = model.eq_type[e];
    const int rows = type == EqualityType::kJoint    ? joint_row(model, data, e, n)
                     : type == EqualityType::kTendon ? tendon_row(model, data, e, n)
                                                     : body_rows(model, data, e, n);
    for (int r = n; r < n + rows; ++r) {
      data.efc_type[r] = ConstraintType::kEquality;
      data.efc_id[r] = e;
      data.efc_dof[r] = -1;
      data.efc_sign[r] = 0.0;
      data.efc_margin[r] = 0.0;
      data.efc_frictionloss[r] = 0.0;
    }
    if (rows > 0) set_equality_soft_rows(model, data, e, n, rows);
    n += rows;
  }
  return n;
}

void complete_equality_data(Model& model, const Data& data) {
  for (int e = 0; e < model.neq; ++e) {
    auto& eq = model.eq_data[e];
    const int b1 = model.eq_obj1id[e], b2 = model.eq_obj2id[e];
    if (model.eq_type[e] == EqualityType::kConnect) {
      // the anchor (in body 1) in body 2's frame
      const Eigen::Vector3d offset = world_point(data, b1, eq.data()) - data.xpos[b2];
      const Eigen::Vector3d local = data.xmat[b2].transpose() * offset;
      for (int k = 0; k < 3; ++k) eq[3 + k] = local[k];
    } else if (model.eq_type[e] == EqualityType::kWeld) {
      if (eq[6] != 0 || eq[7] != 0 || eq[8] != 0 || eq[9] != 0) {  // relpose given
        detail::normalize_quat(eq.data() + 6);
        continue;
      }
      // the anchor (in body 2) in body 1's frame, and body 2's orientation in body 1's
      const Eigen::Vector3d offset = world_point(data, b2, eq.data()) - data.xpos[b1];
      const Eigen::Vector3d local = data.xmat[b1].transpose() * offset;
      for (int k = 0; k < 3; ++k) eq[3 + k] = local[k];
      const Quat relative = quat_mul(conjugate(data.xquat[b1]), data.xquat[b2]);
      for (int k = 0; k < 4; ++k) eq[6 + k] = relative[k];
    }
  }
}

}  // namespace lever
