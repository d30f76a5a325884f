// Passive fluid forces: MuJoCo 2.2.2's inertia-box model (engine_core_smooth.c,
// mj_inertiaBoxFluidModel; its velocity derivative, mjd_inertiaBoxFluid, for the implicit step).
//
// Each body with mass is replaced by the box that has its mass and principal inertia,
//   box_k = sqrt(6 (I_l + I_m - I_k) / m)            ({k, l, m} = {0, 1, 2}),
// moving with the body's velocity at its centre of mass, in its principal axes, relative to the
// wind (the medium's velocity). In those axes, with w the angular and v the linear velocity,
//   viscosity mu (Stokes drag on a sphere of the box's mean side d = (box_0 + box_1 + box_2) / 3):
//     torque = -pi d^3 mu w,                 force = -3 pi d mu v;
//   density rho (quadratic drag on the box's faces):
//     torque_k = -rho box_k (box_l^4 + box_m^4) |w_k| w_k / 64,
//     force_k  = -rho box_l box_m |v_k| v_k / 2.
// The torque and force act at the centre of mass; J^T carries them to qfrc_passive.
#include <algorithm>
#include <cmath>

#include "basics/basics.hpp"
#include "model/model_room.hpp"
#include "smooth/smooth.hpp"

namespace lever {

namespace {

using detail::kMinVal;
using detail::kPi;

// The inertia box's sides (MuJoCo clamps I_l + I_m - I_k at its mjMINVAL before the root).
Eigen::Vector3d inertia_box(const Model& model, int b) {
  const Eigen::Vector3d& I = model.body_inertia[b];
  const double m = model.body_mass[b];
  Eigen::Vector3d box;
  for (int k = 0; k < 3; ++k) {
    const double sum_of_others = I[(k + 1) % 3] + I[(k + 2) % 3] - I[k];
    box[k] = std::sqrt(std::max(kMinVal, sum_of_others) / m * 6.0);
  }
  return box;
}

// Whether body b feels the medium: MuJoCo skips the massless.
bool feels_medium(const Model& model, int b) { return model.body_mass[b] >= kMinVal; }

// The body's velocity at its centre of mass relative to the wind, in its principal axes:
// angular (w) and linear (v). The c-frame velocity cvel is taken at the subtree's centre of
// mass; moving it to xipos subtracts (xipos - subtree_com) x w from the linear part.
void velocity_in_medium(const Model& model, const Data& data, int b, Eigen::Vector3d& w,
                        Eigen::Vector3d& v) {
  const Motion& c = data.cvel[b];
  const Eigen::Vector3d angular = c.head<3>();
  const Eigen::Vector3d offset = data.xipos[b] - data.subtree_com[model.body_rootid[b]];
  const Eigen::Vector3d linear = c.tail<3>() - offset.cross(angular);
  const Mat3& R = data.ximat[b];
  w = rotate_back(R, angular);
  v = rotate_back(R, linear) - rotate_back(R, model.opt.wind);
}

// The first dof on the path from body b to the world (its own last dof, else its nearest
// ancestor's), -1 if none: the dofs that move b are it and its dof_parentid chain.
int last_dof_moving(const Model& model, int b) {
  while (b > 0 && model.body_dofnum[b] == 0) b = model.body_parentid[b];
  return b > 0 ? model.body_dofadr[b] + model.body_dofnum[b] - 1 : -1;
}

// Dof i's columns of the translational and rotational Jacobians of a point fixed to a body it
// moves, `offset` from the subtree's centre of mass (MuJoCo's mj_jac).
void jacobian_columns(const Data& data, int i, const Eigen::Vector3d& offset,
                      Eigen::Vector3d& jacp, Eigen::Vector3d& jacr) {
  const Motion& S = data.cdof[i];
  jacr = S.head<3>();
  jacp = S.tail<3>() + jacr.cross(offset);
}

}  // namespace

namespace detail {

void body_velocities(const Model& model, Data& data) {
  data.cvel[0].setZero();
  for (int b = 1; b < model.nbody; ++b) {
    // summed as mj_comVel sums it: a segment's dofs (a ball's three, a free joint's three and
    // three) together before they join the velocity
    Motion v = data.cvel[model.body_parentid[b]];
    Motion segment = Motion::Zero();
    for (int k = 0; k < model.body_dofnum[b]; ++k) {
      const int i = model.body_dofadr[b] + k;
      if (starts_segment(model, i)) {
        if (k > 0) v += segment;
        segment = data.cdof[i] * data.qvel[i];
      } else {
        segment += data.cdof[i] * data.qvel[i];
      }
    }
    if (model.body_dofnum[b] > 0) v += segment;
    data.cvel[b] = v;
  }
}

void add_fluid_forces(const Model& model, Data& data) {
  const double mu = model.opt.viscosity, rho = model.opt.density;
  body_velocities(model, data);
  for (int b = 1; b < model.nbody; ++b) {
    if (!feels_medium(model, b)) continue;
    const Eigen::Vector3d box = inertia_box(model, b);
    Eigen::Vector3d w, v;
    velocity_in_medium(model, data, b, w, v);

    Eigen::Vector3d torque = Eigen::Vector3d::Zero(), force = Eigen::Vector3d::Zero();
    if (mu > 0) {
      const double d = (box[0] + box[1] + box[2]) / 3.0;
      torque = (-kPi * d * d * d * mu) * w;
      force = (-3.0 * kPi * d * mu) * v;
    }
    if (rho > 0) {
      // the other two sides in increasing order, each power multiplied out, as MuJoCo does
      for (int k = 0; k < 3; ++k) {
        const double l = box[k == 0 ? 1 : 0], m = box[k == 2 ? 1 : 2];
        force[k] -= 0.5 * rho * l * m * std::abs(v[k]) * v[k];
        torque[k] -= rho * box[k] * (l * l * l * l + m * m * m * m) * std::abs(w[k]) * w[k] / 64.0;
      }
    }

    // back to world axes, applied at the centre of mass: qfrc += jacp^T force + jacr^T torque
    const Mat3& R = data.ximat[b];
    const Eigen::Vector3d world_force = R * force, world_torque = R * torque;
    const Eigen::Vector3d offset = data.xipos[b] - data.subtree_com[model.body_rootid[b]];
    for (int i = last_dof_moving(model, b); i >= 0; i = model.dof_parentid[i]) {
      Eigen::Vector3d jacp, jacr;
      jacobian_columns(data, i, offset, jacp, jacr);
      data.qfrc_passive[i] += jacp.dot(world_force);
      data.qfrc_passive[i] += jacr.dot(world_torque);
    }
  }
}

void add_fluid_velocity_terms(const Model& model, const Data& data,
                              Eigen::Ref<Eigen::MatrixXd> D) {
  // Each force component above is f_k = c_k g(u_k), u = J_local qvel (J_local: the body
  // Jacobian at the centre of mass in principal axes, rotation rows first); MuJoCo 2.2.2 adds
  // c_k g'(u_k) J_local,k^T J_local,k row by row, the viscous rows' first, then the density's:
  // g'(u) = 1 for viscosity, 2 |u| for density. Each term is added on its own, in that order,
  // with its factor c_k g'(u_k) formed as mjd_inertiaBoxFluid forms it.
  const double mu = model.opt.viscosity, rho = model.opt.density;
  double slopes[12];  // (torque, force) rows: the viscous six, then the density's six
  for (int b = 1; b < model.nbody; ++b) {
    if (!feels_medium(model, b)) continue;
    const Eigen::Vector3d box = inertia_box(model, b);
    Eigen::Vector3d w, v;
    velocity_in_medium(model, data, b, w, v);
    int rows = 0;
    if (mu > 0) {
      const double d = (box[0] + box[1] + box[2]) / 3.0;
      for (int k = 0; k < 3; ++k) slopes[rows + k] = -kPi * d * d * d * mu;
      for (int k = 0; k < 3; ++k) slopes[rows + 3 + k] = -3.0 * kPi * d * mu;
      rows += 6;
    }
    if (rho > 0) {
      const double fourth[3] = {box[0] * box[0] * box[0] * box[0],
                                box[1] * box[1] * box[1] * box[1],
                                box[2] * box[2] * box[2] * box[2]};
      slopes[rows + 0] = -rho * box[0] * (fourth[1] + fourth[2]) * 2 * std::abs(w[0]) / 64.0;
      slopes[rows + 1] = -rho * box[1] * (fourth[0] + fourth[2]) * 2 * std::abs(w[1]) / 64.0;
      slopes[rows + 2] = -rho * box[2] * (fourth[0] + fourth[1]) * 2 * std::abs(w[2]) / 64.0;
      slopes[rows + 3] = -0.5 * rho * box[1] * box[2] * 2 * std::abs(v[0]);
      slopes[rows + 4] = -0.5 * rho * box[0] * box[2] * 2 * std::abs(v[1]);
      slopes[rows + 5] = -0.5 * rho * box[0] * box[1] * 2 * std::abs(v[2]);
      rows += 6;
    }

    const Mat3& R = data.ximat[b];
    const Eigen::Vector3d offset = data.xipos[b] - data.subtree_com[model.body_rootid[b]];
    const auto local_column = [&](int i) {
      Eigen::Vector3d jacp, jacr;
      jacobian_columns(data, i, offset, jacp, jacr);
      Eigen::Matrix<double, 6, 1> u;
      u.head<3>() = rotate_back(R, jacr);
      u.tail<3>() = rotate_back(R, jacp);
      return u;
    };
    for (int i = last_dof_moving(model, b); i >= 0; i = model.dof_parentid[i]) {
      const Eigen::Matrix<double, 6, 1> ui = local_column(i);
      for (int j = last_dof_moving(model, b); j >= 0; j = model.dof_parentid[j]) {
        const Eigen::Matrix<double, 6, 1> uj = local_column(j);
        double& entry = D(i, j);
        for (int r = 0; r < rows; ++r) entry += ui[r % 6] * slopes[r] * uj[r % 6];
      }
    }
  }
}

}  // namespace detail

}  // namespace lever
