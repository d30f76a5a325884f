// The inertial-parameter regressor and the base parameters (see lever/regressor.hpp).
//
// RNEA's net force on body b, f_b = I_b a_b + v_b x* I_b v_b, is linear in the body's spatial
// inertia I_b, and I_b is linear in pi_b when all three are written in the body's own frame (origin
// at the body frame, body axes). So with v, a moved into that frame by the motion transform X_b,
//   f_b(body frame) = sum_k pi_b,k (E_k a + v x* E_k v),   E_k the inertia of unit parameter k,
// and tau_i = S_i . (the forces of the bodies i supports) = sum_b (X_b S_i) . f_b(body frame).
// Column k of body b's block is therefore (X_b S_i) . (E_k a_b + v_b x* E_k v_b) for each dof i
// that supports b, and zero for the others.
#include <lever/error.hpp>
#include <lever/kinematics.hpp>
#include <lever/regressor.hpp>
#include <lever/spatial.hpp>

#include <Eigen/Eigenvalues>
#include <Eigen/QR>

#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>

#include "internal.hpp"
#include "recursion.hpp"

namespace lever {

namespace {

constexpr int kPerBody = 10;
const char* const kParameterNames[kPerBody] = {"m",   "mx",  "my",  "mz",  "Ixx",
                                               "Iyy", "Izz", "Ixy", "Ixz", "Iyz"};

// The spatial inertia of unit parameter k (not a physical body: the basis of a linear map).
RigidInertia unit_inertia(int k) {
  RigidInertia E;
  if (k == 0) E.m = 1;
  if (k >= 1 && k <= 3) E.h[k - 1] = 1;
  if (k >= 4 && k <= 6) E.I(k - 4, k - 4) = 1;
  if (k == 7) E.I(0, 1) = E.I(1, 0) = 1;
  if (k == 8) E.I(0, 2) = E.I(2, 0) = 1;
  if (k == 9) E.I(1, 2) = E.I(2, 1) = 1;
  return E;
}

// A motion vector about c with world axes, moved to the body frame (origin p, rotation R).
Motion to_body_frame(const Motion& m, const Eigen::Vector3d& c, const Eigen::Vector3d& p,
                     const Mat3& R) {
  Motion out;
  out.head<3>() = rotate_back(R, m.head<3>());
  out.tail<3>() = rotate_back(R, m.tail<3>() + cross(m.head<3>(), p - c));
  return out;
}

std::string body_label(const Model& model, int b) {
  return model.body_name[b].empty() ? std::string("body").append(std::to_string(b))
                                    : model.body_name[b];
}

std::string dof_label(const Model& model, int i) {
  const std::string& joint = model.jnt_name[model.dof_jntid[i]];
  return joint.empty() ? std::string("dof").append(std::to_string(i)) : joint;
}

std::string actuator_label(const Model& model, int a) {
  return model.actuator_name[a].empty() ? std::string("actuator").append(std::to_string(a))
                                        : model.actuator_name[a];
}

bool has_gain_column(const Model& model, int a) {
  return model.actuator_gaintype[a] == GainType::kFixed;
}

int inertial_columns(const Model& model) { return kPerBody * (model.nbody - 1); }

}  // namespace

std::vector<int> gain_actuators(const Model& model) {
  std::vector<int> out;
  for (int a = 0; a < model.nu; ++a) {
    if (has_gain_column(model, a)) out.push_back(a);
  }
  return out;
}

int gain_tied_bias(const Model& model, int a) {
  switch (model.actuator_kind[a]) {
    case ActuatorKind::kPositionServo: return 1;  // kp (ctrl - length)
    case ActuatorKind::kVelocityServo: return 2;  // kv (ctrl - velocity)
    default: return 0;
  }
}

double actuator_gain_basis(const Model& model, int a, double ctrl, double qpos, double qvel) {
  if (model.actuator_ctrllimited[a]) {
    const auto& range = model.actuator_ctrlrange[a];
    ctrl = std::min(std::max(ctrl, range[0]), range[1]);
  }
  const double gear = model.actuator_gear[a][0];
  switch (gain_tied_bias(model, a)) {
    case 1: return ctrl - gear * qpos;
    case 2: return ctrl - gear * qvel;
    default: return ctrl;
  }
}

double actuator_gain_free_force(const Model& model, int a, double qpos, double qvel) {
  if (model.actuator_biastype[a] != BiasType::kAffine) return 0.0;
  const double gear = model.actuator_gear[a][0];
  const double length = gear * qpos, velocity = gear * qvel;
  const auto& b = model.actuator_biasprm[a];
  const int tied = gain_tied_bias(model, a);
  return b[0] + (tied == 1 ? 0.0 : b[1] * length) + (tied == 2 ? 0.0 : b[2] * velocity);
}

InertialParameters to_parameters(const MjcfInertial& inertial) {
  const double m = inertial.mass;
  const Eigen::Vector3d& c = inertial.pos;
  const Eigen::Matrix3d R = quat_to_mat(quat_normalized(inertial.quat));
  const Eigen::Matrix3d Ic = R * inertial.diaginertia.asDiagonal() * R.transpose();
  // parallel axes: about the origin, I = Ic + m (|c|^2 1 - c c^T)
  const Eigen::Matrix3d I =
      Ic + m * (c.squaredNorm() * Eigen::Matrix3d::Identity() - c * c.transpose());
  InertialParameters pi;
  pi << m, m * c, I(0, 0), I(1, 1), I(2, 2), I(0, 1), I(0, 2), I(1, 2);
  return pi;
}

MjcfInertial to_inertial(const InertialParameters& pi) {
  const double m = pi[0];
  if (!(m > 0) || !std::isfinite(m)) {
    throw ModelError("inertial parameters: mass " + std::to_string(m) + " is not positive.");
  }
  MjcfInertial out;
  out.mass = m;
  out.pos = pi.segment<3>(1) / m;
  const Eigen::Vector3d& c = out.pos;
  Eigen::Matrix3d I;
  I << pi[4], pi[7], pi[8], pi[7], pi[5], pi[9], pi[8], pi[9], pi[6];
  const Eigen::Matrix3d Ic =
      I - m * (c.squaredNorm() * Eigen::Matrix3d::Identity() - c * c.transpose());
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(Ic);
  const Eigen::Vector3d& d = eig.eigenvalues();  // increasing
  if (!(d[0] > 0) || d[0] + d[1] < d[2] * (1 - 1e-12)) {
    std::ostringstream s;
    s << "inertial parameters: principal moments " << d[0] << ", " << d[1] << ", " << d[2]
      << " about the centre of mass are not a rigid body's (each must be positive and at most "
         "the sum of the other two).";
    throw ModelError(s.str());
  }
  Eigen::Matrix3d R = eig.eigenvectors();
  if (R.determinant() < 0) R.col(2) = -R.col(2);  // a proper rotation
  out.quat = quat_from_mat(R);
  out.diaginertia = d;
  return out;
}

InertialParameters body_parameters(const Model& model, int body) {
  MjcfInertial inertial;
  inertial.mass = model.body_mass[body];
  inertial.pos = model.body_ipos[body];
  inertial.quat = model.body_iquat[body];
  inertial.diaginertia = model.body_inertia[body];
  return to_parameters(inertial);
}

void set_body_parameters(Model& model, int body, const InertialParameters& pi) {
  MjcfInertial inertial;
  try {
    inertial = to_inertial(pi);
  } catch (const ModelError& e) {
    throw ModelError("body '" + body_label(model, body) + "': " + e.what(), "body", body);
  }
  model.body_mass[body] = inertial.mass;
  model.body_ipos[body] = inertial.pos;
  model.body_iquat[body] = inertial.quat;
  model.body_inertia[body] = inertial.diaginertia;
}

int regressor_columns(const Model& model) {
  int gains = 0;  // counted, not listed: regressor() calls this and allocates nothing
  for (int a = 0; a < model.nu; ++a) gains += has_gain_column(model, a) ? 1 : 0;
  return inertial_columns(model) + 2 * model.nv + gains;
}

std::vector<std::string> regressor_names(const Model& model) {
  std::vector<std::string> names;
  names.reserve(static_cast<std::size_t>(regressor_columns(model)));
  for (int b = 1; b < model.nbody; ++b) {
    for (const char* p : kParameterNames) names.push_back(body_label(model, b) + "." + p);
  }
  for (int i = 0; i < model.nv; ++i) names.push_back(dof_label(model, i) + ".armature");
  for (int i = 0; i < model.nv; ++i) names.push_back(dof_label(model, i) + ".damping");
  for (const int a : gain_actuators(model)) names.push_back(actuator_label(model, a) + ".gain");
  return names;
}

Eigen::VectorXd model_parameters(const Model& model) {
  Eigen::VectorXd pi(regressor_columns(model));
  for (int b = 1; b < model.nbody; ++b) {
    pi.segment<kPerBody>(kPerBody * (b - 1)) = body_parameters(model, b);
  }
  const int tail = kPerBody * (model.nbody - 1);
  for (int i = 0; i < model.nv; ++i) {
    pi[tail + i] = model.dof_armature[i];
    pi[tail + model.nv + i] = model.dof_damping[i];
  }
  int column = tail + 2 * model.nv;
  for (const int a : gain_actuators(model)) pi[column++] = model.actuator_gainprm[a][0];
  return pi;
}

void set_model_parameters(Model& model, const Eigen::Ref<const Eigen::VectorXd>& pi) {
  if (pi.size() != regressor_columns(model)) {
    throw StateError("set_model_parameters: " + std::to_string(pi.size()) +
                     " parameters, the model has " + std::to_string(regressor_columns(model)) +
                     ".");
  }
  Model edited = model;  // nothing half-written if a body is not physical
  for (int b = 1; b < edited.nbody; ++b) {
    const InertialParameters pb = pi.segment<kPerBody>(kPerBody * (b - 1));
    // a body without mass stays without mass (a frame, or a body whose mass is below others)
    if (pb.isZero(0) && edited.body_mass[b] == 0) continue;
    set_body_parameters(edited, b, pb);
  }
  const int tail = kPerBody * (edited.nbody - 1);
  for (int i = 0; i < edited.nv; ++i) {
    edited.dof_armature[i] = pi[tail + i];
    edited.dof_damping[i] = pi[tail + edited.nv + i];
  }
  int column = tail + 2 * edited.nv;
  for (const int a : gain_actuators(model)) {
    const double gain = pi[column++];
    if (!std::isfinite(gain)) {
      throw ModelError("actuator '" + actuator_label(model, a) + "': gain " + std::to_string(gain) +
                       " is not finite.");
    }
    // a servo's tied bias entry follows its gain (read from the model before the edit)
    const int tied = gain_tied_bias(model, a);
    edited.actuator_gainprm[a][0] = gain;
    if (tied > 0) edited.actuator_biasprm[a][static_cast<std::size_t>(tied)] = -gain;
  }
  set_const(edited);
  model = std::move(edited);
}

void regressor(const Model& model, Data& data, const Eigen::Ref<const Eigen::VectorXd>& qacc,
               Eigen::Ref<Eigen::MatrixXd> Y) {
  if (qacc.size() != model.nv || Y.rows() != model.nv || Y.cols() != regressor_columns(model) ||
      data.nv != model.nv) {
    throw StateError("regressor: qacc must have nv elements and Y be nv x regressor_columns.");
  }
  Y.setZero();
  // velocities and accelerations of every body (RNEA's forward pass; gravity as a_0 = -g), kept
  // in Data's RNEA workspace
  auto& v = data.cvel;
  auto& a = data.work.cacc;
  forward_pass(model, data, data.qvel.data(), qacc.data(), true, v, a, nullptr, nullptr);
  for (int b = 1; b < model.nbody; ++b) {
    const Motion& vb = v[b];
    const Motion& ab = a[b];

    // body b's block: the dofs that support it, seen in its frame
    const Eigen::Vector3d& c = data.subtree_com[model.body_rootid[b]];
    const Eigen::Vector3d& p = data.xpos[b];
    const Mat3& R = data.xmat[b];
    const Motion vB = to_body_frame(vb, c, p, R), aB = to_body_frame(ab, c, p, R);
    Eigen::Matrix<double, 6, kPerBody> F;  // net force of each unit parameter
    for (int k = 0; k < kPerBody; ++k) {
      const RigidInertia E = unit_inertia(k);
      F.col(k) = E * aB + cross_force(vB, E * vB);
    }
    int top = b;  // the nearest body at or above b that has dofs
    while (top > 0 && model.body_dofnum[top] == 0) top = model.body_parentid[top];
    if (top == 0) continue;
    for (int i = model.body_dofadr[top] + model.body_dofnum[top] - 1; i >= 0;
         i = model.dof_parentid[i]) {
      const Motion S = to_body_frame(data.cdof[i], c, p, R);
      Y.block<1, kPerBody>(i, kPerBody * (b - 1)) = S.transpose() * F;
    }
  }
  const int tail = kPerBody * (model.nbody - 1);
  for (int i = 0; i < model.nv; ++i) {
    Y(i, tail + i) = qacc[i];                  // armature: part of M
    Y(i, tail + model.nv + i) = data.qvel[i];  // damping: the motor supplies + b qvel
  }
  // gains: the actuator's gain-scaled torque, moved to the parameter side (hence the sign)
  int column = tail + 2 * model.nv;
  for (int u = 0; u < model.nu; ++u) {
    if (!has_gain_column(model, u)) continue;
    const int j = model.actuator_trnid[u];
    const int q = model.jnt_qposadr[j], d = model.jnt_dofadr[j];
    Y(d, column++) = -model.actuator_gear[u][0] *
                     actuator_gain_basis(model, u, data.ctrl[u], data.qpos[q], data.qvel[d]);
  }
}

Eigen::MatrixXd BaseParameters::base_regressor(const Eigen::Ref<const Eigen::MatrixXd>& Y) const {
  Eigen::MatrixXd out(Y.rows(), rank);
  for (int k = 0; k < rank; ++k) out.col(k) = Y.col(base[static_cast<std::size_t>(k)]);
  return out;
}

BaseParameters base_parameters(const Model& model, int samples, unsigned long long seed) {
  return base_parameters_with_gains(model, gain_actuators(model), samples, seed);
}

BaseParameters base_parameters_with_gains(const Model& model, const std::vector<int>& gains,
                                          int samples, unsigned long long seed) {
  for (const int a : gains) {
    if (a < 0 || a >= model.nu || !has_gain_column(model, a)) {
      throw StateError("base_parameters: actuator " + std::to_string(a) +
                       " has no gain column (only fixed-gain actuators have one).");
    }
  }
  const int n = regressor_columns(model);
  const int nv = model.nv;
  if (model.nq != model.nv) {
    throw ModelError(
        "base parameters: the model has ball or free joints; lever identifies "
        "robots of hinge and slide joints so far.");
  }
  std::mt19937_64 rng(seed);
  const auto uniform = [&](double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(rng);
  };

  // the regressor stacked over random states
  Data data(model);
  Eigen::MatrixXd W(static_cast<Eigen::Index>(samples) * nv, n);
  Eigen::VectorXd qacc(nv);
  for (int s = 0; s < samples; ++s) {
    for (int j = 0; j < model.njnt; ++j) {
      const int q = model.jnt_qposadr[j];
      data.qpos[q] = model.jnt_limited[j] ? uniform(model.jnt_range[j][0], model.jnt_range[j][1])
                                          : model.qpos0[q] + uniform(-3, 3);
    }
    for (int i = 0; i < nv; ++i) {
      data.qvel[i] = uniform(-2, 2);
      qacc[i] = uniform(-10, 10);
    }
    for (const int a : gains) {
      const auto& range = model.actuator_ctrlrange[a];
      data.ctrl[a] =
          model.actuator_ctrllimited[a] ? uniform(range[0], range[1]) : uniform(-1.0, 1.0);
    }
    kinematics(model, data);
    regressor(model, data, qacc, W.middleRows(static_cast<Eigen::Index>(s) * nv, nv));
  }

  // the gain columns of actuators whose gain is known are left out (zero: unidentifiable)
  const std::vector<int> fixed = gain_actuators(model);
  for (std::size_t g = 0; g < fixed.size(); ++g) {
    if (std::find(gains.begin(), gains.end(), fixed[g]) != gains.end()) continue;
    W.col(n - static_cast<int>(fixed.size()) + static_cast<int>(g)).setZero();
  }

  // W P = Q R: the first `rank` pivoted columns span the rest, W_D = W_B beta
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(W);
  const Eigen::MatrixXd R = qr.matrixR().triangularView<Eigen::Upper>();
  const double largest = n > 0 ? std::abs(R(0, 0)) : 0.0;
  int rank = 0;
  while (rank < std::min<Eigen::Index>(W.rows(), n) && std::abs(R(rank, rank)) > 1e-9 * largest) {
    ++rank;
  }
  const auto& perm = qr.colsPermutation().indices();
  const Eigen::MatrixXd beta = R.topLeftCorner(rank, rank)
                                   .triangularView<Eigen::Upper>()
                                   .solve(R.topRightCorner(rank, n - rank));

  BaseParameters out;
  out.rank = rank;
  out.K = Eigen::MatrixXd::Zero(rank, n);
  const std::vector<std::string> names = regressor_names(model);
  for (int k = 0; k < rank; ++k) {
    out.base.push_back(perm[k]);
    out.K(k, perm[k]) = 1.0;
  }
  for (int d = 0; d < n - rank; ++d) {
    const int column = perm[rank + d];
    bool used = false;
    for (int k = 0; k < rank; ++k) {
      const double coefficient = beta(k, d);
      if (std::abs(coefficient) < 1e-10) continue;  // a structural zero, up to rounding
      out.K(k, column) = coefficient;
      used = true;
    }
    if (!used) out.unidentifiable.push_back(column);
  }
  std::sort(out.unidentifiable.begin(), out.unidentifiable.end());
  for (int k = 0; k < rank; ++k) {
    std::ostringstream s;
    s.precision(6);
    s << names[static_cast<std::size_t>(out.base[static_cast<std::size_t>(k)])];
    for (int c = 0; c < n; ++c) {
      const double coefficient = out.K(k, c);
      if (c == out.base[static_cast<std::size_t>(k)] || coefficient == 0.0) continue;
      s << (coefficient < 0 ? " - " : " + ");
      if (std::abs(coefficient) != 1.0) s << std::abs(coefficient) << " ";
      s << names[static_cast<std::size_t>(c)];
    }
    out.names.push_back(s.str());
  }
  return out;
}

}  // namespace lever
