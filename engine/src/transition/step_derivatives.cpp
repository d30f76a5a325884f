// Analytic derivatives of forward dynamics (the chain rule through M^-1, the passive forces, the
// actuators with their gains, biases and activation dynamics, and the limit rows; contacts' rows in
// contact_rows.cpp) and of the step on the state [dq; qvel; act] (Euler with implicit damping,
// RK4, MuJoCo 2.2.2's implicit), on the inverse-dynamics derivatives of
// derivatives/inverse_dynamics.cpp, with the check that the rows' active set holds over the step.
// docs/derivatives.md derives each formula.
//
// Ball and free joints, in qpos's tangent space (q -> q exp(dq)): the step's position update
// qpos (+) h w contributes exp(-h [w]) and SO(3)'s right Jacobian Jr(h w) on a turn's rows, and a
// ball's spring -k log(ref^-1 q) the inverse right Jacobian.
#include <lever/collision.hpp>
#include <lever/derivatives.hpp>
#include <lever/dynamics.hpp>
#include <lever/error.hpp>
#include <lever/fields.hpp>
#include <lever/forward.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "basics/basics.hpp"
#include "constraint/constraint_room.hpp"
#include "derivatives/derivatives_room.hpp"
#include "pipeline/pipeline.hpp"
#include "smooth/recursion.hpp"
#include "smooth/smooth.hpp"
#include "transition/transition.hpp"

namespace lever {

namespace {

using detail::check_derivative_sizes;
using detail::inertia_columns;
using detail::kMinVal;  // the floor of a limit row's R
using detail::polar_derivatives_into;
using detail::rnea_derivatives_into;
using detail::rotation_block;

// ---- ball and free joints in tangent space ------------------------------------------------------
// A tangent coordinate of a ball (or of a free joint's rotation) turns the body about its own axes:
// qpos' = qpos exp(dq) (integrate_pos). SO(3)'s exponential and its right Jacobian Jr, with
// exp(phi + d) = exp(phi) exp(Jr(phi) d), and Jr's inverse, for phi = theta u.

// exp([phi]): the rotation by the rotation vector phi (Rodrigues).
Eigen::Matrix3d rotation_of(const Eigen::Vector3d& phi) {
  const double theta = phi.norm();
  const Eigen::Matrix3d K = skew(phi);
  // sin(t) / t and (1 - cos(t)) / t^2, by their series below 1e-4 (error below 1e-17)
  const double a = theta < 1e-4 ? 1 - theta * theta / 6 : std::sin(theta) / theta;
  const double b =
      theta < 1e-4 ? 0.5 - theta * theta / 24 : (1 - std::cos(theta)) / (theta * theta);
  return Eigen::Matrix3d::Identity() + a * K + b * K * K;
}

// SO(3)'s right Jacobian Jr(phi) = I - (1 - cos t) / t^2 [phi] + (t - sin t) / t^3 [phi]^2.
Eigen::Matrix3d right_jacobian(const Eigen::Vector3d& phi) {
  const double theta = phi.norm();
  const Eigen::Matrix3d K = skew(phi);
  const double b =
      theta < 1e-4 ? 0.5 - theta * theta / 24 : (1 - std::cos(theta)) / (theta * theta);
  const double c = theta < 1e-4 ? 1.0 / 6 - theta * theta / 120
                                : (theta - std::sin(theta)) / (theta * theta * theta);
  return Eigen::Matrix3d::Identity() - b * K + c * K * K;
}

// Jr(phi)^-1 = I + [phi] / 2 + (1 / t^2 - (1 + cos t) / (2 t sin t)) [phi]^2 (|t| < pi).
Eigen::Matrix3d inverse_right_jacobian(const Eigen::Vector3d& phi) {
  const double theta = phi.norm();
  const Eigen::Matrix3d K = skew(phi);
  const double c =
      theta < 1e-4 ? 1.0 / 12 + theta * theta / 720
                   : 1 / (theta * theta) - (1 + std::cos(theta)) / (2 * theta * std::sin(theta));
  return Eigen::Matrix3d::Identity() + 0.5 * K + c * K * K;
}

// The position update qpos' = qpos (+) h velocity in tangent space, applied to the rows of two
// Jacobians: rows = [d qpos' / d y] for an input y, given rows = X + [identity] d qpos / d y
// computed as if every coordinate added (hinge and slide: d qpos' = d qpos + h d velocity, X the
// second term), with the identity in `state_rows` (d / d x) and not in `control_rows` (d / d ctrl).
// A rotation block instead has d qpos' = exp(-h [w]) d qpos + Jr(h w) h d w: its three rows
// become Jr X, plus exp(-h [w]) in its own columns where the identity was (Jr and the rotation
// made once for both). Hinges, slides and a free joint's translation keep their rows.
void through_position_update(const Model& model, const double* velocity, double h,
                             Eigen::Ref<Eigen::MatrixXd> state_rows,
                             Eigen::Ref<Eigen::MatrixXd> control_rows) {
  if (model.nq == model.nv) return;
  // rows = Jr rows, column by column: no temporary
  const auto turn = [](const Eigen::Matrix3d& Jr, auto&& block_rows) {
    for (Eigen::Index c = 0; c < block_rows.cols(); ++c) {
      const Eigen::Vector3d x = block_rows.col(c);
      block_rows.col(c) = Jr * x;
    }
  };
  for (int j = 0; j < model.njnt; ++j) {
    const int r = rotation_block(model, j);
    if (r < 0) continue;
    const Eigen::Vector3d phi = h * Eigen::Vector3d(velocity[r], velocity[r + 1], velocity[r + 2]);
    const Eigen::Matrix3d Jr = right_jacobian(phi);
    auto state_block = state_rows.middleRows<3>(r);
    state_block.middleCols<3>(r) -= Eigen::Matrix3d::Identity();
    turn(Jr, state_block);
    state_block.middleCols<3>(r) += rotation_of(phi).transpose();
    turn(Jr, control_rows.middleRows<3>(r));
  }
}

// X += b r^T r for a row r of n numbers (a tendon's Jacobian, a tendon actuator's moment): the
// derivative of the force r^T f(r x) along the row, f' = b.
void add_row_outer_product(const double* r, int n, double b, Eigen::MatrixXd& X) {
  if (b == 0) return;
  for (int j = 0; j < n; ++j) {
    if (r[j] == 0.0) continue;
    const double a = b * r[j];
    for (int i = 0; i < n; ++i) X(i, j) += r[i] * a;
  }
}

// q exp(dq).
void quaternion_springs(const Model& model, const Data& data, Derivatives::Workspace& w) {
  for (int j = 0; j < model.njnt; ++j) {
    const int r = rotation_block(model, j);
    if (r < 0) continue;
    const int d = model.jnt_dofadr[j];
    const double k = model.jnt_stiffness[j];
    w.rhs_q(d, d) += k;  // undo the loop's hinge spring on the first dof
    for (int c = d; c < r; ++c) w.rhs_q(c, c) -= k;
    for (int c = d + 1; c < r + 3; ++c) w.rhs_v(c, c) -= model.dof_damping[c];
    if (k == 0) continue;
    const int qadr = model.jnt_qposadr[j] + (r - d);
    const Eigen::Vector3d turn =
        detail::quat_difference(&data.qpos[qadr], &model.qpos_spring[qadr]);
    w.rhs_q.block<3, 3>(r, r) -= k * inverse_right_jacobian(turn);
  }
}

// Site actuator a's moment and length differentiated: w.moment_change(i, c) = d moment_i / d q_c
// and w.length_gradient[c] = d length / d q_c. With p the site, r the reference site (if any),
// s_i and r_i whether dof i moves the site's body and the reference's, j_i(x) = u_i + w_i x (x - O)
// dof i's velocity at x, and f = R gear[0-2], t = R gear[3-5] the wrench in the world (R the
// reference's frame, or the site's own without one), the moment is (MuJoCo 2.2.2's)
//   moment_i = (s_i j_i(p) - r_i j_i(r)) . f + (s_i - r_i) w_i . t.
// Moving dof c turns the axes of the dofs it carries and moves the bodies it moves rigidly, so
//   d j_i(x) / d q_c = [c carries i] (w_c x j_i(x) - w_i x j_c(x)) + w_i x j_c(x)  (c moves x)
//   d w_i / d q_c    = [c carries i] w_c x w_i,   d f = w_c x f,   d t = w_c x t  (c moves R)
// The length (a reference site's alone; without one it is 0) is
//   length = gear[0-2] . R^T (p - r) + gear[3-5] . phi,   phi = log(q_r^-1 q_p),
// with MuJoCo's quaternions q_p = site_quat (x) xquat of the site's body (that order), q_r the
// reference's. Turning a body by w_c dq turns q_p by site_quat w_c dq (on the left), so phi moves by
// Jl^-1(phi) R(q_r)^T (s_c R(site_quat) w_c - r_c R(ref site_quat) w_c), Jl^-1 SO(3)'s inverse
// left Jacobian; and d (R^T (p - r)) = R^T (s_c j_c(p) - r_c j_c(r) - r_c w_c x (p - r)).
// (w.tangent_motion and w.segment_motion serve as scratch.)
void site_transmission_change(const Model& model, const Data& data, int a,
                              Derivatives::Workspace& w) {
  using Vec3 = Eigen::Vector3d;
  const int nv = model.nv;
  Eigen::MatrixXd& G = w.moment_change;
  G.setZero();
  w.length_gradient.setZero();
  const int site = model.actuator_trnid[a][0], ref = model.actuator_trnid[a][1];
  const auto& gear = model.actuator_gear[a];
  const Vec3 gear_force(gear[0], gear[1], gear[2]), gear_torque(gear[3], gear[4], gear[5]);
  const Mat3& R = data.site_xmat[ref >= 0 ? ref : site];
  const Vec3 f = R * gear_force, t = R * gear_torque;
  std::vector<char>& on_site = w.moves1;
  std::vector<char>& on_ref = w.moves2;
  detail::dofs_moving(model, model.site_bodyid[site], on_site);
  if (ref >= 0) {
    detail::dofs_moving(model, model.site_bodyid[ref], on_ref);
  } else {
    std::fill(on_ref.begin(), on_ref.end(), 0);
  }
  const std::vector<char>& on_frame = ref >= 0 ? on_ref : on_site;  // the dofs that turn R
  Vec3* const j_site = w.equality_point_velocity.data();
  Vec3* const j_ref = j_site + nv;
  for (int i = 0; i < nv; ++i) {
    if (on_site[i]) j_site[i] = detail::point_velocity(model, data, i, data.site_xpos[site]);
    if (on_ref[i]) j_ref[i] = detail::point_velocity(model, data, i, data.site_xpos[ref]);
  }
  // With a_i = j_i(x) x f for each dof i that moves x, e_i = w_i x t, and the triple product's
  // turns, (w_i x j_c) . f = w_i . a_c, (w_c x j_i) . f = w_c . a_i, j_i . (w_c x f) = -w_c . a_i,
  // (w_c x w_i) . t = w_c . e_i and w_i . (w_c x t) = -w_c . e_i: every term of G(i, c) a dot
  // product of vectors made once per dof
  Vec3* const a_site = w.tangent_motion.data();
  Vec3* const a_ref = a_site + nv;
  Vec3* const e = w.segment_motion.data();
  for (int i = 0; i < nv; ++i) {
    if (on_site[i]) a_site[i] = j_site[i].cross(f);
    if (on_ref[i]) a_ref[i] = j_ref[i].cross(f);
    e[i] = data.cdof[i].head<3>().cross(t);
  }
  for (int c = 0; c < nv; ++c) {
    if (!on_site[c] && !on_ref[c]) continue;
    const Vec3 wc = data.cdof[c].head<3>();
    const double frame_turns = on_frame[c] ? 1.0 : 0.0;  // c turns f and t
    for (int i = 0; i < nv; ++i) {
      if (!on_site[i] && !on_ref[i]) continue;
      const Vec3 wi = data.cdof[i].head<3>();
      const double carried = w.carries[static_cast<std::size_t>(c * nv + i)] != 0 ? 1.0 : 0.0;
      // d j_i(x) / d q_c . f = [c moves x] (w_i . a_c + carried (w_c . a_i - w_i . a_c)), and
      // j_i(x) . d f = -frame_turns w_c . a_i
      const auto point_term = [&](const Vec3* a_point, bool c_moves_point) {
        const double wc_ai = wc.dot(a_point[i]);
        double g = -frame_turns * wc_ai;
        if (c_moves_point) g += (1 - carried) * wi.dot(a_point[c]) + carried * wc_ai;
        return g;
      };
      double g = 0.0;
      if (on_site[i]) g += point_term(a_site, on_site[c] != 0);
      if (on_ref[i]) g -= point_term(a_ref, on_ref[c] != 0);
      const int turn = on_site[i] - on_ref[i];
      if (turn != 0) g += turn * (carried - frame_turns) * wc.dot(e[i]);
      G(i, c) = g;
    }
  }
  if (ref < 0) return;  // no length
  const Vec3 offset = data.site_xpos[site] - data.site_xpos[ref];
  const Quat q_site = quat_mul(model.site_quat[site], data.xquat[model.site_bodyid[site]]);
  const Quat q_ref = quat_mul(model.site_quat[ref], data.xquat[model.site_bodyid[ref]]);
  const Vec3 phi = detail::quat_difference(q_site.data(), q_ref.data());
  // rho . (R(q_r)^T e) = (R(q_r) Jl^-1(phi)^T gear_torque) . e, with Jl^-1(phi)^T = Jr^-1(phi)
  const Vec3 rho = detail::quat_rotate(q_ref, inverse_right_jacobian(phi) * gear_torque);
  const auto conj = [](const Quat& q) { return Quat(q[0], -q[1], -q[2], -q[3]); };
  const Vec3 rho_site = detail::quat_rotate(conj(model.site_quat[site]), rho);
  const Vec3 rho_ref = detail::quat_rotate(conj(model.site_quat[ref]), rho);
  for (int c = 0; c < nv; ++c) {
    const Vec3 wc = data.cdof[c].head<3>();
    Vec3 dx = Vec3::Zero();  // d (p - r) - w_c x (p - r) for the reference's turn
    double d_turn = 0.0;
    if (on_site[c]) {
      dx += j_site[c];
      d_turn += rho_site.dot(wc);
    }
    if (on_ref[c]) {
      dx -= j_ref[c] + wc.cross(offset);
      d_turn -= rho_ref.dot(wc);
    }
    w.length_gradient[c] = f.dot(dx) + d_turn;
  }
}

// An actuator's gain and the slopes of its force in its length and velocity at a given input
// (the clamped ctrl, or the activation): force = gain input + bias.
struct ActuatorSlopes {
  double gain = 0, per_length = 0, per_velocity = 0;
};

ActuatorSlopes actuator_slopes(const Model& model, const Data& data, int a, double input) {
  ActuatorSlopes s;
  const double length = data.actuator_length[a], velocity = data.actuator_velocity[a];
  const bool muscle_gain = model.actuator_gaintype[a] == GainType::kMuscle;
  const bool muscle_bias = model.actuator_biastype[a] == BiasType::kMuscle;
  MusclePartials muscle;
  if (muscle_gain || muscle_bias) {
    muscle = muscle_partials(length, velocity, model.actuator_lengthrange[a],
                             model.actuator_acc0[a], model.actuator_gainprm[a].data(),
                             model.actuator_biasprm[a].data());
  }
  s.gain = actuator_gain(model, a, length, velocity);
  if (model.actuator_gaintype[a] == GainType::kAffine) {
    s.per_length += model.actuator_gainprm[a][1] * input;
    s.per_velocity += model.actuator_gainprm[a][2] * input;
  } else if (muscle_gain) {
    s.per_length += muscle.gain_per_length * input;
    s.per_velocity += muscle.gain_per_velocity * input;
  }
  if (model.actuator_biastype[a] == BiasType::kAffine) {
    s.per_length += model.actuator_biasprm[a][1];
    s.per_velocity += model.actuator_biasprm[a][2];
  } else if (muscle_bias) {
    s.per_length += muscle.bias_per_length;
  }
  return s;
}

// d act_dot / d act and d act_dot / d ctrl of stateful actuator a into w.act_rate_*, at its
// clamped control u (the ctrl term 0 where the clamp binds: u is then constant): an integrator's
// act_dot = u, a filter's (u - act) / tau, a muscle's muscle_activation_rate.
void activation_rate_partials(const Model& model, const Data& data, int a, double u,
                              bool ctrl_clamped, Derivatives::Workspace& w) {
  const int k = a - (model.nu - model.na);
  const auto& prm = model.actuator_dynprm[a];
  double per_ctrl = 0.0, per_act = 0.0;
  switch (model.actuator_dyntype[a]) {
    case DynType::kIntegrator: per_ctrl = 1.0; break;
    case DynType::kFilter: {
      const double tau = std::max(kMinVal, prm[0]);
      per_ctrl = 1 / tau;
      per_act = -1 / tau;
      break;
    }
    case DynType::kMuscle:
      muscle_activation_rate_partials(u, data.act[k], prm.data(), per_ctrl, per_act);
      break;
    case DynType::kNone:
    case DynType::kUser: break;  // refused before (refuse_uncovered): a callback's rate
  }
  w.act_rate_per_act[k] = per_act;
  w.act_rate_per_ctrl[k] = ctrl_clamped ? 0.0 : per_ctrl;
}

// The explicit force terms of the smooth dynamics, minus the inverse-dynamics derivatives:
// rhs = d (qfrc_passive + qfrc_actuator) / d x - d rnea / d x, for x = qpos, qvel, ctrl.
void smooth_rhs(const Model& model, const Data& data, const Eigen::MatrixXd& dtau_dq,
                const Eigen::MatrixXd& dtau_dv, Derivatives::Workspace& w) {
  w.rhs_q = -dtau_dq;
  w.rhs_v = -dtau_dv;
  if (!model.opt.disabled(kDisablePassive)) {  // <flag passive="disable">: no springs, dampers
    for (int j = 0; j < model.njnt; ++j) {
      const int d = model.jnt_dofadr[j];
      w.rhs_q(d, d) -= model.jnt_stiffness[j];  // spring: -k (q - springref)
      w.rhs_v(d, d) -= model.dof_damping[d];    // damper: -b qd
    }
    if (model.nq != model.nv) quaternion_springs(model, data, w);
    // a tendon's spring-damper f = -k (L - lengthspring) - b v along its Jacobian J (d L = J dq,
    // v = J qd), carried to the dofs as J^T f: -k J^T J and -b J^T J; a spatial tendon's J moves
    // too (T = d J / d q): + T f in qpos, and -b J (T^T qd)^T through the velocity
    for (int t = 0; t < model.ntendon; ++t) {
      const double k = model.tendon_stiffness[t], b = model.tendon_damping[t];
      if (k == 0 && b == 0) continue;
      const double* J = data.ten_J.row(t).data();
      add_row_outer_product(J, model.nv, -k, w.rhs_q);
      add_row_outer_product(J, model.nv, -b, w.rhs_v);
      if (!detail::is_spatial_tendon(model, t)) continue;
      detail::spatial_tendon_change(model, data, t, w);
      const Eigen::MatrixXd& T = w.tendon_change;
      const double f = -k * (data.ten_length[t] - model.tendon_lengthspring[t]) -
                       b * data.ten_velocity[t];
      w.rhs_q += f * T;
      if (b == 0) continue;
      for (int c = 0; c < model.nv; ++c) {
        const double dv = T.col(c).dot(data.qvel);
        for (int i = 0; i < model.nv; ++i) w.rhs_q(i, c) -= b * J[i] * dv;
      }
    }
  }

  // actuators: force = clamp_f(gain input + bias), input = clamp_c(ctrl) (stateless) or act
  // (stateful), gain = p0 + p1 length + p2 velocity (affine; p0 when fixed) or a muscle's
  // -F FL(length) FV(velocity), bias = b0 + b1 length + b2 velocity (affine; 0 when none) or a
  // muscle's -F FP(length), with length = gear q and velocity = gear qd on the actuator's dof,
  // which gets gear force. Where the force clamp binds the actuator passes on nothing; where the
  // ctrl clamp binds it has no sensitivity to ctrl but keeps its length and velocity terms. A
  // stateful actuator's ctrl acts through act_dot alone (activation_rate_partials).
  w.rhs_u.setZero();
  w.act_rate_per_act.setZero();
  w.act_rate_per_ctrl.setZero();
  // <flag actuation="disable">: no actuator forces; clampctrl="disable": ctrl as it is
  const int actuators = model.opt.disabled(kDisableActuation) ? 0 : model.nu;
  const bool clamp_ctrl = !model.opt.disabled(kDisableClampctrl);
  const int first_stateful = model.nu - model.na;  // actuator a's activation: act[a - this]
  bool bad = false;  // one bad control zeroes every control (actuation's kBadCtrl); bias stays
  for (int a = 0; a < actuators; ++a) bad = bad || is_bad(data.ctrl[a]);
  for (int a = 0; a < actuators; ++a) {
    double u = bad ? 0.0 : data.ctrl[a];
    bool ctrl_clamped = bad;
    if (!bad && clamp_ctrl && model.actuator_ctrllimited[a]) {
      const auto& range = model.actuator_ctrlrange[a];
      ctrl_clamped = u < range[0] || u > range[1];
      u = std::clamp(u, range[0], range[1]);
    }
    const bool stateful = a >= first_stateful;
    if (stateful) activation_rate_partials(model, data, a, u, ctrl_clamped, w);
    // what the gain multiplies, and the column of rhs_u that moves it (-1: nothing does)
    const double input = stateful ? data.act[a - first_stateful] : u;
    const int input_column =
        stateful ? model.nu + (a - first_stateful) : (ctrl_clamped ? -1 : a);
    const ActuatorSlopes slope = actuator_slopes(model, data, a, input);
    // in actuation()'s order, so the clamp test sees the same number
    const double force =
        input * slope.gain + actuator_bias(model, a, data.actuator_length[a],
                                           data.actuator_velocity[a]);
    bool force_clamped = false;
    if (model.actuator_forcelimited[a]) {
      const auto& range = model.actuator_forcerange[a];
      force_clamped = force < range[0] || force > range[1];
    }
    const double per_length = slope.per_length, per_velocity = slope.per_velocity;
    if (model.actuator_trntype[a] == TransmissionType::kSite) {
      // a site: velocity = m . qvel, qfrc = m force, m turns with the site and its reference
      // (G = d m / d q), and the length (a reference site's) has its own gradient, which is not m
      // (site_transmission_change): d qfrc / d q = G force + m (per_length d length / d q +
      // per_velocity G^T qvel) (the first even where the force is clamped),
      // d qfrc / d qvel = m per_velocity m^T
      site_transmission_change(model, data, a, w);
      const Eigen::MatrixXd& G = w.moment_change;
      const double* m = data.actuator_moment.row(a).data();
      w.rhs_q += data.actuator_force[a] * G;
      if (force_clamped) continue;
      for (int c = 0; c < model.nv; ++c) {
        const double dforce = per_length * w.length_gradient[c] +
                              per_velocity * G.col(c).dot(data.qvel);
        for (int i = 0; i < model.nv; ++i) w.rhs_q(i, c) += m[i] * dforce;
      }
      add_row_outer_product(m, model.nv, per_velocity, w.rhs_v);
      if (input_column >= 0) {
        for (int i = 0; i < model.nv; ++i) w.rhs_u(i, input_column) = m[i] * slope.gain;
      }
      continue;
    }
    if (model.actuator_trntype[a] == TransmissionType::kTendon) {
      // length = gear L, so d length / d q = gear J = the moment m, and qfrc = m force:
      // m^T per_length m, m^T per_velocity m, m gain; a spatial tendon's m moves too
      // (G = gear d J / d q): + G force (even where the force is clamped) and
      // m per_velocity (G^T qvel)^T
      const double* m = data.actuator_moment.row(a).data();
      const int t = model.actuator_trnid[a][0];
      if (detail::is_spatial_tendon(model, t)) {
        detail::spatial_tendon_change(model, data, t, w);
        const double gear = model.actuator_gear[a][0];
        w.rhs_q += (gear * data.actuator_force[a]) * w.tendon_change;
        if (force_clamped) continue;
        for (int c = 0; c < model.nv; ++c) {
          const double dvelocity = per_velocity * gear * w.tendon_change.col(c).dot(data.qvel);
          for (int i = 0; i < model.nv; ++i) w.rhs_q(i, c) += m[i] * dvelocity;
        }
      }
      if (force_clamped) continue;
      add_row_outer_product(m, model.nv, per_length, w.rhs_q);
      add_row_outer_product(m, model.nv, per_velocity, w.rhs_v);
      if (input_column >= 0) {
        for (int i = 0; i < model.nv; ++i) w.rhs_u(i, input_column) = m[i] * slope.gain;
      }
      continue;
    }
    if (force_clamped) continue;  // a constant moment: no sensitivity
    const double gear = model.actuator_gear[a][0];
    const int dof = actuator_scalar_dof(model, a);  // >= 0: refuse_uncovered checked
    w.rhs_q(dof, dof) += gear * per_length * gear;
    w.rhs_v(dof, dof) += gear * per_velocity * gear;
    if (input_column >= 0) w.rhs_u(dof, input_column) = gear * slope.gain;
  }
}

// The limit rows with their active set S held fixed. Forward dynamics satisfies
//   M qacc = f_smooth + J_S^T f_S,    J_S qacc + R_S f_S = aref_S
// so, with G = M^-1 (d f_smooth - d M qacc) already in dqacc (one column per input),
//   (J M^-1 J^T + R)_SS df_S = d aref_S - dR_S f_S - J_S G,   dqacc = G + M^-1 J_S^T df_S.
// aref = -B vel - K imp (pos - margin) and R = (1 - imp) invweight0 / imp depend on qpos through
// the impedance, and aref on qvel through vel; neither depends on ctrl.
void limit_rows(const Model& model, Data& data, Derivatives& deriv) {
  auto& w = deriv.work;
  deriv.dconstraint_dq.setZero();
  deriv.dconstraint_dv.setZero();
  deriv.dconstraint_du.setZero();
  deriv.dconstraint_dact.setZero();
  int n = 0;
  for (int r = 0; r < data.nefc; ++r) {
    if (data.efc_state[r] == ConstraintState::kActive) w.rows[n++] = r;
  }
  w.active_rows = n;
  if (n == 0) return;

  // M^-1 J^T and the Cholesky factor of (J M^-1 J^T + R)_SS (J's row r is sign_r e_dof_r)
  for (int k = 0; k < n; ++k) {
    auto column = w.MinvJ.col(k);
    column.setZero();
    column[data.efc_dof[w.rows[k]]] = data.efc_sign[w.rows[k]];
    solve_mass(model, data, column);
  }
  for (int k = 0; k < n; ++k) {
    const int rk = w.rows[k];
    for (int l = 0; l <= k; ++l) {
      double s = data.efc_sign[rk] * w.MinvJ(data.efc_dof[rk], l);
      if (l == k) s += data.efc_R[rk];
      for (int c = 0; c < l; ++c) s -= w.AR(k, c) * w.AR(l, c);
      w.AR(k, l) = l == k ? std::sqrt(s) : s / w.AR(l, l);
    }
  }

  // d aref / d q_dof, d R / d q_dof, d aref / d qd_dof of each active row (zero elsewhere)
  const auto solve_column = [&](Eigen::MatrixXd& dqacc, Eigen::MatrixXd& dconstraint, int c,
                                const double* drhs_dx) {
    Eigen::VectorXd& df = w.col;
    for (int k = 0; k < n; ++k) {
      const int r = w.rows[k];
      df[k] =
          (drhs_dx != nullptr ? drhs_dx[k] : 0.0) - data.efc_sign[r] * dqacc(data.efc_dof[r], c);
    }
    for (int k = 0; k < n; ++k) {  // L y = rhs, then L^T df = y
      for (int l = 0; l < k; ++l) df[k] -= w.AR(k, l) * df[l];
      df[k] /= w.AR(k, k);
    }
    for (int k = n - 1; k >= 0; --k) {
      for (int l = k + 1; l < n; ++l) df[k] -= w.AR(l, k) * df[l];
      df[k] /= w.AR(k, k);
    }
    for (int k = 0; k < n; ++k) {
      const int r = w.rows[k];
      dqacc.col(c) += w.MinvJ.col(k) * df[k];
      dconstraint(data.efc_dof[r], c) += data.efc_sign[r] * df[k];
    }
  };

  std::array<double, 2> solref;
  std::array<double, 5> solimp;
  for (int c = 0; c < model.nv; ++c) {
    for (int k = 0; k < n; ++k) {
      const int r = w.rows[k];
      w.drhs_q[k] = w.drhs_v[k] = 0.0;
      if (data.efc_dof[r] != c) continue;
      const double sign = data.efc_sign[r];  // d pos / d q_dof: pos = sign (q - stop)
      limit_parameters(model, data.efc_id[r], solref, solimp);
      double slope = 0.0;
      const double imp = impedance(solimp, data.efc_pos[r], data.efc_margin[r], &slope);
      const double dimp_dq = slope * sign;
      const double daref_dq =
          -data.efc_K[r] * (dimp_dq * (data.efc_pos[r] - data.efc_margin[r]) + imp * sign);
      const double invweight = model.dof_invweight0[c];
      const bool R_floored = (1 - imp) * invweight / imp < kMinVal;  // R = mjMINVAL: constant
      const double dR_dq = R_floored ? 0.0 : -invweight / (imp * imp) * dimp_dq;
      w.drhs_q[k] = daref_dq - dR_dq * data.efc_force[r];
      w.drhs_v[k] = -data.efc_B[r] * sign;  // aref = -B sign qd - K imp (pos - margin)
    }
    solve_column(deriv.dqacc_dq, deriv.dconstraint_dq, c, w.drhs_q.data());
    solve_column(deriv.dqacc_dv, deriv.dconstraint_dv, c, w.drhs_v.data());
  }
  for (int c = 0; c < model.nu; ++c) solve_column(deriv.dqacc_du, deriv.dconstraint_du, c, nullptr);
  for (int c = 0; c < model.na; ++c) {
    solve_column(deriv.dqacc_dact, deriv.dconstraint_dact, c, nullptr);
  }
}

// ---- solves with many right-hand sides ---------------------------------------------------------
// The right-hand sides of a derivative (its qpos, qvel and ctrl columns, 2 nv + nu of them) are
// solved together: side by side in one row-major matrix, each substitution of a solve is one row
// operation over all of them, instead of one walk of the tree per column. The arithmetic of each
// column is the single solve's, in the same order.


// X = (L^T D L)^-1 X with an LTDL factor in crba.cpp's layout (ltdl: D on the diagonal, L(k, i)
// at LD(i, k) for each ancestor i of k), as solve_mass does one column.
void ltdl_solve_rows(const Model& model, const Eigen::Ref<const Eigen::MatrixXd>& LD,
                     const Eigen::Ref<const Eigen::VectorXd>& diag_inverse, RowMatrix& X) {
  const Eigen::Index n = X.cols();
  for (int k = model.nv - 1; k >= 0; --k) {  // L^-T, leaves to root
    for (int i = model.dof_parentid[k]; i >= 0; i = model.dof_parentid[i]) {
      detail::add_scaled_row(X.row(i).data(), -LD(i, k), X.row(k).data(), n);
    }
  }
  for (int k = 0; k < model.nv; ++k) {  // D^-1
    detail::scale_row(X.row(k).data(), diag_inverse[k], n);
  }
  for (int k = 0; k < model.nv; ++k) {                             // L^-1, root to leaves
    for (int i = model.dof_parentid[k]; i >= 0; i = model.dof_parentid[i]) {
      detail::add_scaled_row(X.row(k).data(), -LD(i, k), X.row(i).data(), n);
    }
  }
}

// X = K^-1 X with factor_lu_tree()'s factor K = (U + I) L, as solve_lu_tree does one column but
// for L's diagonal, each row scaled by its reciprocal (diagonal_inverse: nv numbers of scratch):
// tens of columns a row, where a division costs several multiplications' time.
void lu_tree_solve_rows(const Model& model, const Eigen::MatrixXd& LU, RowMatrix& X,
                        double* diagonal_inverse) {
  const Eigen::Index n = X.cols();
  for (int k = 0; k < model.nv; ++k) diagonal_inverse[k] = 1.0 / LU(k, k);
  for (int k = model.nv - 1; k >= 0; --k) {  // (U + I)^-1, leaves to root
    for (int i = model.dof_parentid[k]; i >= 0; i = model.dof_parentid[i]) {
      detail::add_scaled_row(X.row(i).data(), -LU(i, k), X.row(k).data(), n);
    }
  }
  for (int k = 0; k < model.nv; ++k) {  // L^-1, root to leaves
    for (int j = model.dof_parentid[k]; j >= 0; j = model.dof_parentid[j]) {
      detail::add_scaled_row(X.row(k).data(), -LU(k, j), X.row(j).data(), n);
    }
    detail::scale_row(X.row(k).data(), diagonal_inverse[k], n);
  }
}

// [in_q in_v in_u] side by side in w.right_hand_sides, then solve(X) solving every column of X in
// place; returns X.
template <class Solve>
RowMatrix& solve_side_by_side(Derivatives::Workspace& w, const Eigen::MatrixXd& in_q,
                              const Eigen::MatrixXd& in_v, const Eigen::MatrixXd& in_u,
                              Solve&& solve) {
  const Eigen::Index nv = in_q.cols(), inputs = in_u.cols();
  RowMatrix& X = w.right_hand_sides;
  X.leftCols(nv) = in_q;
  X.middleCols(nv, nv) = in_v;
  X.rightCols(inputs) = in_u;
  solve(X);
  return X;
}

// forward_derivatives() without its checks, for the step's calls (step_derivatives checked once).
void forward_derivatives_unchecked(const Model& model, Data& data, Derivatives& deriv) {
  forward(model, data);
  auto& w = deriv.work;
  inertia_columns(model, data, data.work.crb, w);
  const detail::Velocities at_qvel = detail::bias_stage_velocities(data);  // forward()'s
  rnea_derivatives_into(model, data, data.qvel.data(), data.qacc.data(), true, data.work.crb, w,
                        deriv.dtau_dq, deriv.dtau_dv, &at_qvel);
  smooth_rhs(model, data, deriv.dtau_dq, deriv.dtau_dv, w);
  if (detail::rows_beyond_joint_limits(data)) {  // every row in dof space, solved with H, not M
    detail::constraint_rows_held(model, data, deriv);
    return;
  }
  // the unconstrained part: M^-1 times each column
  const RowMatrix& X = solve_side_by_side(w, w.rhs_q, w.rhs_v, w.rhs_u, [&](RowMatrix& Y) {
    ltdl_solve_rows(model, data.qLD, data.qLDiagInv, Y);
  });
  deriv.dqacc_dq = X.leftCols(model.nv);
  deriv.dqacc_dv = X.middleCols(model.nv, model.nv);
  deriv.dqacc_du = X.middleCols(2 * model.nv, model.nu);
  deriv.dqacc_dact = X.rightCols(model.na);
  limit_rows(model, data, deriv);
}

// ---- the active set's check -----------------------------------------------------------------
// The derivatives hold the rows' active set of the step's start. Where another set holds at its
// end (a contact made or lost, a row starting or stopping to push), or at an RK4 stage, the step
// is not differentiable across the perturbations a user would make: reported, not smoothed.

// A point of a spatial tendon's path as forward() recorded it (data.wrap_obj, wrap_xpos: two
// points per row): its object (-1 a site, -2 a pulley's marker, else the wrapping geom) and where
// it is.
int path_object(const Data& data, int point) { return data.wrap_obj[point / 2][point % 2]; }

Eigen::Vector3d path_point(const Data& data, int point) {
  const double* x = data.wrap_xpos[point / 2].data() + 3 * (point % 2);
  return {x[0], x[1], x[2]};
}

// Which way round geom g the path from site x0 over tangent points t0, t1 to site x1 goes: the
// sign of the turn from x0 to t0 about the geom's centre, seen along a cylinder's axis or along
// the normal of a sphere's great circle through x0 and x1 (wrap_path.hpp's plane). Each of the two
// pairs of tangent points turns its own way, so the sign tells which pair the wrap took; 0 for a
// path through the geom (a side site inside it: t0 = t1, one point) or sites in line with the
// centre.
int wrap_side(const Model& model, const Data& data, int g, const Eigen::Vector3d& x0,
              const Eigen::Vector3d& t0, const Eigen::Vector3d& t1, const Eigen::Vector3d& x1) {
  if (t0 == t1) return 0;
  const Eigen::Vector3d& centre = data.geom_xpos[g];
  const Eigen::Vector3d p0 = x0 - centre, p1 = x1 - centre, turn = p0.cross(t0 - centre);
  const Eigen::Vector3d axis = model.geom_type[g] == GeomType::kCylinder
                                   ? Eigen::Vector3d(data.geom_xmat[g].col(2))
                                   : Eigen::Vector3d(p0.cross(p1));
  const double side = turn.dot(axis);
  return side > 0 ? 1 : side < 0 ? -1 : 0;
}

// The active set after forward(): the contacts' geom pairs, each row's state, and each spatial
// tendon's path (its points' objects: which geoms it wraps, and which way round each). A wrap
// switching on or off, or to the other pair of tangent points, changes the tendon's Jacobian's
// formula as a contact made or lost changes the rows. Its numbers in order to emit(number), which
// returns false to stop the walk; returns whether the walk finished.
template <class Emit>
bool walk_active_set(const Model& model, const Data& data, Emit&& emit) {
  for (int i = 0; i < data.ncon; ++i) {
    const Contact& con = data.contact[static_cast<std::size_t>(i)];
    if (!emit(con.geom1) || !emit(con.geom2) || !emit(con.efc_address >= 0 ? 1 : 0)) return false;
  }
  if (!emit(-1)) return false;
  for (int r = 0; r < data.nefc; ++r) {
    if (!emit(static_cast<int>(data.efc_state[r]))) return false;
  }
  if (!emit(-1)) return false;
  for (int t = 0; t < model.ntendon; ++t) {
    const int first = data.ten_wrapadr[t], end = first + data.ten_wrapnum[t];
    for (int k = first; k < end; ++k) {
      const int object = path_object(data, k);
      if (!emit(object)) return false;
      // a wrapped geom's first tangent point, between its sites: site, t0, t1, site
      const bool first_tangent =
          object >= 0 && k > first && k + 2 < end && path_object(data, k - 1) != object;
      if (!first_tangent) continue;
      if (!emit(wrap_side(model, data, object, path_point(data, k - 1), path_point(data, k),
                          path_point(data, k + 1), path_point(data, k + 2)))) {
        return false;
      }
    }
  }
  return true;
}

void record_active_set(const Model& model, const Data& data, std::vector<int>& set) {
  set.clear();
  walk_active_set(model, data, [&](int number) {
    set.push_back(number);
    return true;
  });
}

// Whether data's active set is `set` (record_active_set()'s), compared number by number as the
// walk makes them (stopping at the first that differs).
bool same_active_set(const Model& model, const Data& data, const std::vector<int>& set) {
  std::size_t k = 0;
  const bool walked = walk_active_set(model, data, [&](int number) {
    if (k == set.size() || set[k] != number) return false;
    ++k;
    return true;
  });
  return walked && k == set.size();
}

// Whether the active set at `next` (forward_until_solve() run, the rows not yet solved) is
// `set` (record_active_set()'s). Where the active-set solve would solve next's rows and the
// start's rows each pushed or not, the start's states are tried at next: written into
// next.efc_state, the record compared (contacts, row count, states, tendon paths), and only if
// that matches, whether the rows settle with the start's pushing set (active_set_round(): the
// one-sided rows' solution is unique, so a set that settles is the set the solve finds): the
// same answer as the solve and the record, without the solve's first residual, its other rounds
// and its forces. Without rows, nothing to solve: the record at once. Otherwise the solve, then
// the record.
bool same_active_set_at_end(const Model& model, Data& next, const std::vector<int>& set) {
  if (next.nefc == 0) return same_active_set(model, next, set);
  if (!solved_by_active_sets(model, next)) {
    detail::forward_solve(model, next);
    return same_active_set(model, next, set);
  }
  // the start's states: between the record's first -1 (after the contacts' triples of geom
  // ids and flags, none of them -1) and its second
  const auto first = std::find(set.begin(), set.end(), -1) + 1;
  const auto end = std::find(first, set.end(), -1);
  if (end - first != next.nefc) return false;  // a row more or fewer: not the same record
  int* const active = next.work.lcp_active.data();
  for (int r = 0; r < next.nefc; ++r) {
    const int state = first[r];
    if (state != static_cast<int>(ConstraintState::kSatisfied) &&
        state != static_cast<int>(ConstraintState::kActive)) {
      detail::forward_solve(model, next);
      return same_active_set(model, next, set);
    }
    next.efc_state[r] = static_cast<ConstraintState>(state);
    active[r] = state == static_cast<int>(ConstraintState::kActive) ? 1 : 0;
  }
  return same_active_set(model, next, set) && active_set_round(next, active);
}

// forward() at the step's end x' = (qpos (+) h velocity, qvel + h acceleration), in
// deriv.work.next, against the start's set (deriv.work.active_set); a change sets the flag and
// data's warning.
void check_step_end(const Model& model, Data& data, Derivatives& deriv,
                    const Eigen::Ref<const Eigen::VectorXd>& velocity,
                    const Eigen::Ref<const Eigen::VectorXd>& acceleration,
                    const Eigen::Ref<const Eigen::VectorXd>& act_dot) {
  auto& w = deriv.work;
  Data& next = *w.next;
  const double h = model.opt.timestep;
  next.time = data.time + h;
  next.qpos = data.qpos;
  detail::integrate_positions(model, next.qpos.data(), velocity.data(), h);
  next.qvel = data.qvel + h * acceleration;
  next.ctrl = data.ctrl;
  next.qfrc_applied = data.qfrc_applied;
  next.act = data.act;
  detail::advance_activations(model, next, act_dot.data(), h);
  // the rows' set only: the lean kinematics, no sensors, and the solve as far as the set needs
  detail::forward_until_solve(model, next);
  if (!same_active_set_at_end(model, next, w.active_set)) {
    deriv.active_set_changes = true;
  }
  if (deriv.active_set_changes) {
    WarningStat& stat = data.warning[static_cast<int>(Warning::kActiveSetChanges)];
    ++stat.number;
    stat.lastinfo = next.nefc;
  }
}

// Whether stateful actuator k's activation act + h act_dot leaves its actrange (strictly: an
// edge counts as inside), where the step clamps it and it no longer follows the state.
bool activation_clamped(const Model& model, int k, double act, double act_dot) {
  const int a = model.nu - model.na + k;
  if (!model.actuator_actlimited[a]) return false;
  const double next = act + model.opt.timestep * act_dot;
  const auto& range = model.actuator_actrange[a];
  return next < range[0] || next > range[1];
}

// x' = [qpos (+) h qvel'; qvel'; act'] with qvel' = qvel + h qacc_step and
// act' = clamp(act + h act_dot), given d qacc_step / d (q, v, u, act): the rows of hinges and slides here, a turn's by euler_turns(). act_dot
// depends on its own actuator's ctrl and act alone (w.act_rate_*); a clamped act' on nothing.
template <class Matrix, class ActMatrix>
void assemble_euler(const Model& model, const Data& data, const Matrix& Dq, const Matrix& Dv,
                    const Matrix& Du, const ActMatrix& Da, Derivatives& deriv) {
  const int nv = model.nv, nu = model.nu, na = model.na;
  const double h = model.opt.timestep;
  Eigen::MatrixXd& A = deriv.A;
  // column by column, A = [[pos_q, pos_v], [vel_q, vel_v]]; the identity's zeros added too (a
  // -0 becomes +0, as the sum with the identity's entry makes it), its ones after the column
  const auto block = [&](int r, int c, double identity) {
    const double vel_q = h * Dq(r, c);
    const double vel_v = h * Dv(r, c) + identity;
    A(nv + r, c) = vel_q;
    A(nv + r, nv + c) = vel_v;
    A(r, c) = h * vel_q + identity;
    A(r, nv + c) = h * vel_v;
  };
  for (int c = 0; c < nv; ++c) {
    for (int r = 0; r < nv; ++r) block(r, c, 0.0);
    block(c, c, 1.0);
  }
  for (int c = 0; c < nu; ++c) {
    for (int r = 0; r < nv; ++r) {
      deriv.B(nv + r, c) = h * Du(r, c);
      deriv.B(r, c) = (h * h) * Du(r, c);
    }
  }
  if (na == 0) return;
  const auto& w = deriv.work;
  for (int k = 0; k < na; ++k) {  // the act columns of qpos' and qvel'
    for (int r = 0; r < nv; ++r) {
      A(nv + r, 2 * nv + k) = h * Da(r, k);
      A(r, 2 * nv + k) = (h * h) * Da(r, k);
    }
  }
  A.bottomRows(na).setZero();
  deriv.B.bottomRows(na).setZero();
  for (int k = 0; k < na; ++k) {
    if (activation_clamped(model, k, data.act[k], data.act_dot[k])) continue;
    A(2 * nv + k, 2 * nv + k) = 1 + h * w.act_rate_per_act[k];
    deriv.B(2 * nv + k, nu - na + k) = h * w.act_rate_per_ctrl[k];
  }
}

// The rows of ball and free joints' turns in an Euler-form step (Euler, implicit), after
// assemble_euler(): qpos' = qpos (+) h qvel', qvel' = qvel + h qacc_step.
void euler_turns(const Model& model, const Data& data,
                 const Eigen::Ref<const Eigen::VectorXd>& qacc_step, Derivatives& deriv) {
  const int nv = model.nv;
  const double h = model.opt.timestep;
  auto& qvel_next = deriv.work.qvel_next;
  qvel_next = data.qvel + h * qacc_step;
  through_position_update(model, qvel_next.data(), h, deriv.A.topRows(nv), deriv.B.topRows(nv));
}

// The right-hand sides += d qfrc_constraint (forward's linearised solve), for a step that
// advances with the forward solve's constraint force (Euler with damping, implicit).
void add_constraint_change(const Model& model, Derivatives& deriv) {
  auto& w = deriv.work;
  w.rhs_q += deriv.dconstraint_dq;
  w.rhs_v += deriv.dconstraint_dv;
  w.rhs_u.leftCols(model.nu) += deriv.dconstraint_du;
  w.rhs_u.rightCols(model.na) += deriv.dconstraint_dact;
}

void euler_derivatives(const Model& model, Data& data, Derivatives& deriv) {
  auto& w = deriv.work;
  forward_derivatives_unchecked(model, data, deriv);
  bool damped = false;
  for (int i = 0; i < model.nv; ++i) damped = damped || model.dof_damping[i] > 0;
  if (!damped) {
    w.qacc_step = data.qacc;
    assemble_euler(model, data, deriv.dqacc_dq, deriv.dqacc_dv, deriv.dqacc_du, deriv.dqacc_dact,
                   deriv);
    if (model.nq != model.nv) euler_turns(model, data, data.qacc, deriv);
    return;
  }

  // implicit damping: (M + h B) qacc_step = qfrc_smooth + qfrc_constraint, so
  // (M + h B) d qacc_step = d f_smooth - d M qacc_step + d qfrc_constraint, where
  // d f_smooth - d M qacc_step is smooth_rhs() with rnea differentiated at qacc_step
  const double h = model.opt.timestep;
  factor_mass_damped(model, data, h);
  w.qacc_step = data.qfrc_smooth + data.qfrc_constraint;
  solve_mass_damped(model, data, w.qacc_step);
  // rnea's derivatives at qacc_step, in the held rows' buffers (free once forward's are solved)
  Eigen::MatrixXd &tau_q = w.contact_E, &tau_v = w.contact_G;
  const detail::Velocities at_qvel = detail::bias_stage_velocities(data);  // forward()'s
  rnea_derivatives_into(model, data, data.qvel.data(), w.qacc_step.data(), true, data.work.crb, w,
                        tau_q, tau_v, &at_qvel);
  smooth_rhs(model, data, tau_q, tau_v, w);
  if (w.active_rows > 0) add_constraint_change(model, deriv);
  const RowMatrix& X = solve_side_by_side(w, w.rhs_q, w.rhs_v, w.rhs_u, [&](RowMatrix& Y) {
    ltdl_solve_rows(model, data.work.LD2, data.work.LD2DiagInv, Y);
  });
  assemble_euler(model, data, X.leftCols(model.nv), X.middleCols(model.nv, model.nv),
                 X.middleCols(2 * model.nv, model.nu), X.rightCols(model.na), deriv);
  if (model.nq != model.nv) euler_turns(model, data, w.qacc_step, deriv);
}

// MuJoCo 2.2.2's implicit step (implicit.cpp): K a = f with K = M - h D, D = d qfrc_smooth / d qvel
// as smooth_velocity_derivative() holds it, f = qfrc_smooth + qfrc_constraint, then Euler's update
// with a. Differentiating exactly that, K da = df - dM a + h dD a. D is
//   D = D_act - diag(damping) - d c / d qvel,    D_act = diag(gear^2 (b2 + p2 ctrl)) (raw ctrl),
// with c(q, qd) = qfrc_bias, which is gravity plus a quadratic form Q(q)(qd, qd). So
//   d D_act a / d ctrl_k = gear^2 p2 a_dof on the actuator's dof (MuJoCo's FD misses it, see the
//   docs), damping is constant, and (d c / d qvel) a = 2 Q(qd, a), whose derivatives are
//   d/d qvel = d c / d qvel at velocity a, and d/d q = d/d q [2 Q(q)(qd, a)]:
// the derivatives of the velocity product's polar form (polar_derivatives_into()), which also
// carries M's derivative at a - qacc (below). No finite difference is taken.
void implicit_derivatives(const Model& model, Data& data, Derivatives& deriv) {
  auto& w = deriv.work;
  const int nv = model.nv;
  const double h = model.opt.timestep;
  forward_derivatives_unchecked(model, data, deriv);

  // the step's K, its LU factor and its acceleration a, as implicit_step computes them; D is
  // smooth_velocity_derivative()'s, its bias part d c / d qvel read from the RNEA derivative just
  // taken (the same velocity columns: the M qacc and gravity terms are free of qvel) rather than
  // recomputed. D is made in K's buffer, then K = M - h D in place (element by element)
  w.K = -deriv.dtau_dv;
  add_actuator_damping_velocity_terms(model, data, w.K);
  {  // K = M - h D, and its copy the factor is made in, in one pass
    const double* const M = data.M.data();
    double* const K = w.K.data();
    double* const K_lu = w.K_lu.data();
    for (int e = 0; e < nv * nv; ++e) K_lu[e] = K[e] = M[e] - h * K[e];
  }
  factor_lu_tree(model, w.K_lu);
  w.qacc_step = data.qfrc_smooth + data.qfrc_constraint;
  solve_lu_tree(model, w.K_lu, w.qacc_step.data(), data.work.dof_chain.data());

  // df - dM a + h dD a's bias part, from forward_derivatives' dtau (at qacc) and the polar
  // form's derivatives P(qd, h a) + L(a - qacc) (rnea = Q(qd, qd) + L(qdd, gravity), L linear):
  //   - d rnea at a = - dtau - dL(a - qacc)
  //   - h d[2 Q(qd, a)] = - d[2 Q(qd, h a)]   (D's bias part)
  // in qpos, and in qvel - d c / d qvel at velocity h a. (w.rhs_* still hold smooth_rhs() at
  // dtau: forward_derivatives_unchecked solved them into dqacc_* and left them as they were; w.CC
  // holds C at qd, which the polar form reads)
  w.qvel_change = h * w.qacc_step;
  w.qacc_change = w.qacc_step - data.qacc;
  // (in the held rows' buffers, free once forward's derivatives are solved)
  Eigen::MatrixXd &tau_q = w.contact_E, &tau_v = w.contact_G;
  polar_derivatives_into(model, data, detail::bias_stage_velocities(data), data.qvel.data(),
                         w.qvel_change.data(), w.qacc_change.data(), data.work.crb, w, tau_q,
                         tau_v);
  // rhs + d qfrc_constraint (forward's linearised solve) - the polar form's, written in one pass
  // straight into the solve's row-major right-hand sides [q v u] (w.rhs_* keep smooth_rhs()'s),
  // where the terms below add to them
  RowMatrix& X = w.right_hand_sides;
  const bool rows = w.active_rows > 0;
  const Eigen::Index stride = X.cols();
  for (int c = 0; c < nv; ++c) {
    const double* q = w.rhs_q.col(c).data();
    const double* v = w.rhs_v.col(c).data();
    const double* dq = deriv.dconstraint_dq.col(c).data();
    const double* dv = deriv.dconstraint_dv.col(c).data();
    const double* tq = tau_q.col(c).data();
    const double* tv = tau_v.col(c).data();
    double* x = X.data() + c;
    if (rows) {
      for (int i = 0; i < nv; ++i, x += stride) {
        x[0] = (q[i] + dq[i]) - tq[i];
        x[nv] = (v[i] + dv[i]) - tv[i];
      }
    } else {
      for (int i = 0; i < nv; ++i, x += stride) {
        x[0] = q[i] - tq[i];
        x[nv] = v[i] - tv[i];
      }
    }
  }
  const int nu = model.nu, na = model.na;
  for (int i = 0; i < nv; ++i) {
    double* x = X.row(i).data() + 2 * nv;
    for (int c = 0; c < nu; ++c) {
      x[c] = rows ? w.rhs_u(i, c) + deriv.dconstraint_du(i, c) : w.rhs_u(i, c);
    }
    for (int c = 0; c < na; ++c) {
      x[nu + c] = rows ? w.rhs_u(i, nu + c) + deriv.dconstraint_dact(i, c) : w.rhs_u(i, nu + c);
    }
  }
  auto X_q = X.leftCols(nv);
  auto X_v = X.middleCols(nv, nv);
  auto X_u = X.rightCols(nu + na);
  // + h dD a, D's actuator part: m^T k m per actuator (kept where M is non-zero, as the step's D
  // keeps it), k = b2 + gain_velocity input, with gain_velocity an affine gain's p2 or a muscle's
  // d gain / d velocity (a function of the length and velocity), input the raw ctrl or the act
  const int actuators = model.opt.disabled(kDisableActuation) ? 0 : model.nu;
  const int first_stateful = model.nu - model.na;
  for (int a = 0; a < actuators; ++a) {
    const bool stateful = a >= first_stateful;
    const double input = stateful ? data.act[a - first_stateful] : data.ctrl[a];
    const int input_column = stateful ? model.nu + (a - first_stateful) : a;
    double gain_velocity = 0.0, per_length = 0.0, per_velocity = 0.0;  // the last two: of k
    if (model.actuator_gaintype[a] == GainType::kAffine) {
      gain_velocity = model.actuator_gainprm[a][2];
    } else if (model.actuator_gaintype[a] == GainType::kMuscle) {
      const MusclePartials muscle = muscle_partials(
          data.actuator_length[a], data.actuator_velocity[a], model.actuator_lengthrange[a],
          model.actuator_acc0[a], model.actuator_gainprm[a].data(),
          model.actuator_biasprm[a].data());
      gain_velocity = muscle.gain_per_velocity;
      per_length = muscle.gain_per_velocity_per_length * input;
      per_velocity = muscle.gain_per_velocity_per_velocity * input;
    }
    double k = gain_velocity * input;
    if (model.actuator_biastype[a] == BiasType::kAffine) k += model.actuator_biasprm[a][2];
    const bool site = model.actuator_trntype[a] == TransmissionType::kSite;
    const bool spatial = model.actuator_trntype[a] == TransmissionType::kTendon &&
                         detail::is_spatial_tendon(model, model.actuator_trnid[a][0]);
    const bool turning = site || spatial;  // the moment moves with the pose
    if (gain_velocity == 0.0 && per_length == 0.0 && per_velocity == 0.0 &&
        !(turning && k != 0.0)) {
      continue;
    }
    const double gear = model.actuator_gear[a][0];
    // the moment's change with the pose, once for both of its uses below
    if (spatial) detail::spatial_tendon_change(model, data, model.actuator_trnid[a][0], w);
    if (site && (per_length != 0.0 || per_velocity != 0.0 || k != 0.0)) {
      site_transmission_change(model, data, a, w);
    }
    // r = (m m^T a) where M is non-zero (for one dof: gear^2 a_dof)
    const double* m = data.actuator_moment.row(a).data();
    Eigen::VectorXd& r = w.moment_times_a;
    r.setZero();
    for (int i = 0; i < nv; ++i) {
      if (m[i] == 0.0) continue;
      for (int j = i; j >= 0; j = model.dof_parentid[j]) {
        if (m[j] == 0.0) continue;
        r[i] += m[i] * m[j] * w.qacc_step[j];
        if (j != i) r[j] += m[j] * m[i] * w.qacc_step[i];
      }
    }
    // d k / d input
    if (gain_velocity != 0.0) X_u.col(input_column) += (h * gain_velocity) * r;
    // a muscle's k moves with the length (gradient m: L = gear q or gear ten_length; a site's
    // its own) and the velocity (gradient m in qvel; in qpos, a turning moment's G^T qvel)
    if (per_length != 0.0 || per_velocity != 0.0) {
      for (int col = 0; col < nv; ++col) {
        double dk_dq = per_length * (site ? w.length_gradient[col] : m[col]);
        if (site) dk_dq += per_velocity * w.moment_change.col(col).dot(data.qvel);
        if (spatial) dk_dq += per_velocity * gear * w.tendon_change.col(col).dot(data.qvel);
        const double dk_dv = per_velocity * m[col];
        if (dk_dq != 0.0) X_q.col(col) += (h * dk_dq) * r;
        if (dk_dv != 0.0) X_v.col(col) += (h * dk_dv) * r;
      }
    }
    // a site's moment turning: m k m^T changes by G_c k m^T + m k G_c^T along q_c (G = d m / d q)
    if (site && k != 0.0) {
      const Eigen::MatrixXd& G = w.moment_change;
      double m_a = 0.0;
      for (int i = 0; i < nv; ++i) m_a += m[i] * w.qacc_step[i];
      for (int col = 0; col < nv; ++col) {
        const double G_a = G.col(col).dot(w.qacc_step);
        for (int i = 0; i < nv; ++i) X_q(i, col) += h * k * (G(i, col) * m_a + m[i] * G_a);
      }
    }
    // a spatial tendon's moment turning: P(m k m^T) changes by k P(G_c m^T + m G_c^T),
    // G = gear d J / d q
    if (spatial && k != 0.0) {
      for (int col = 0; col < nv; ++col) {
        detail::add_pair_product(model, w.tendon_change.col(col).data(), m, w.qacc_step.data(),
                                 h * k * gear, X_q.col(col));
      }
    }
  }
  // + h dD a, D's tendon dampers -b P(J J^T): a spatial tendon's J moves (T = d J / d q)
  if (!model.opt.disabled(kDisablePassive)) {
    for (int t = 0; t < model.ntendon; ++t) {
      const double b = model.tendon_damping[t];
      if (!(b > 0) || !detail::is_spatial_tendon(model, t)) continue;
      detail::spatial_tendon_change(model, data, t, w);
      for (int col = 0; col < nv; ++col) {
        detail::add_pair_product(model, w.tendon_change.col(col).data(), data.ten_J.row(t).data(),
                                 w.qacc_step.data(), -h * b, X_q.col(col));
      }
    }
  }

  // da = K^-1 (...) in place, then Euler's update
  lu_tree_solve_rows(model, w.K_lu, X, w.col.data());
  assemble_euler(model, data, X.leftCols(nv), X.middleCols(nv, nv), X.middleCols(2 * nv, model.nu),
                 X.rightCols(model.na), deriv);
  if (model.nq != model.nv) euler_turns(model, data, w.qacc_step, deriv);
}

// Classical RK4 on x = [qpos; qvel; act] with slope k(x) = [qvel; qacc(x); act_dot(x)], as
// step(): stage i starts from x_i = (qpos_0 (+) h a_i qvel_{i-1}, qvel_0 + h a_i qacc_{i-1},
// act_0 + h a_i act_dot_{i-1}) (the stages' act unclamped), and
// x' = (qpos_0 (+) h sum_i b_i qvel_i, qvel_0 + h sum_i b_i qacc_i, clamp(act_0 + h sum_i b_i
// act_dot_i)). By the chain rule, with F_i = d k / d x at x_i =
// [0 I 0; dqacc_dq dqacc_dv dqacc_dact; 0 0 diag(d act_dot / d act)]:
//   d k_i / d x_0 = F_i J_i,   d k_i / d u = F_i J^u_i + [0; dqacc_du; d act_dot / d ctrl],
//   J_i = d x_i / d x_0 = I + h a_i d k_{i-1} / d x_0,   J^u_i = h a_i d k_{i-1} / d u,
// where, for the rows of a ball's or free joint's turn, (+) makes "I + h X" into
// exp(-h a_i [w]) + Jr(h a_i w) h X (through_position_update), as for the final x'.
void rk4_derivatives(const Model& model, Data& data, Derivatives& deriv) {
  constexpr double kA[3] = {0.5, 0.5, 1.0};
  constexpr double kB[4] = {1.0 / 6.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0};
  const int nv = model.nv, nu = model.nu, na = model.na;
  const double h = model.opt.timestep;
  auto& w = deriv.work;
  const double time0 = data.time;
  w.qpos0 = data.qpos;
  w.qvel0 = data.qvel;
  w.act0 = data.act;
  const bool quaternions = model.nq != model.nv;
  w.qvel_next.setZero();  // sum_i b_i qvel_i: the velocity the final qpos is integrated with
  w.qacc_sum.setZero();   // sum_i b_i qacc_i
  w.act_dot_sum.setZero();

  w.Jx.setIdentity();  // d x_0 / d x_0
  w.Ju.setZero();
  deriv.A.setZero();  // sum_i b_i d k_i / d x_0 until the end
  deriv.B.setZero();
  for (int i = 0; i < 4; ++i) {
    if (i > 0) {
      // x_i from the previous stage's slope (data still holds its qvel, qacc and act_dot), as
      // step()
      w.qacc_step = data.qacc;
      if (quaternions) {  // as step(): qpos_0 (+) h (a_i qvel_{i-1})
        w.stage_dq = kA[i - 1] * data.qvel;
        data.qpos = w.qpos0;
        detail::integrate_positions(model, data.qpos.data(), w.stage_dq.data(), h);
      } else {
        data.qpos = w.qpos0 + (h * kA[i - 1]) * data.qvel;
      }
      data.qvel = w.qvel0 + (h * kA[i - 1]) * w.qacc_step;
      data.act = w.act0 + (h * kA[i - 1]) * data.act_dot;
      data.time = time0 + kA[i - 1] * h;
    }
    forward_derivatives_unchecked(model, data, deriv);
    if (i == 0) {
      record_active_set(model, data, w.active_set);
    } else if (!same_active_set(model, data, w.active_set)) {
      deriv.active_set_changes = true;
    }
    w.qvel_next += kB[i] * data.qvel;
    w.qacc_sum += kB[i] * data.qacc;
    w.act_dot_sum += kB[i] * data.act_dot;

    // K = F J: the qpos rows of the slope are J's qvel rows; its qvel rows the chain rule; its
    // act rows each activation's own rate
    w.Kx.topRows(nv) = w.Jx.middleRows(nv, nv);
    w.Kx.middleRows(nv, nv).noalias() = deriv.dqacc_dq.lazyProduct(w.Jx.topRows(nv));
    w.Kx.middleRows(nv, nv).noalias() += deriv.dqacc_dv.lazyProduct(w.Jx.middleRows(nv, nv));
    w.Ku.topRows(nv) = w.Ju.middleRows(nv, nv);
    w.Ku.middleRows(nv, nv) = deriv.dqacc_du;
    w.Ku.middleRows(nv, nv).noalias() += deriv.dqacc_dq.lazyProduct(w.Ju.topRows(nv));
    w.Ku.middleRows(nv, nv).noalias() += deriv.dqacc_dv.lazyProduct(w.Ju.middleRows(nv, nv));
    if (na > 0) {
      w.Kx.middleRows(nv, nv).noalias() += deriv.dqacc_dact.lazyProduct(w.Jx.bottomRows(na));
      w.Ku.middleRows(nv, nv).noalias() += deriv.dqacc_dact.lazyProduct(w.Ju.bottomRows(na));
      w.Kx.bottomRows(na) = w.act_rate_per_act.asDiagonal() * w.Jx.bottomRows(na);
      w.Ku.bottomRows(na) = w.act_rate_per_act.asDiagonal() * w.Ju.bottomRows(na);
      for (int k = 0; k < na; ++k) w.Ku(2 * nv + k, nu - na + k) += w.act_rate_per_ctrl[k];
    }

    deriv.A += kB[i] * w.Kx;
    deriv.B += kB[i] * w.Ku;
    if (i < 3) {
      w.Jx = (h * kA[i]) * w.Kx;
      w.Jx.diagonal().array() += 1.0;
      w.Ju = (h * kA[i]) * w.Ku;
      // the next stage's qpos turns by h a_{i+1} qvel_i (data.qvel is still stage i's)
      through_position_update(model, data.qvel.data(), h * kA[i], w.Jx.topRows(nv),
                              w.Ju.topRows(nv));
    }
  }
  deriv.A *= h;
  deriv.A.diagonal().array() += 1.0;
  deriv.B *= h;
  through_position_update(model, w.qvel_next.data(), h, deriv.A.topRows(nv), deriv.B.topRows(nv));
  for (int k = 0; k < na; ++k) {  // a clamped activation follows nothing
    if (!activation_clamped(model, k, w.act0[k], w.act_dot_sum[k])) continue;
    deriv.A.row(2 * nv + k).setZero();
    deriv.B.row(2 * nv + k).setZero();
  }

  data.qpos = w.qpos0;
  data.qvel = w.qvel0;
  data.act = w.act0;
  data.time = time0;
}

// The fluid forces depend on the pose and the velocity in ways the chain rule above leaves out,
// and so do the moments of transmissions other than a hinge's, a slide's, a fixed tendon's and a
// site's. Every built-in gain, bias and activation dynamics is covered (fixed, affine, muscle;
// none, integrator, filter, muscle); a user's callback has no derivative lever could know.
void refuse_uncovered(const Model& model) {
  if (has_fluid(model.opt)) {
    throw ModelError("derivatives: the model has fluid forces (option viscosity or density); "
                     "lever's analytic derivatives do not cover them yet.");
  }
  for (int a = 0; a < model.nu; ++a) {
    const char* user = actuator_user_attribute(model, a);
    if (user == nullptr) continue;
    throw ModelError("derivatives: actuator " + actuator_label(model, a) + " has " + user +
                         " \"user\" (a callback); lever's analytic derivatives cannot "
                         "differentiate a callback.",
                     "actuator", a);
  }
  // the chain rule above carries each actuator's force through a constant moment (a gear on one
  // dof, or gear ten_J of a tendon, whose change spatial_tendon_change gives for a spatial one)
  // or a site's moment and length, whose change with the pose it differentiates (site_transmission_change)
  for (int a = 0; a < model.nu; ++a) {
    if (actuator_scalar_dof(model, a) >= 0) continue;
    const TransmissionType trn = model.actuator_trntype[a];
    if (trn == TransmissionType::kTendon || trn == TransmissionType::kSite) continue;
    const char* what = "a slider-crank";
    switch (trn) {
      case TransmissionType::kJoint:
      case TransmissionType::kJointInParent: what = "a ball or free joint"; break;
      case TransmissionType::kSliderCrank: what = "a slider-crank"; break;
      case TransmissionType::kBody: what = "a body through its contacts (adhesion)"; break;
      default: break;
    }
    throw ModelError("derivatives: actuator " + actuator_label(model, a) + " drives " + what +
                         "; lever's analytic derivatives cover actuators on hinge and slide "
                         "joints, fixed tendons and sites so far.",
                     "actuator", a);
  }
}

// The derivatives are those of the constraint problem's minimizer, its active set held. MuJoCo's
// iterative solvers (conjugate gradients, projected Gauss-Seidel) stopped by a tolerance end short
// of it, where the rows' states can be others: refused. At tolerance 0 they run to the minimizer
// as their iterations allow, where the solver no longer matters.
void refuse_stopped_solver(const Model& model) {
  if (model.opt.solver != Solver::kNewton && model.opt.tolerance > 0) {
    const char* solver = model.opt.solver == Solver::kCG ? "CG" : "PGS";
    throw ModelError(std::string("derivatives: opt.solver is ") + solver + " with tolerance " +
                     std::to_string(model.opt.tolerance) +
                     " > 0; the derivatives hold the active set of the converged solution, which "
                     "a solve stopped by a tolerance need not reach. Set opt.tolerance to 0 (" +
                     solver + " then converges as its iterations allow) or use the Newton solver.");
  }
}

}  // namespace

Derivatives::Derivatives(const Model& model) : nv(model.nv), nu(model.nu), na(model.na) {
  const int nefc_max = constraint_rows_max(model);  // Data's: limits, and contacts' rows
  dtau_dq.setZero(nv, nv);
  dtau_dv.setZero(nv, nv);
  dqacc_dq.setZero(nv, nv);
  dqacc_dv.setZero(nv, nv);
  dqacc_du.setZero(nv, nu);
  dqacc_dact.setZero(nv, na);
  dqacc_dapplied.setZero(nv, nv);
  dconstraint_dq.setZero(nv, nv);
  dconstraint_dv.setZero(nv, nv);
  dconstraint_du.setZero(nv, nu);
  dconstraint_dact.setZero(nv, na);
  const int states = 2 * nv + na;  // [dq; qvel; act]
  A.setZero(states, states);
  B.setZero(states, nu);

  const auto nbody = static_cast<std::size_t>(model.nbody);
  const auto ndof = static_cast<std::size_t>(nv);
  work.v.assign(nbody, Motion::Zero());
  work.a.assign(nbody, Motion::Zero());
  work.F.assign(nbody, Force::Zero());
  work.IC.assign(nbody, RigidInertia());
  work.CC.assign(nbody, VelocityCoupling());
  work.CC2.assign(nbody, VelocityCoupling());
  work.momentum.assign(nbody, Force::Zero());
  work.CCt_S.assign(ndof, Eigen::Vector3d::Zero());
  work.v2.assign(nbody, Motion::Zero());
  work.Sdot2.assign(ndof, Motion::Zero());
  work.Sdot.assign(ndof, Motion::Zero());
  work.IC_S.assign(ndof, Force::Zero());
  work.Sddot.assign(ndof, Motion::Zero());
  work.rhs_q.setZero(nv, nv);
  work.rhs_v.setZero(nv, nv);
  work.rhs_u.setZero(nv, nu + na);
  work.right_hand_sides.setZero(nv, 2 * nv + nu + na);
  const int limit_rows_max = 2 * model.njnt;  // limit_rows() sees limit rows alone
  work.MinvJ.setZero(nv, limit_rows_max);
  work.AR.setZero(limit_rows_max, limit_rows_max);
  work.col.setZero(std::max(nv, nefc_max));
  work.drhs_q.setZero(nefc_max);
  work.drhs_v.setZero(nefc_max);
  work.rows.assign(static_cast<std::size_t>(nefc_max), 0);
  work.qacc_step.setZero(nv);
  work.qpos0.setZero(model.nq);
  work.qvel0.setZero(nv);
  work.qvel_next.setZero(nv);
  work.stage_dq.setZero(nv);
  work.Jx.setZero(states, states);
  work.Ju.setZero(states, nu);
  work.Kx.setZero(states, states);
  work.Ku.setZero(states, nu);
  work.act_rate_per_act.setZero(na);
  work.act_rate_per_ctrl.setZero(na);
  work.act0.setZero(na);
  work.act_dot_sum.setZero(na);
  work.moment_times_a.setZero(nv);
  work.length_gradient.setZero(nv);
  work.tendon_change.setZero(nv, nv);
  work.segment_motion.assign(2 * ndof, Eigen::Vector3d::Zero());
  work.tangent_motion.assign(2 * ndof, Eigen::Vector3d::Zero());
  work.K.setZero(nv, nv);
  work.K_lu.setZero(nv, nv);
  work.qvel_change.setZero(nv);
  work.qacc_change.setZero(nv);
  work.contact_Y.setZero(nefc_max, nv);
  work.contact_E.setZero(nv, nv);
  work.contact_H.setZero(nv, nv);
  work.contact_G.setZero(nv, nv);
  work.contact_H_first.assign(ndof, 0);
  // contacts, rows and the tendons' path points (at most two a wrap row), each wrapped geom's side
  const auto active_set_max =
      static_cast<std::size_t>(3 * std::max(0, model.nconmax) + nefc_max + 4 * model.nwrap + 2);
  work.active_set.reserve(active_set_max);
  work.qacc_sum.setZero(nv);
  work.next.emplace(model);
  work.contact_point_velocity.assign(ndof, Eigen::Vector3d::Zero());
  work.equality_point_velocity.assign(2 * ndof, Eigen::Vector3d::Zero());
  work.moment_change.setZero(nv, nv);
  work.moves1.assign(ndof, 0);
  work.moves2.assign(ndof, 0);
  detail::carry_table(model, work.carries);
  detail::branch_table(model, work.branch_first, work.branch_dofs);
  work.pair_changes.assign(ndof * static_cast<std::size_t>(kMaxPairContacts), ContactChange{});
  work.pair_motions.assign(ndof, GeomPairMotion{});
  work.pair_dofs.assign(ndof, 0);
  work.pair_turned.assign(ndof, Derivatives::Workspace::PathSums{});
  work.pair_columns.assign(ndof, Derivatives::Workspace::ColumnWrench{});
}

void forward_derivatives(const Model& model, Data& data, Derivatives& deriv) {
  check_derivative_sizes(model, data, deriv);
  refuse_uncovered(model);
  refuse_stopped_solver(model);
  forward_derivatives_unchecked(model, data, deriv);
}

void applied_force_derivatives(const Model& model, const Data& data, Derivatives& deriv) {
  check_derivative_sizes(model, data, deriv);
  refuse_stopped_solver(model);
  // qfrc_applied enters as f_smooth does: d qacc = G + (rows' part) with G = M^-1 d f, which with
  // the rows held is H^-1 d f (docs/derivatives.md), the same H the contact rows are solved with
  auto& w = deriv.work;
  const int n = detail::held_active_rows(data, w.rows);
  detail::factor_held_rows(data, w.rows.data(), n, w.contact_G, w.contact_H, w.contact_H_first);
  auto X = w.right_hand_sides.leftCols(model.nv);
  X.setIdentity();
  detail::solve_held_rows(w.contact_H, w.contact_H_first, X, w.col.data());
  deriv.dqacc_dapplied = X;
}

void step_derivatives(const Model& model, Data& data, Derivatives& deriv) {
  check_derivative_sizes(model, data, deriv);
  refuse_uncovered(model);
  refuse_stopped_solver(model);
  // forward() normalizes the quaternions of qpos in place; the caller's state is given back as it
  // was, bit for bit (RK4 restores its start itself)
  const bool quaternions = model.nq != model.nv;
  auto& w = deriv.work;
  deriv.active_set_changes = false;
  switch (model.opt.integrator) {
    case Integrator::kEuler:
    case Integrator::kImplicit:
      if (quaternions) w.qpos0 = data.qpos;
      if (model.opt.integrator == Integrator::kEuler) {
        euler_derivatives(model, data, deriv);
      } else {
        implicit_derivatives(model, data, deriv);
      }
      record_active_set(model, data, w.active_set);
      if (quaternions) data.qpos = w.qpos0;
      w.qvel_next = data.qvel + model.opt.timestep * w.qacc_step;
      check_step_end(model, data, deriv, w.qvel_next, w.qacc_step, data.act_dot);
      return;
    case Integrator::kRK4:
      rk4_derivatives(model, data, deriv);
      check_step_end(model, data, deriv, w.qvel_next, w.qacc_sum, w.act_dot_sum);
      return;
    case Integrator::kImplicitFast: break;  // MuJoCo 3's: not differentiated yet
  }
  throw Error("step_derivatives: integrator " +
              std::to_string(static_cast<int>(model.opt.integrator)) +
              " (MuJoCo 3's implicitfast) is not supported yet (Euler, RK4 and implicit are).");
}

}  // namespace lever
