// set_const(): check a model's parameters, derive lever's link tree from them, and compute the
// constants MuJoCo's mj_setConst freezes at qpos0 (engine_setconst.c).
#include <lever/dynamics.hpp>
#include <lever/error.hpp>
#include <lever/fields.hpp>
#include <lever/forward.hpp>
#include <lever/kinematics.hpp>
#include <lever/model.hpp>

#include <atomic>
#include <cmath>
#include <string>

namespace lever {

namespace {

template <typename T>
void require_size(const std::vector<T>& v, int n, const char* name) {
  if (static_cast<int>(v.size()) != n) {
    throw ModelError("model array " + std::string(name) + " has " + std::to_string(v.size()) +
                     " entries where " + std::to_string(n) + " are needed.");
  }
}

#define LEVER_REQUIRE_SIZE(field, n) require_size(model.field, n, #field)

void check_sizes(Model& model) {
  if (model.nbody < 1 || model.nv < 0 || model.njnt < 0 || model.nu < 0 || model.nsite < 0 ||
      model.ngeom < 0) {
    throw ModelError("model sizes must be non-negative and include the world body.");
  }
  LEVER_REQUIRE_SIZE(jnt_type, model.njnt);
  int nq = 0, nv = 0;
  for (const JointType type : model.jnt_type) {
    nq += joint_nq(type);
    nv += joint_nv(type);
  }
  if (model.nq != nq || model.nv != nv) {
    throw ModelError("the joints need nq = " + std::to_string(nq) +
                     " coordinates and nv = " + std::to_string(nv) +
                     " dofs (hinge and slide 1 and 1, ball 4 and 3, free 7 and 6); "
                     "the model says nq = " +
                     std::to_string(model.nq) + ", nv = " + std::to_string(model.nv) + ".");
  }
  LEVER_REQUIRE_SIZE(body_name, model.nbody);
  LEVER_REQUIRE_SIZE(jnt_name, model.njnt);
  LEVER_REQUIRE_SIZE(geom_name, model.ngeom);
  LEVER_REQUIRE_SIZE(site_name, model.nsite);
  LEVER_REQUIRE_SIZE(actuator_name, model.nu);
  LEVER_REQUIRE_SIZE(key_name, model.nkey);
  LEVER_REQUIRE_SIZE(key_time, model.nkey);
  if (model.nkey < 0 || model.key_qpos.rows() != model.nkey || model.key_qpos.cols() != model.nq ||
      model.key_qvel.rows() != model.nkey || model.key_qvel.cols() != model.nv ||
      model.key_ctrl.rows() != model.nkey || model.key_ctrl.cols() != model.nu) {
    throw ModelError(
        "keyframe arrays key_qpos, key_qvel, key_ctrl must be nkey x nq, nkey x nv "
        "and nkey x nu (nkey = " +
        std::to_string(model.nkey) + ").");
  }
  // contact (issue 19): the counts the contact arrays of the field table are sized by
  if (model.npair < 0 || model.nexclude < 0 || model.nconmax < 0 || model.njmax < 0) {
    throw ModelError("npair, nexclude, nconmax and njmax must be non-negative; got " +
                     std::to_string(model.npair) + ", " + std::to_string(model.nexclude) + ", " +
                     std::to_string(model.nconmax) + ", " + std::to_string(model.njmax) + ".");
  }
  // what set_const derives is sized here; every other array must have the size the field table
  // gives it (lever/fields.hpp)
  model.body_rootid.resize(model.nbody);
  model.body_subtreemass.resize(model.nbody);
  model.body_invweight0.resize(model.nbody);
  model.dof_invweight0.resize(model.nv);
  model.dof_M0.resize(model.nv);
  check_model_sizes(model);
}

#undef LEVER_REQUIRE_SIZE

// Parents precede children, joints and dofs follow the body tree, indices are in range.
void check_tree(const Model& model) {
  for (int b = 1; b < model.nbody; ++b) {
    const int p = model.body_parentid[b];
    if (p < 0 || p >= b) {
      throw ModelError("body " + std::to_string(b) + " ('" + model.body_name[b] +
                       "') must come after its parent (parent id " + std::to_string(p) + ").");
    }
  }
  int next_joint = 0, next_qpos = 0, next_dof = 0;
  for (int b = 0; b < model.nbody; ++b) {
    if (model.body_jntnum[b] == 0) continue;
    if (model.body_jntadr[b] != next_joint || model.body_dofadr[b] != next_dof) {
      throw ModelError("the joints and dofs of body '" + model.body_name[b] +
                       "' are not numbered in body order.");
    }
    for (int k = 0; k < model.body_jntnum[b]; ++k, ++next_joint) {
      const int j = next_joint;
      const int dofs = joint_nv(model.jnt_type[j]);
      bool wired = model.jnt_bodyid[j] == b && model.jnt_qposadr[j] == next_qpos &&
                   model.jnt_dofadr[j] == next_dof;
      for (int i = next_dof; wired && i < next_dof + dofs; ++i) {
        wired = model.dof_jntid[i] == j && model.dof_bodyid[i] == b;
      }
      if (!wired) {
        throw ModelError("joint " + std::to_string(j) + " is not wired to body '" +
                         model.body_name[b] + "' consistently.");
      }
      // MuJoCo's rule: a free joint moves a body of the world alone (its pose is its qpos)
      if (model.jnt_type[j] == JointType::kFree &&
          (model.body_parentid[b] != 0 || model.body_jntnum[b] != 1)) {
        throw ModelError("joint '" + model.jnt_name[j] + "' is free, so its body '" +
                             model.body_name[b] +
                             "' must be a child of the world with no other joint.",
                         "joint", j);
      }
      next_qpos += joint_nq(model.jnt_type[j]);
      next_dof += dofs;
    }
    if (model.body_dofnum[b] != next_dof - model.body_dofadr[b]) {
      throw ModelError("body '" + model.body_name[b] + "' has " +
                       std::to_string(model.body_dofnum[b]) + " dofs recorded and " +
                       std::to_string(next_dof - model.body_dofadr[b]) + " in its joints.");
    }
  }
  // each dof's parent is the previous dof on its path to the world
  std::vector<int> last_dof(model.nbody, -1);
  for (int b = 1; b < model.nbody; ++b) {
    int previous = last_dof[model.body_parentid[b]];
    for (int k = 0; k < model.body_dofnum[b]; ++k) {
      const int i = model.body_dofadr[b] + k;
      if (model.dof_parentid[i] != previous) {
        throw ModelError("dof " + std::to_string(i) + "'s parent must be dof " +
                         std::to_string(previous) + ", the previous dof on its path to the world.");
      }
      previous = i;
    }
    last_dof[b] = previous;
  }
  for (int j = 0; j < model.njnt; ++j) {
    const JointType type = model.jnt_type[j];
    if (type != JointType::kHinge && type != JointType::kSlide && type != JointType::kBall &&
        type != JointType::kFree) {
      throw ModelError("joint " + std::to_string(j) + " has type " +
                       std::to_string(static_cast<int>(type)) +
                       ", which is none of free (0), ball (1), slide (2) and hinge (3).");
    }
    // a ball's limit is a cone MuJoCo bounds by the rotation angle: not in lever yet
    if (type == JointType::kBall && model.jnt_limited[j]) {
      throw ModelError("joint '" + model.jnt_name[j] +
                           "' is a limited ball joint; lever limits hinge and slide joints only "
                           "(remove limited=\"true\" or use hinges).",
                       "joint", j);
    }
    if (type == JointType::kFree && model.jnt_limited[j]) {
      throw ModelError("joint '" + model.jnt_name[j] + "' is free and cannot be limited.", "joint",
                       j);
    }
    if ((type == JointType::kHinge || type == JointType::kSlide) &&
        std::abs(model.jnt_axis[j].norm() - 1.0) > 1e-10) {
      throw ModelError("joint " + std::to_string(j) + "'s axis is not a unit vector.");
    }
  }
  for (int s = 0; s < model.nsite; ++s) {
    if (model.site_bodyid[s] < 0 || model.site_bodyid[s] >= model.nbody) {
      throw ModelError("site " + std::to_string(s) + " names no body.");
    }
  }
  for (int a = 0; a < model.nu; ++a) {
    const int j = model.actuator_trnid[a];
    if (j < 0 || j >= model.njnt) {
      throw ModelError("actuator " + std::to_string(a) + " names no joint.");
    }
    if (model.jnt_type[j] != JointType::kHinge && model.jnt_type[j] != JointType::kSlide) {
      throw ModelError("actuator '" + model.actuator_name[a] + "' drives joint '" +
                           model.jnt_name[j] +
                           "', a ball or free joint; lever's actuators drive hinges and slides.",
                       "actuator", a);
    }
  }
}

bool is_identity(const Quat& q) { return q[0] == 1.0 && q[1] == 0.0 && q[2] == 0.0 && q[3] == 0.0; }

// Each body's world child, and the subtree masses (summed leaves to root).
void build_tree_sums(Model& model) {
  model.body_rootid.assign(model.nbody, 0);
  for (int b = 1; b < model.nbody; ++b) {
    const int p = model.body_parentid[b];
    model.body_rootid[b] = p == 0 ? b : model.body_rootid[p];
  }
  model.body_subtreemass.assign(model.body_mass.begin(), model.body_mass.end());
  for (int b = model.nbody - 1; b > 0; --b) {
    model.body_subtreemass[model.body_parentid[b]] += model.body_subtreemass[b];
  }
}

// Rotation matrices of the constant quaternions, and whether each is the identity.
// A hinge whose axis is exactly +-1 along one coordinate axis of its body and zero along the
// others is dispatched to the kernels that leave the zeros out (bit for bit the general product).
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

// The actuators' kinds (lever/model.hpp), from their current parameters.
void build_actuator_kinds(Model& model) {
  model.actuator_kind.resize(model.nu);
  for (int a = 0; a < model.nu; ++a) {
    model.actuator_kind[a] =
        actuator_kind_of(model.actuator_gaintype[a], model.actuator_gainprm[a],
                         model.actuator_biastype[a], model.actuator_biasprm[a]);
  }
}

// R as a quarter turn (lever/model.hpp AxisMap), or {0, 0, 0}: every entry within 1e-15 of 0 or
// +-1, so that a normalized quaternion's rounding (1/sqrt(2) squared) still counts.
AxisMap axis_map(const Mat3& R) {
  constexpr double kRounding = 1e-15;
  AxisMap map{0, 0, 0};
  for (int c = 0; c < 3; ++c) {
    for (int k = 0; k < 3; ++k) {
      const double x = R(k, c);
      if (std::abs(x) <= kRounding) continue;
      if (std::abs(std::abs(x) - 1.0) > kRounding || map[c] != 0) return AxisMap{0, 0, 0};
      map[c] = static_cast<int8_t>(x > 0 ? k + 1 : -(k + 1));
    }
    if (map[c] == 0) return AxisMap{0, 0, 0};
  }
  return map;
}

void build_rotations(Model& model) {
  model.body_rotated.resize(model.nbody);
  model.body_mat.resize(model.nbody);
  model.body_imat.resize(model.nbody);
  model.body_irotated.resize(model.nbody);
  model.body_axismap.resize(model.nbody);
  model.body_iaxismap.resize(model.nbody);
  for (int b = 0; b < model.nbody; ++b) {
    model.body_rotated[b] = !is_identity(model.body_quat[b]);
    model.body_mat[b] = quat_to_mat(quat_normalized(model.body_quat[b]));
    model.body_imat[b] = quat_to_mat(quat_normalized(model.body_iquat[b]));
    model.body_irotated[b] = !is_identity(model.body_iquat[b]);
    model.body_axismap[b] = axis_map(model.body_mat[b]);
    model.body_iaxismap[b] = axis_map(model.body_imat[b]);
  }
  model.geom_mat.resize(model.ngeom);
  model.geom_rotated.resize(model.ngeom);
  model.geom_axismap.resize(model.ngeom);
  for (int g = 0; g < model.ngeom; ++g) {
    model.geom_mat[g] = quat_to_mat(quat_normalized(model.geom_quat[g]));
    model.geom_rotated[g] = !is_identity(model.geom_quat[g]);
    model.geom_axismap[g] = axis_map(model.geom_mat[g]);
  }
  model.site_mat.resize(model.nsite);
  model.site_rotated.resize(model.nsite);
  model.site_axismap.resize(model.nsite);
  for (int s = 0; s < model.nsite; ++s) {
    model.site_mat[s] = quat_to_mat(quat_normalized(model.site_quat[s]));
    model.site_rotated[s] = !is_identity(model.site_quat[s]);
    model.site_axismap[s] = axis_map(model.site_mat[s]);
  }
  model.jnt_kind.resize(model.njnt);
  model.jnt_offset.resize(model.njnt);
  for (int j = 0; j < model.njnt; ++j) {
    model.jnt_kind[j] = joint_kind(model, j);
    model.jnt_offset[j] = !model.jnt_pos[j].isZero(0.0);
  }
}

template <typename Vector>
bool finite(const Vector& v) {
  for (const double x : v) {
    if (!std::isfinite(x)) return false;
  }
  return true;
}

[[noreturn]] void reject(const std::string& what, int index, const std::string& name,
                         const std::string& why) {
  throw ModelError(what + " '" + name + "' " + why + ".", what, index);
}

// Finite numbers everywhere, a positive timestep, valid quaternions, ranges with lo < hi where
// they are used, and no negative armature, damping or stiffness (each would make the model gain
// energy from nothing; MuJoCo 2.2.2 accepts them silently).
void check_parameters(const Model& model) {
  if (!(model.opt.timestep > 0) || !std::isfinite(model.opt.timestep)) {
    throw ModelError("the timestep must be a positive number of seconds; it is " +
                     std::to_string(model.opt.timestep) + ".");
  }
  if (!model.opt.gravity.allFinite()) throw ModelError("gravity must be finite.");
  for (int b = 1; b < model.nbody; ++b) {
    const std::string& n = model.body_name[b];
    if (!model.body_pos[b].allFinite() || !model.body_ipos[b].allFinite()) {
      reject("body", b, n, "has a non-finite position");
    }
    for (const Quat* q : {&model.body_quat[b], &model.body_iquat[b]}) {
      if (!q->allFinite() || q->norm() < 1e-10)
        reject("body", b, n, "has a zero or non-finite quaternion");
    }
  }
  for (int j = 0; j < model.njnt; ++j) {
    const std::string& n = model.jnt_name[j];
    if (!model.jnt_pos[j].allFinite()) reject("joint", j, n, "has a non-finite anchor");
    if (!finite(model.jnt_solref[j]) || !finite(model.jnt_solimp[j]) ||
        !std::isfinite(model.jnt_margin[j])) {
      reject("joint", j, n, "has non-finite limit parameters");
    }
    if (model.jnt_limited[j] &&
        !(model.jnt_range[j][0] < model.jnt_range[j][1] && finite(model.jnt_range[j]))) {
      reject("joint", j, n, "is limited but its range is not finite with lo < hi");
    }
    for (int d = model.jnt_dofadr[j]; d < model.jnt_dofadr[j] + joint_nv(model.jnt_type[j]); ++d) {
      if (!(model.dof_armature[d] >= 0) || !(model.dof_damping[d] >= 0) ||
          !(model.jnt_stiffness[j] >= 0) || !std::isfinite(model.dof_armature[d]) ||
          !std::isfinite(model.dof_damping[d]) || !std::isfinite(model.jnt_stiffness[j])) {
        reject("joint", j, n, "needs finite, non-negative armature, damping and stiffness");
      }
    }
  }
  if (!model.qpos0.allFinite() || !model.qpos_spring.allFinite()) {
    throw ModelError("qpos0 and qpos_spring must be finite.");
  }
  for (int s = 0; s < model.nsite; ++s) {
    if (!model.site_pos[s].allFinite() || !model.site_quat[s].allFinite() ||
        model.site_quat[s].norm() < 1e-10) {
      reject("site", s, model.site_name[s], "has a non-finite position or a zero quaternion");
    }
  }
  for (int a = 0; a < model.nu; ++a) {
    const std::string& n = model.actuator_name[a];
    if (!finite(model.actuator_gear[a])) reject("actuator", a, n, "has a non-finite gear");
    const auto& c = model.actuator_ctrlrange[a];
    const auto& f = model.actuator_forcerange[a];
    if (model.actuator_ctrllimited[a] && !(c[0] < c[1] && finite(c))) {
      reject("actuator", a, n, "is ctrllimited but its ctrlrange is not finite with lo < hi");
    }
    if (model.actuator_forcelimited[a] && !(f[0] < f[1] && finite(f))) {
      reject("actuator", a, n, "is forcelimited but its forcerange is not finite with lo < hi");
    }
    const int gaintype = static_cast<int>(model.actuator_gaintype[a]);
    const int biastype = static_cast<int>(model.actuator_biastype[a]);
    if (model.actuator_dyntype[a] != DynType::kNone || gaintype < 0 || gaintype > 1 ||
        biastype < 0 || biastype > 1) {
      reject("actuator", a, n,
             "needs dyntype none, gaintype fixed or affine and biastype none or affine");
    }
    if (!finite(model.actuator_gainprm[a]) || !finite(model.actuator_biasprm[a])) {
      reject("actuator", a, n, "has a non-finite gainprm or biasprm");
    }
  }
  for (int k = 0; k < model.nkey; ++k) {
    if (!std::isfinite(model.key_time[k]) || !model.key_qpos.row(k).allFinite() ||
        !model.key_qvel.row(k).allFinite() || !model.key_ctrl.row(k).allFinite()) {
      reject("keyframe", k, model.key_name[k], "has a non-finite time, qpos, qvel or ctrl");
    }
  }
}

// Non-negative, finite masses and inertias.
void check_mass(const Model& model) {
  for (int b = 1; b < model.nbody; ++b) {
    const double m = model.body_mass[b];
    const Eigen::Vector3d& I = model.body_inertia[b];
    if (!std::isfinite(m) || m < 0 || !I.allFinite() || (I.array() < 0).any()) {
      throw ModelError(
          "body '" + model.body_name[b] + "' has a negative or non-finite mass or inertia.", "body",
          b);
    }
  }
}

// The model evaluated once at qpos0, at rest and without control: every number must be finite and
// the acceleration within MuJoCo's 1e10 (mju_isBad). Finite parameters can still overflow (an
// offset of 1e300, a gravity of 1e308); such a model would give NaN on its first evaluation, or
// be reset by every step (mj_step's mj_checkAcc). MuJoCo 2.2.2 loads it; lever says which object
// overflows instead.
void check_at_qpos0(const Model& model, Data& data) {
  data.qpos = model.qpos0;
  data.qvel.setZero();
  data.ctrl.setZero();
  data.qfrc_applied.setZero();
  forward(model, data);
  compute_energy(model, data);
  const char* const too_large = "gives non-finite numbers at qpos0: its numbers are too large";
  // first the bodies' own frames (so that the body at fault is named, not its parent, whose
  // subtree quantities include it), then what combines several bodies
  for (int b = 1; b < model.nbody; ++b) {
    const bool ok = data.xpos[b].allFinite() && data.xmat[b].allFinite() &&
                    data.xipos[b].allFinite() && data.ximat[b].allFinite();
    if (!ok) reject("body", b, model.body_name[b], too_large);
  }
  for (int b = 1; b < model.nbody; ++b) {
    const RigidInertia& c = data.cinert[b];
    const bool ok = data.subtree_com[b].allFinite() && std::isfinite(c.m) && c.h.allFinite() &&
                    c.I.allFinite() && finite(model.body_invweight0[b]);
    if (!ok) reject("body", b, model.body_name[b], too_large);
  }
  for (int j = 0; j < model.njnt; ++j) {
    const int d = model.jnt_dofadr[j];
    const bool ok = data.xanchor[j].allFinite() && data.xaxis[j].allFinite() &&
                    data.cdof[d].allFinite() && data.M.row(d).allFinite() &&
                    std::isfinite(data.qfrc_bias[d]) && std::isfinite(data.qfrc_passive[d]) &&
                    std::isfinite(model.dof_invweight0[d]) && std::isfinite(model.dof_M0[d]);
    if (!ok) reject("joint", j, model.jnt_name[j], too_large);
    if (!(std::abs(data.qacc[d]) <= 1e10)) {
      reject("joint", j, model.jnt_name[j],
             "accelerates at more than 1e10 at rest at qpos0 (MuJoCo's limit for a diverged "
             "state, which every step would reset): its masses, inertias or gravity are out of "
             "scale");
    }
  }
  for (int s = 0; s < model.nsite; ++s) {
    if (!data.site_xpos[s].allFinite() || !data.site_xmat[s].allFinite()) {
      reject("site", s, model.site_name[s], too_large);
    }
  }
  if (!std::isfinite(data.energy[0])) {
    throw ModelError(
        "the model's potential energy at qpos0 is not finite: its numbers are too large.");
  }
}

// Whether the collision stage can find anything (see Model::contacts_possible).
bool contacts_possible(const Model& model) {
  const auto n = static_cast<size_t>(model.ngeom);
  const bool has_parameters = model.geom_friction.size() == n && model.geom_condim.size() == n &&
                              model.geom_margin.size() == n;
  if (!has_parameters || model.opt.contact_disabled) return false;
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

void set_const(Model& model) {
  check_sizes(model);
  check_tree(model);
  check_parameters(model);
  check_mass(model);
  build_tree_sums(model);
  build_rotations(model);
  build_actuator_kinds(model);
  // the constants and the checks at qpos0 are about the parameters: computed without contacts
  model.contacts_possible = false;
  static std::atomic<std::uint64_t> last_tag{0};
  model.fit_tag = ++last_tag;

  // constants at qpos0: diag of M and of M^-1, and the bodies' mean inverse inertias
  Data data(model);
  data.qpos = model.qpos0;
  kinematics(model, data);
  crba(model, data);
  factor_mass(model, data);
  model.dof_M0.resize(model.nv);
  model.dof_invweight0.resize(model.nv);
  Eigen::VectorXd x(model.nv);
  for (int i = 0; i < model.nv; ++i) {
    model.dof_M0[i] = data.M(i, i);
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
  model.body_invweight0.assign(model.nbody, {0.0, 0.0});
  Eigen::MatrixXd jacp(3, model.nv), jacr(3, model.nv), Minv_Jt(model.nv, 3);
  for (int b = 1; b < model.nbody; ++b) {
    jac_point(model, data, b, data.xipos[b], jacp, jacr);
    std::array<double, 2> weight{0.0, 0.0};
    for (int part = 0; part < 2; ++part) {
      const Eigen::MatrixXd& J = part == 0 ? jacp : jacr;
      Minv_Jt = J.transpose();
      for (int c = 0; c < 3; ++c) solve_mass(model, data, Minv_Jt.col(c));
      weight[part] = (J * Minv_Jt).trace() / 3.0;
    }
    model.body_invweight0[b] = weight;
  }
  check_at_qpos0(model, data);

  // from here on a Data of this model makes room for contact rows, and forward() collides: a
  // new edition, so that Data made before are checked again
  model.contacts_possible = contacts_possible(model);
  model.fit_tag = ++last_tag;
}

}  // namespace lever
