// set_const(): compute what follows from a model's parameters, once validate() (model_check.cpp)
// has accepted them: the constants MuJoCo's mj_setConst freezes at qpos0 (engine_setconst.c), and
// lever's constant rotations, joint and actuator kinds, and the frames of the bodies welded to
// the world.
#include <lever/dynamics.hpp>
#include <lever/forward.hpp>
#include <lever/kinematics.hpp>
#include <lever/model.hpp>
#include <lever/model_check.hpp>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <string>

#include "lifecycle/lifecycle.hpp"
#include "collision/collision_room.hpp"
#include "constraint/constraint_room.hpp"

namespace lever {

namespace {

bool is_identity(const Quat& q) { return q[0] == 1.0 && q[1] == 0.0 && q[2] == 0.0 && q[3] == 0.0; }

// The subtree masses (summed leaves to root).
void build_subtree_masses(Model& model) {
  std::copy(model.body_mass.begin(), model.body_mass.end(), model.body_subtreemass.begin());
  for (int b = model.nbody - 1; b > 0; --b) {
    model.body_subtreemass[model.body_parentid[b]] += model.body_subtreemass[b];
  }
}

// A joint's kind (lever/model.hpp JointKind). A hinge whose axis is exactly +-1 along one
// coordinate axis of its body and zero along the others is dispatched to the kernels that leave the
// zeros out (bit for bit the general product).
JointKind joint_kind(const Model& model, int j) {
  switch (model.jnt_type[j]) {
    case JointType::kFree: return JointKind::kFree;
    case JointType::kBall: return JointKind::kBall;
    case JointType::kSlide: return JointKind::kSlide;
    case JointType::kHinge: break;
  }
  const Eigen::Vector3d& a = model.jnt_axis[j];
  constexpr JointKind kAligned[3] = {JointKind::kHingeX, JointKind::kHingeY, JointKind::kHingeZ};
  for (int k = 0; k < 3; ++k) {
    const bool others_zero = a[(k + 1) % 3] == 0.0 && a[(k + 2) % 3] == 0.0;
    if (others_zero && std::abs(a[k]) == 1.0) return kAligned[k];
  }
  return JointKind::kHinge;
}

// The actuators' kinds (lever/model.hpp) and the dofs they drive alone, from their current
// parameters.
void build_actuator_kinds(Model& model) {
  for (int a = 0; a < model.nu; ++a) {
    model.actuator_scalar_dof[a] = actuator_scalar_dof(model, a);
    // an actuator with dynamics, a muscle's curves or a user part is none of the simple kinds
    const bool simple = model.actuator_dyntype[a] == DynType::kNone &&
                        model.actuator_gaintype[a] != GainType::kMuscle &&
                        model.actuator_biastype[a] != BiasType::kMuscle &&
                        model.actuator_gaintype[a] != GainType::kUser &&
                        model.actuator_biastype[a] != BiasType::kUser;
    model.actuator_kind[a] =
        simple ? actuator_kind_of(model.actuator_gaintype[a], model.actuator_gainprm[a],
                                  model.actuator_biastype[a], model.actuator_biasprm[a])
               : ActuatorKind::kGeneral;
  }
}

// Whether R is a quarter turn (every entry within 1e-15 of 0 or +-1, so that a normalized
// quaternion's rounding, 1/sqrt(2) squared, still counts); if so, its columns into `f`.
bool is_quarter_turn(const Mat3& R, FramePlacement& f) {
  constexpr double kRounding = 1e-15;
  for (int c = 0; c < 3; ++c) {
    int found = 0;
    for (int k = 0; k < 3; ++k) {
      const double x = R(k, c);
      if (std::abs(x) <= kRounding) continue;
      if (std::abs(std::abs(x) - 1.0) > kRounding || found++ > 0) return false;
      f.column[c] = static_cast<uint8_t>(k);
      f.sign[c] = x > 0 ? 1.0 : -1.0;
    }
    if (found == 0) return false;
  }
  return true;
}

// How kinematics() places a constant frame at offset v, rotation R (of quaternion q).
FramePlacement placement(const Eigen::Vector3d& v, const Quat& q, const Mat3& R) {
  FramePlacement f;
  int nonzero = 0;
  for (int k = 0; k < 3; ++k) {
    if (v[k] == 0.0) continue;
    ++nonzero;
    f.axis = static_cast<uint8_t>(k);
  }
  using Offset = FramePlacement::Offset;
  f.offset = nonzero == 0 ? Offset::kZero : nonzero == 1 ? Offset::kAlongAxis : Offset::kGeneral;
  if (is_identity(q)) {
    f.turn = FramePlacement::Turn::kNone;
  } else if (is_quarter_turn(R, f)) {
    f.turn = FramePlacement::Turn::kQuarter;
  } else {
    f.turn = FramePlacement::Turn::kGeneral;
  }
  return f;
}

void build_rotations(Model& model) {
  for (int b = 0; b < model.nbody; ++b) {
    model.body_mat[b] = quat_to_mat(quat_normalized(model.body_quat[b]));
    model.body_imat[b] = quat_to_mat(quat_normalized(model.body_iquat[b]));
    model.body_placement[b] = placement(model.body_pos[b], model.body_quat[b], model.body_mat[b]);
    model.body_iplacement[b] =
        placement(model.body_ipos[b], model.body_iquat[b], model.body_imat[b]);
  }
  for (int g = 0; g < model.ngeom; ++g) {
    model.geom_mat[g] = quat_to_mat(quat_normalized(model.geom_quat[g]));
    model.geom_placement[g] = placement(model.geom_pos[g], model.geom_quat[g], model.geom_mat[g]);
  }
  for (int s = 0; s < model.nsite; ++s) {
    model.site_mat[s] = quat_to_mat(quat_normalized(model.site_quat[s]));
    model.site_placement[s] = placement(model.site_pos[s], model.site_quat[s], model.site_mat[s]);
  }
  for (int j = 0; j < model.njnt; ++j) {
    model.jnt_kind[j] = joint_kind(model, j);
    model.jnt_offset[j] = !model.jnt_pos[j].isZero(0.0);
  }
}

// Whether the collision stage can find anything (see Model::contacts_possible).
bool contacts_possible(const Model& model) {
  const auto n = static_cast<size_t>(model.ngeom);
  const bool has_parameters = model.geom_friction.size() == n && model.geom_condim.size() == n &&
                              model.geom_margin.size() == n;
  if (!has_parameters || model.opt.disabled(kDisableContact) ||
      model.opt.disabled(kDisableConstraint)) return false;
  if (model.npair > 0) return true;
  for (int g1 = 0; g1 < model.ngeom; ++g1) {
    for (int g2 = g1 + 1; g2 < model.ngeom; ++g2) {
      const int b1 = model.geom_bodyid[g1], b2 = model.geom_bodyid[g2];
      if (b1 == b2 || (b1 == 0 && b2 == 0)) continue;
      if ((model.geom_contype[g1] & model.geom_conaffinity[g2]) ||
          (model.geom_contype[g2] & model.geom_conaffinity[g1])) {
        return true;
      }
    }
  }
  return false;
}

// MuJoCo's simple bodies (Model::body_simple), by its compiler's rule: the inertial frame is the
// body's own (exactly: ipos zero, iquat the identity); the body is a child of the world, or of a
// body without dofs that is one; it has no child body; each joint is at its origin, a hinge's or
// slide's axis has one nonzero component, and no joint follows one that turns (hinge, ball). Such
// a body's block of M is diagonal and constant: translations along fixed axes weigh its mass,
// turns about its centre of mass its principal moments. Its dofs then count down to its last
// (dof_simplenum).
void build_simple_bodies(Model& model) {
  std::fill(model.body_simple.begin(), model.body_simple.end(), 0);
  for (int b = 0; b < model.nbody; ++b) {
    const int parent = model.body_parentid[b];
    const bool same_frame = model.body_ipos[b].isZero(0.0) && is_identity(model.body_iquat[b]);
    const bool on_world = model.body_rootid[b] == b ||
                          (model.body_parentid[parent] == 0 && model.body_dofnum[parent] == 0);
    bool simple = same_frame && on_world;
    if (parent > 0) model.body_simple[parent] = 0;  // a body with a child is not simple
    bool turned = false;
    for (int j = model.body_jntadr[b]; j < model.body_jntadr[b] + model.body_jntnum[b]; ++j) {
      const JointType type = model.jnt_type[j];
      const Eigen::Vector3d& axis = model.jnt_axis[j];
      const int components = (axis[0] != 0) + (axis[1] != 0) + (axis[2] != 0);
      const bool along_one_axis =
          (type != JointType::kHinge && type != JointType::kSlide) || components <= 1;
      if (turned || !model.jnt_pos[j].isZero(0.0) || !along_one_axis) simple = false;
      if (type == JointType::kHinge || type == JointType::kBall) turned = true;
    }
    model.body_simple[b] = simple;
  }
  std::fill(model.dof_simplenum.begin(), model.dof_simplenum.end(), 0);
  model.has_simple_dofs = false;
  for (int i = model.nv - 1, count = 0; i >= 0; --i) {
    count = model.body_simple[model.dof_bodyid[i]] ? count + 1 : 0;
    model.dof_simplenum[i] = count;
    model.has_simple_dofs = model.has_simple_dofs || count > 0;
  }
}

// The bodies welded to the world (Model::body_static): no joint, no mocap body, the parent the
// world or such a body (a parent comes before its children). Their frames are taken from `data`,
// placed at some qpos by kinematics() while body_static_leading was 0: they depend on no
// coordinate, so these are the frames every later call would compose, bit for bit.
void build_static_bodies(Model& model, const Data& data) {
  int leading = 0;  // bodies 1..leading are welded to the world
  for (int b = 0; b < model.nbody; ++b) {
    const int parent = model.body_parentid[b];
    const bool on_world = parent == 0 || model.body_static[parent];
    const bool fixed = b > 0 && on_world && model.body_jntnum[b] == 0 && model.body_mocapid[b] < 0;
    model.body_static[b] = fixed;
    model.body_static_xpos[b] = fixed ? data.xpos[b] : Eigen::Vector3d::Zero();
    model.body_static_xquat[b] = fixed ? data.xquat[b] : Eigen::Vector4d::Zero();
    model.body_static_xmat[b] = fixed ? data.xmat[b] : Mat3::Zero();
    model.body_static_xipos[b] = fixed ? data.xipos[b] : Eigen::Vector3d::Zero();
    model.body_static_ximat[b] = fixed ? data.ximat[b] : Mat3::Zero();
    if (fixed && b == leading + 1) leading = b;
  }
  model.body_static_leading = leading;
}

}  // namespace

ActuatorKind actuator_kind_of(GainType gaintype, const std::array<double, kGainParameters>& g,
                              BiasType biastype, const std::array<double, kBiasParameters>& b) {
  const bool affine_bias = biastype == BiasType::kAffine;
  if (affine_bias && g[0] != 0 && b[1] == -g[0]) return ActuatorKind::kPositionServo;
  if (affine_bias && g[0] != 0 && b[1] == 0 && b[2] == -g[0]) return ActuatorKind::kVelocityServo;
  const bool state_bias = affine_bias && (b[1] != 0 || b[2] != 0);
  const bool state_gain = gaintype == GainType::kAffine && (g[1] != 0 || g[2] != 0);
  return state_bias || state_gain ? ActuatorKind::kGeneral : ActuatorKind::kMotor;
}

namespace {

// The tendons' constants (mj_setConst): each length at qpos0 and its inverse weight J M^-1 J^T
// there (data: kinematics and M's factor at qpos0), then a negative spring length replaced by the
// length at qpos_spring.
void build_tendon_constants(Model& model, Data& data) {
  std::fill(model.tendon_length0.begin(), model.tendon_length0.end(), 0.0);
  std::fill(model.tendon_invweight0.begin(), model.tendon_invweight0.end(), 0.0);
  if (model.ntendon == 0) return;
  tendon(model, data);
  Eigen::VectorXd x(model.nv);
  for (int t = 0; t < model.ntendon; ++t) {
    model.tendon_length0[t] = data.ten_length[t];
    x = data.ten_J.row(t).transpose();
    solve_mass(model, data, x);
    // summed as mju_dot sums it (a tendon limit's R is proportional to it)
    model.tendon_invweight0[t] =
        dot_as_mujoco(data.ten_J.row(t).data(), x.data(), 0, model.nv, model.nv);
  }
  // a spatial tendon's length needs the sites (and wrapping geoms) placed at qpos_spring
  const Eigen::VectorXd qpos = data.qpos;
  data.qpos = model.qpos_spring;
  kinematics(model, data);
  tendon(model, data);
  for (int t = 0; t < model.ntendon; ++t) {
    if (model.tendon_lengthspring[t] < 0) model.tendon_lengthspring[t] = data.ten_length[t];
  }
  data.qpos = qpos;
  kinematics(model, data);
  tendon(model, data);
}

// The actuators' constants (mj_setConst): each length at qpos0 and the norm of M^-1 times its
// moment there (data: kinematics, tendons and M's factor at qpos0).
void build_actuator_constants(Model& model, Data& data) {
  std::fill(model.actuator_length0.begin(), model.actuator_length0.end(), 0.0);
  std::fill(model.actuator_acc0.begin(), model.actuator_acc0.end(), 0.0);
  if (model.nu == 0) return;
  transmission(model, data);
  Eigen::VectorXd x(model.nv);
  for (int a = 0; a < model.nu; ++a) {
    model.actuator_length0[a] = data.actuator_length[a];
    if (model.nv == 0) continue;
    x = data.actuator_moment.row(a).transpose();
    solve_mass(model, data, x);
    model.actuator_acc0[a] = std::sqrt(dot_as_mujoco(x.data(), x.data(), 0, model.nv, model.nv));
  }
}

}  // namespace

void set_const(Model& model) {
  validate(model);  // lever/model_check.hpp: nothing below runs on a model it refuses
  build_subtree_masses(model);
  build_rotations(model);
  build_actuator_kinds(model);
  model.tendons_wrap_geoms = std::any_of(model.wrap_type.begin(), model.wrap_type.end(), [](WrapType w) {
    return w == WrapType::kSphere || w == WrapType::kCylinder;
  });
  model.has_body_transmission =
      std::find(model.actuator_trntype.begin(), model.actuator_trntype.end(),
                TransmissionType::kBody) != model.actuator_trntype.end();
  const auto positive = [](double loss) { return loss > 0; };
  model.has_friction_loss =
      std::any_of(model.dof_frictionloss.begin(), model.dof_frictionloss.end(), positive) ||
      std::any_of(model.tendon_frictionloss.begin(), model.tendon_frictionloss.end(), positive);
  detail::build_collision_constants(model);
  // the constants and the checks at qpos0 are about the parameters: computed without contacts
  model.contacts_possible = false;
  static std::atomic<std::uint64_t> last_tag{0};
  model.fit_tag = ++last_tag;

  // constants at qpos0: diag of M and of M^-1, and the bodies' mean inverse inertias; M computed
  // whole (no dof simple yet: crba() would copy the simple ones' diagonal from dof_M0)
  std::fill(model.dof_simplenum.begin(), model.dof_simplenum.end(), 0);
  model.has_simple_dofs = false;
  // every body placed from its parameters, none copied from frames an earlier edition stored
  model.body_static_leading = 0;
  Data data(model);
  data.qpos = model.qpos0;
  kinematics(model, data);
  crba(model, data);
  for (int i = 0; i < model.nv; ++i) model.dof_M0[i] = data.M(i, i);
  // the factor MuJoCo's solves at qpos0 use: the whole M, its simple dofs (marked by its compiler
  // before mj_setConst) left out of the elimination. Their blocks are diagonal but for rounding
  // (a principal inertia turned into the world's axes and back), which the solves then ignore.
  build_simple_bodies(model);  // crba() copies their dofs' diagonal from dof_M0 from now on
  factor_mass(model, data);
  Eigen::VectorXd x(model.nv);
  for (int i = 0; i < model.nv; ++i) {
    x.setZero();
    x[i] = 1.0;
    solve_mass(model, data, x);
    model.dof_invweight0[i] = x[i];
  }
  // a ball's three dofs share the mean of their diagonal entries, as a free joint's translations
  // and its rotations do (mj_setConst: one weight per direction-free group)
  for (int j = 0; j < model.njnt; ++j) {
    const JointType type = model.jnt_type[j];
    if (type != JointType::kBall && type != JointType::kFree) continue;
    for (int first = model.jnt_dofadr[j]; first < model.jnt_dofadr[j] + joint_nv(type);
         first += 3) {
      double* w = &model.dof_invweight0[first];
      const double mean = (w[0] + w[1] + w[2]) / 3;
      w[0] = w[1] = w[2] = mean;
    }
  }
  std::fill(model.body_invweight0.begin(), model.body_invweight0.end(),
            std::array<double, 2>{0.0, 0.0});
  // a body's weights: the mean of the diagonal of J M^-1 J^T, its translational and its
  // rotational 3 x 3 block at its centre of mass, each entry summed over the dofs as mju_dot sums
  // it (MuJoCo's mju_mulMatMatT): a contact's R is proportional to it, so its last bit is efc_D's
  Eigen::MatrixXd jacp(3, model.nv), jacr(3, model.nv), Jt(model.nv, 3), Minv_Jt(model.nv, 3);
  for (int b = 1; b < model.nbody; ++b) {
    jac_point(model, data, b, data.xipos[b], jacp, jacr);
    std::array<double, 2> weight{0.0, 0.0};
    for (int part = 0; part < 2; ++part) {
      Jt = (part == 0 ? jacp : jacr).transpose();
      Minv_Jt = Jt;
      for (int c = 0; c < 3; ++c) solve_mass(model, data, Minv_Jt.col(c));
      double diagonal[3];
      for (int c = 0; c < 3; ++c) {
        diagonal[c] = dot_as_mujoco(Jt.col(c).data(), Minv_Jt.col(c).data(), 0, model.nv, model.nv);
      }
      weight[part] = (diagonal[0] + diagonal[1] + diagonal[2]) / 3;
    }
    model.body_invweight0[b] = weight;
  }
  build_tendon_constants(model, data);
  build_actuator_constants(model, data);
  complete_equality_data(model, data);  // constraint/equality.cpp: anchors at qpos0
  detail::check_at_qpos0(model, data);  // model_check.cpp: finite parameters can still overflow
  build_static_bodies(model, data);  // kinematics() copies their frames from now on

  // from here on a Data of this model makes room for contact rows, and forward() collides: a
  // new edition, so that Data made before are checked again
  model.contacts_possible = contacts_possible(model);
  model.fit_tag = ++last_tag;
}

}  // namespace lever
