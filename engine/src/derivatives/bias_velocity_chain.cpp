// d qfrc_bias / d qvel as MuJoCo 2.2.2's implicit integrator forms it (mjd_rne_vel and
// mjd_comVel_vel, engine_derivative.c): the chain rule through the recursive Newton-Euler passes,
// the derivative of every body's velocity, acceleration and force with respect to qvel carried
// from the root to the leaves, the forces summed back, and each dof's row read off as
// -cdof . d cfrc. It is the same matrix as Carpentier and Mansard's (inverse_dynamics.cpp), but
// rounded as MuJoCo rounds it, which the implicit step needs: (M - h D) magnifies D's last bits
// (a 340-dof cloth's qvel moved by 1.4 times the 1e-12 bound).
//
// MuJoCo forms the whole 6 x nv derivative of every body at once, its products skipping the
// matrices' zero entries. Every operation acts on the columns one by one, so here the columns are
// taken one at a time (the derivative along one dof's velocity c): the same products and sums,
// element by element, over the bodies whose numbers in that column are not zero, those in the
// subtree of c's body (velocity, acceleration, force) and their ancestors (summed forces).
//
// For column c, with v_b = d cvel_b / d qvel_c, a_b = d cacc_b, f_b = d cfrc_b:
//   forward, each body b from its parent p:   v_b = v_p, a_b = a_p, then for each dof j of b
//     d cdof_dot_j = X(cdof_j) v_b              X: d (vel x cdof) / d vel
//     v_b += cdof_j [j = c]                     (a ball's three dofs take X with v_b before any
//                                                of their three columns; a free joint's
//                                                translations have cdof_dot = 0)
//     a_b += cdof_dot_j [j = c] + d cdof_dot_j qvel_j
//   f_b = I_b a_b + C_b v_b                     C_b = d (v x* (I v)) / d v at cvel_b
//   backward, leaves to root:                   f_p += f_b  (p not the world)
//   D(r, c) -= cdof_r . f_body(r)               (six products added one at a time)
#include <lever/data.hpp>
#include <lever/model.hpp>

#include "derivatives/derivatives_room.hpp"

namespace lever {

namespace {

using Matrix6 = std::array<double, 36>;  // row-major

// A 3 x 3 skew block [a]x (a x . = [a]x .) written into M at (row, col), times sign.
void put_skew(Matrix6& M, int row, int col, const double* a, double sign) {
  double* r0 = &M[6 * row + col];
  double* r1 = r0 + 6;
  double* r2 = r1 + 6;
  r0[1] = -sign * a[2];
  r0[2] = sign * a[1];
  r1[0] = sign * a[2];
  r1[2] = -sign * a[0];
  r2[0] = -sign * a[1];
  r2[1] = sign * a[0];
}

// d (vel x* f) / d vel for the force cross product vel x* f = [w x n + u x p; w x p]
// (f = [n; p]): [-[n]x, -[p]x; -[p]x, 0].
Matrix6 force_cross_by_velocity(const Force& f) {
  Matrix6 X{};
  put_skew(X, 0, 0, f.data(), -1.0);
  put_skew(X, 0, 3, f.data() + 3, -1.0);
  put_skew(X, 3, 0, f.data() + 3, -1.0);
  return X;
}

// d (vel x* f) / d f = [[w]x, [u]x; 0, [w]x] times the inertia matrix [I, [h]x; -[h]x, m 1] of
// I (mju_mulInertVec's coefficients, h = m times the centre of mass's offset): each entry summed
// over k in order, as MuJoCo's mju_mulMatMat sums it, on the left factor's non-zeros only (its
// zero entries would add zeros, which change no sum but a zero's sign).
Matrix6 force_cross_times_inertia(const Motion& vel, const RigidInertia& I) {
  double inertia[36] = {};
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) inertia[6 * r + c] = I.I(r, c);
  }
  const double* h = I.h.data();
  inertia[4] = -h[2], inertia[5] = h[1];     // [h]x
  inertia[9] = h[2], inertia[11] = -h[0];
  inertia[15] = -h[1], inertia[16] = h[0];
  inertia[19] = h[2], inertia[20] = -h[1];   // -[h]x
  inertia[24] = -h[2], inertia[26] = h[0];
  inertia[30] = h[1], inertia[31] = -h[0];
  inertia[21] = inertia[28] = inertia[35] = I.m;

  // the left factor's rows, on their non-zero columns k in order
  const double* w = vel.data();
  const double* u = vel.data() + 3;
  const double* B0 = inertia;
  const double* B1 = inertia + 6;
  const double* B2 = inertia + 12;
  const double* B3 = inertia + 18;
  const double* B4 = inertia + 24;
  const double* B5 = inertia + 30;
  Matrix6 out;
  for (int c = 0; c < 6; ++c) {
    out[c] = -w[2] * B1[c] + w[1] * B2[c] + -u[2] * B4[c] + u[1] * B5[c];
    out[6 + c] = w[2] * B0[c] + -w[0] * B2[c] + u[2] * B3[c] + -u[0] * B5[c];
    out[12 + c] = -w[1] * B0[c] + w[0] * B1[c] + -u[1] * B3[c] + u[0] * B4[c];
    out[18 + c] = -w[2] * B4[c] + w[1] * B5[c];
    out[24 + c] = w[2] * B3[c] + -w[0] * B5[c];
    out[30 + c] = -w[1] * B3[c] + w[0] * B4[c];
  }
  return out;
}

// A x (6 x 6), each row summed over its columns in order, as MuJoCo's mju_mulMatMat sums it.
// MuJoCo skips A's zero entries; here a zero entry adds a zero, which changes no sum (only,
// where a sum is zero, that zero's sign).
inline void times(const Matrix6& A, const double* x, double* out) {
  for (int r = 0; r < 6; ++r) {
    const double* a = &A[6 * r];
    out[r] = a[0] * x[0] + a[1] * x[1] + a[2] * x[2] + a[3] * x[3] + a[4] * x[4] + a[5] * x[5];
  }
}

// The two products the columns repeat, written out on their matrices' structural non-zeros, each
// row summed over its columns in order, as times() sums it.

// d (vel x m) / d vel times x, for the motion cross product vel x m = [w x m_w; w x m_v + u x m_w]
// (vel = [w; u], m = [m_w; m_v]), whose derivative is [-[m_w]x, 0; -[m_v]x, -[m_w]x]
inline void motion_cross_times(const Motion& m, const Motion& x, Motion& out) {
  out[0] = m[2] * x[1] - m[1] * x[2];
  out[1] = -m[2] * x[0] + m[0] * x[2];
  out[2] = m[1] * x[0] - m[0] * x[1];
  out[3] = m[5] * x[1] - m[4] * x[2] + m[2] * x[4] - m[1] * x[5];
  out[4] = -m[5] * x[0] + m[3] * x[2] - m[2] * x[3] + m[0] * x[5];
  out[5] = m[4] * x[0] - m[3] * x[1] + m[1] * x[3] - m[0] * x[4];
}

// inertia_matrix(I) x: mju_mulInertVec's sums
inline void inertia_times(const RigidInertia& I, const double* x, double* out) {
  const Eigen::Matrix3d& J = I.I;
  const Eigen::Vector3d& h = I.h;
  out[0] = J(0, 0) * x[0] + J(0, 1) * x[1] + J(0, 2) * x[2] - h[2] * x[4] + h[1] * x[5];
  out[1] = J(1, 0) * x[0] + J(1, 1) * x[1] + J(1, 2) * x[2] + h[2] * x[3] - h[0] * x[5];
  out[2] = J(2, 0) * x[0] + J(2, 1) * x[1] + J(2, 2) * x[2] - h[1] * x[3] + h[0] * x[4];
  out[3] = h[2] * x[1] - h[1] * x[2] + I.m * x[3];
  out[4] = -h[2] * x[0] + h[0] * x[2] + I.m * x[4];
  out[5] = h[1] * x[0] - h[0] * x[1] + I.m * x[5];
}

}  // namespace

void subtract_bias_velocity_derivative(const Model& model, Data& data,
                                       Eigen::Ref<Eigen::MatrixXd> D) {
  const int nbody = model.nbody, nv = model.nv;
  BiasVelocityBody* const body = data.work.bias_chain_body.data();
  Motion* const dcdof_dot = data.work.bias_chain_dof.data();
  const int* const parent = model.body_parentid.data();

  // the matrices of the state, the same for every column
  for (int b = 1; b < nbody; ++b) {
    Force momentum;  // I cvel
    inertia_times(data.cinert[b], data.cvel[b].data(), momentum.data());
    body[b].coupling = force_cross_by_velocity(momentum);
    const Matrix6 through_momentum = force_cross_times_inertia(data.cvel[b], data.cinert[b]);
    for (int e = 0; e < 36; ++e) body[b].coupling[e] += through_momentum[e];
  }

  for (int c = 0; c < nv; ++c) {
    const int top = model.dof_bodyid[c];
    for (int b = 0; b < nbody; ++b) body[b].branch = 0;
    for (int b = parent[top]; b > 0; b = parent[b]) {  // the subtree's forces are summed here
      body[b].branch = 2;
      body[b].force.setZero();
    }

    // forward: the subtree of c's body (its bodies come after it)
    for (int b = top; b < nbody; ++b) {
      const int p = parent[b];
      const bool inside = b == top || (p > 0 && body[p].branch == 1);
      if (!inside) continue;
      BiasVelocityBody& B = body[b];
      B.branch = 1;
      if (b == top) {  // its parent's numbers in this column are zero
        B.velocity.setZero();
        B.acceleration.setZero();
      } else {
        B.velocity = body[p].velocity;
        B.acceleration = body[p].acceleration;
      }
      const int first = model.body_dofadr[b], last = first + model.body_dofnum[b];
      for (int j = first; j < last; ++j) {
        const JointType type = model.jnt_type[model.dof_jntid[j]];
        if (type == JointType::kFree) {  // translations: cdof_dot = 0, then the rotations
          for (int t = j; t < j + 3; ++t) dcdof_dot[t].setZero();
          for (int t = j; t < j + 3; ++t) {
            if (t == c) B.velocity += data.cdof[t];
          }
          j += 3;
        }
        if (type == JointType::kFree || type == JointType::kBall) {
          for (int t = j; t < j + 3; ++t) {
            motion_cross_times(data.cdof[t], B.velocity, dcdof_dot[t]);
          }
          for (int t = j; t < j + 3; ++t) {
            if (t == c) B.velocity += data.cdof[t];
          }
          j += 2;
          continue;
        }
        motion_cross_times(data.cdof[j], B.velocity, dcdof_dot[j]);
        if (j == c) B.velocity += data.cdof[j];
      }
      for (int j = first; j < last; ++j) {
        if (j == c) B.acceleration += data.cdof_dot[j];
        const double qvel = data.qvel[j];
        for (int k = 0; k < 6; ++k) B.acceleration[k] += dcdof_dot[j][k] * qvel;
      }
      inertia_times(data.cinert[b], B.acceleration.data(), B.force.data());
      Force coupled;
      times(B.coupling, B.velocity.data(), coupled.data());
      B.force += coupled;
    }

    // backward: each body's force to its parent, leaves first
    for (int b = nbody - 1; b > 0; --b) {
      if (body[b].branch != 0 && parent[b] > 0) body[parent[b]].force += body[b].force;
    }

    // D(r, c) -= cdof_r . f over the dofs of the bodies on c's branch
    double* const column = &D(0, c);
    for (int b = 1; b < nbody; ++b) {
      const BiasVelocityBody& B = body[b];
      if (B.branch == 0) continue;
      const int first = model.body_dofadr[b], last = first + model.body_dofnum[b];
      for (int r = first; r < last; ++r) {
        double out = column[r];
        for (int k = 0; k < 6; ++k) out += B.force[k] * -data.cdof[r][k];
        column[r] = out;
      }
    }
  }
}

}  // namespace lever
