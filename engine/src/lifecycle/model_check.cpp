// validate(): whether a model's parameters make a model lever can evaluate (see
// lever/model_check.hpp), and the check of the model evaluated once at qpos0 that set_const runs
// after computing its constants.
#include <lever/dynamics.hpp>
#include <lever/error.hpp>
#include <lever/fields.hpp>
#include <lever/forward.hpp>
#include <lever/model_check.hpp>

#include <cmath>
#include <cstdint>
#include <sstream>
#include <string>
#include <string_view>

#include "lifecycle/lifecycle.hpp"

namespace lever {

namespace {

// ---- naming the object at fault ----------------------------------------------------------------

[[noreturn]] void reject(const std::string& what, int index, const std::string& name,
                         const std::string& why) {
  const std::string label = name.empty() ? std::to_string(index) : "'" + name + "'";
  throw ModelError(what + " " + label + " " + why + ".", what, index);
}

// The object a row of a Model array belongs to: the body, joint (for dof and qpos rows too),
// geom, site, actuator or pair its size counts.
struct Owner {
  std::string kind;  ///< "" when the array is not counted per object
  int index = -1;
  std::string name;
};

Owner owner_of_row(const Model& model, Size size, int row) {
  switch (size) {
    case Size::kNbody: return {"body", row, model.body_name[row]};
    case Size::kNjnt: return {"joint", row, model.jnt_name[row]};
    case Size::kNv: {
      const int j = model.dof_jntid[row];
      return {"joint", j, model.jnt_name[j]};
    }
    case Size::kNq:
      for (int j = 0; j < model.njnt; ++j) {
        const int first = model.jnt_qposadr[j];
        if (row >= first && row < first + joint_nq(model.jnt_type[j])) {
          return {"joint", j, model.jnt_name[j]};
        }
      }
      return {};
    case Size::kNu: return {"actuator", row, model.actuator_name[row]};
    case Size::kNgeom: return {"geom", row, model.geom_name[row]};
    case Size::kNsite: return {"site", row, model.site_name[row]};
    case Size::kNpair: return {"pair", row, ""};
    case Size::kNsensor: return {"sensor", row, model.sensor_name[row]};
    case Size::kNeq: return {"equality", row, model.eq_name[row]};
    case Size::kNtendon: return {"tendon", row, model.tendon_name[row]};
    default: return {};
  }
}

// Row `row` of a double array, as "(a, b, c)" or "a".
std::string row_text(const FieldView& field, int row) {
  std::ostringstream s;
  const double* x = field.doubles() + static_cast<long>(row) * field.cols;
  if (field.cols > 1) s << "(";
  for (int k = 0; k < field.cols; ++k) s << (k ? ", " : "") << x[k];
  if (field.cols > 1) s << ")";
  return s.str();
}

[[noreturn]] void reject_row(const Model& model, const FieldView& field, int row,
                             const std::string& why) {
  const Owner owner = owner_of_row(model, field.info->rows, row);
  if (owner.kind.empty()) {
    throw ModelError(std::string("Model::") + field.info->name + " " + why + ".");
  }
  reject(owner.kind, owner.index, owner.name, "has " + why);
}

// ---- driven by the field table -----------------------------------------------------------------

// Every number of every double array the model is given is finite.
void check_finite(const Model& model) {
  for (const FieldView& field : model_fields(model)) {
    if (field.info->scalar != Scalar::kDouble || computed_by_set_const(field.info->name)) continue;
    for (int row = 0; row < field.rows; ++row) {
      const double* x = field.doubles() + static_cast<long>(row) * field.cols;
      for (int k = 0; k < field.cols; ++k) {
        if (!std::isfinite(x[k])) {
          reject_row(model, field, row,
                     std::string("a non-finite ") + field.info->name + " " + row_text(field, row));
        }
      }
    }
  }
}

// Arrays no entry of which may be negative, and why.
struct NonNegative {
  const char* field;
  const char* why;
};
constexpr NonNegative kNonNegative[] = {
    {"sensor_cutoff", "a sensor's cutoff is a bound on its magnitude"},
    {"sensor_noise", "a sensor's noise is a standard deviation"},
    {"body_mass", "no body has a negative mass"},
    {"body_inertia", "no body has a negative principal moment of inertia"},
    // each would make the model gain energy from nothing; MuJoCo 2.2.2 accepts them silently
    {"dof_armature", "a negative armature would make the model gain energy from nothing"},
    {"dof_damping", "a negative damping would make the model gain energy from nothing"},
    {"jnt_stiffness", "a negative stiffness would make the model gain energy from nothing"},
    {"dof_frictionloss", "friction loss is the bound on a force's size"},
};

// A range used when its flag is set must have lo < hi.
struct Ordered {
  const char* range;
  const char* flag;
};
constexpr Ordered kOrdered[] = {{"jnt_range", "jnt_limited"},
                                {"actuator_ctrlrange", "actuator_ctrllimited"},
                                {"actuator_forcerange", "actuator_forcelimited"},
                                {"actuator_actrange", "actuator_actlimited"}};

void check_ranges(const Model& model) {
  for (const NonNegative& rule : kNonNegative) {
    const FieldView field = model_field(model, rule.field);
    for (int row = 0; row < field.rows; ++row) {
      for (int k = 0; k < field.cols; ++k) {
        if (field.doubles()[static_cast<long>(row) * field.cols + k] < 0) {
          reject_row(model, field, row,
                     std::string("a negative ") + rule.field + " " + row_text(field, row) + ": " +
                         rule.why);
        }
      }
    }
  }
  // every quaternion of the table the model is given (its arrays named *quat, four numbers a
  // row) has a direction
  for (const FieldView& field : model_fields(model)) {
    const std::string_view name = field.info->name;
    if (field.cols != 4 || name.size() < 4 || name.substr(name.size() - 4) != "quat") continue;
    if (computed_by_set_const(name)) continue;
    for (int row = 0; row < field.rows; ++row) {
      const Eigen::Map<const Eigen::Vector4d> q(field.doubles() + 4L * row);
      if (q.norm() < 1e-10) {
        reject_row(model, field, row,
                   std::string("a zero quaternion ") + field.info->name + " " +
                       row_text(field, row) + ": it has no direction to normalize");
      }
    }
  }
  for (const Ordered& rule : kOrdered) {
    const FieldView range = model_field(model, rule.range);
    const FieldView flag = model_field(model, rule.flag);
    const auto* flags = static_cast<const std::uint8_t*>(flag.data);
    for (int row = 0; row < range.rows; ++row) {
      const double lo = range.doubles()[2L * row], hi = range.doubles()[2L * row + 1];
      if (flags[row] && !(lo < hi)) {
        reject_row(model, range, row,
                   std::string(rule.flag) + " set but a " + rule.range + " " +
                       row_text(range, row) + " that does not have lo < hi");
      }
    }
  }
}

// ---- what the table cannot say -----------------------------------------------------------------

template <class Array>
void require_size(const Array& v, int n, const char* name) {
  if (static_cast<int>(v.size()) != n) {
    throw ModelError("model array " + std::string(name) + " has " + std::to_string(v.size()) +
                     " entries where " + std::to_string(n) +
                     " are needed: a count changed since the arrays were sized; call "
                     "lever::size_model after setting the counts.");
  }
}

#define LEVER_REQUIRE_SIZE(field, n) require_size(model.field, n, #field)

// The counts agree with each other, and every array has the size they give it (the field table's
// arrays through check_model_sizes; names and keyframes here).
void check_sizes(const Model& model) {
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
#define LEVER_REQUIRE_NAMES(name, count) LEVER_REQUIRE_SIZE(name, model.count);
  LEVER_MODEL_NAMES(LEVER_REQUIRE_NAMES)
#undef LEVER_REQUIRE_NAMES
  LEVER_REQUIRE_SIZE(key_time, model.nkey);
  if (model.nkey < 0 || model.key_qpos.rows() != model.nkey || model.key_qpos.cols() != model.nq ||
      model.key_qvel.rows() != model.nkey || model.key_qvel.cols() != model.nv ||
      model.key_ctrl.rows() != model.nkey || model.key_ctrl.cols() != model.nu ||
      model.key_act.rows() != model.nkey || model.key_act.cols() != model.na) {
    throw ModelError(
        "keyframe arrays key_qpos, key_qvel, key_ctrl, key_act must be nkey x nq, nkey x nv, "
        "nkey x nu and nkey x na (nkey = " +
        std::to_string(model.nkey) + ").");
  }
  if (model.nmocap < 0 || model.key_mpos.rows() != model.nkey ||
      model.key_mpos.cols() != 3 * model.nmocap || model.key_mquat.rows() != model.nkey ||
      model.key_mquat.cols() != 4 * model.nmocap) {
    throw ModelError("nmocap must be non-negative and key_mpos, key_mquat nkey x 3 nmocap and "
                     "nkey x 4 nmocap (nkey = " + std::to_string(model.nkey) +
                     ", nmocap = " + std::to_string(model.nmocap) + ").");
  }
  // contact: the counts the contact arrays of the field table are sized by
  if (model.nmesh < 0 || model.nmeshvert < 0 || model.nmeshgraph < 0 || model.nmeshface < 0) {
    throw ModelError("nmesh, nmeshvert, nmeshgraph and nmeshface must be non-negative.");
  }
  if (model.neq < 0)
    throw ModelError("neq must be non-negative; got " + std::to_string(model.neq) + ".");
  if (model.npair < 0 || model.nexclude < 0 || model.nconmax < 0 || model.njmax < 0) {
    throw ModelError("npair, nexclude, nconmax and njmax must be non-negative; got " +
                     std::to_string(model.npair) + ", " + std::to_string(model.nexclude) + ", " +
                     std::to_string(model.nconmax) + ", " + std::to_string(model.njmax) + ".");
  }
  check_model_sizes(model);
}

#undef LEVER_REQUIRE_SIZE

// Parents precede children, joints and dofs follow the body tree, indices are in range.
void check_tree(const Model& model) {
  // the mocap bodies: numbered 0.. in body order, each a child of the world without joints (as
  // MuJoCo 2.2.2's compiler requires)
  int next_mocap = 0;
  for (int b = 0; b < model.nbody; ++b) {
    const int id = model.body_mocapid[b];
    if (id == -1) continue;
    if (id != next_mocap++) {
      throw ModelError("body " + std::to_string(b) + " ('" + model.body_name[b] +
                       "'): body_mocapid must number the mocap bodies 0, 1, ... in body order "
                       "(or be -1); found " + std::to_string(id) + ".");
    }
    if (b == 0 || model.body_parentid[b] != 0 || model.body_jntnum[b] != 0) {
      throw ModelError("body " + std::to_string(b) + " ('" + model.body_name[b] +
                       "') is a mocap body but not a child of the world without joints.");
    }
  }
  if (next_mocap != model.nmocap) {
    throw ModelError("nmocap is " + std::to_string(model.nmocap) + " but body_mocapid names " +
                     std::to_string(next_mocap) + " mocap bodies.");
  }
  for (int b = 1; b < model.nbody; ++b) {
    const int p = model.body_parentid[b];
    if (p < 0 || p >= b) {
      throw ModelError("body " + std::to_string(b) + " ('" + model.body_name[b] +
                       "') must come after its parent (parent id " + std::to_string(p) + ").");
    }
  }
  // each body's world child, which the compiler records (kinematics reads subtree_com there)
  if (model.body_rootid[0] != 0) throw ModelError("the world's body_rootid must be 0.");
  for (int b = 1; b < model.nbody; ++b) {
    const int p = model.body_parentid[b];
    const int root = p == 0 ? b : model.body_rootid[p];
    if (model.body_rootid[b] != root) {
      reject("body", b, model.body_name[b],
             "has body_rootid " + std::to_string(model.body_rootid[b]) +
                 ", but the child of the world it hangs from is body " + std::to_string(root));
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
    const int id = model.actuator_trnid[a][0], second = model.actuator_trnid[a][1];
    const auto names_no = [&](const char* kind) {
      throw ModelError("actuator " + std::to_string(a) + " names no " + kind + ".", "actuator", a);
    };
    const auto site = [&](int s) { return s >= 0 && s < model.nsite; };
    switch (model.actuator_trntype[a]) {
      case TransmissionType::kJoint:
      case TransmissionType::kJointInParent:
        if (id < 0 || id >= model.njnt) names_no("joint");
        if (second != -1) names_no("second object (a joint transmission has none: -1)");
        break;
      case TransmissionType::kTendon:
        if (id < 0 || id >= model.ntendon) names_no("tendon");
        if (second != -1) names_no("second object (a tendon transmission has none: -1)");
        break;
      case TransmissionType::kSliderCrank:
        if (!site(id)) names_no("crank site");
        if (!site(second)) names_no("slider site");
        if (!(model.actuator_cranklength[a] > 0)) {
          reject("actuator", a, model.actuator_name[a],
                 "is a slider-crank whose cranklength is not positive");
        }
        break;
      case TransmissionType::kSite:
        if (!site(id)) names_no("site");
        if (second != -1 && !site(second)) names_no("reference site");
        break;
      case TransmissionType::kBody:
        if (id < 0 || id >= model.nbody) names_no("body");
        if (second != -1) names_no("second object (a body transmission has none: -1)");
        break;
      default:
        reject("actuator", a, model.actuator_name[a],
               "has a transmission type that is not MuJoCo 2.2.2's (joint 0, jointinparent 1, "
               "slider-crank 2, tendon 3, site 4, body 5)");
    }
  }
}

// Each equality constraint names objects of its kind: two different bodies (connect, weld; body
// 2 may be the world), or a hinge or slide and, optionally (-1: none), a second one (joint).
void check_equalities(const Model& model) {
  for (int e = 0; e < model.neq; ++e) {
    const int type = static_cast<int>(model.eq_type[e]);
    const int id1 = model.eq_obj1id[e], id2 = model.eq_obj2id[e];
    if (type < 0 || type > static_cast<int>(EqualityType::kTendon)) {
      reject("equality", e, model.eq_name[e],
             "has a type lever does not have (connect 0, weld 1, joint 2, tendon 3)");
    }
    if (id1 == id2) reject("equality", e, model.eq_name[e], "names the same object twice");
    if (model.eq_type[e] == EqualityType::kTendon) {
      if (id1 < 0 || id1 >= model.ntendon || id2 < -1 || id2 >= model.ntendon) {
        reject("equality", e, model.eq_name[e], "names a tendon that does not exist");
      }
      continue;
    }
    if (model.eq_type[e] != EqualityType::kJoint) {
      if (id1 < 0 || id1 >= model.nbody || id2 < 0 || id2 >= model.nbody) {
        reject("equality", e, model.eq_name[e], "names a body that does not exist");
      }
      continue;
    }
    for (const int j : {id1, id2}) {
      if (j == id2 && j == -1) continue;  // one joint: held at its qpos0 plus polycoef[0]
      if (j < 0 || j >= model.njnt) {
        reject("equality", e, model.eq_name[e], "names a joint that does not exist");
      }
      if (model.jnt_type[j] != JointType::kHinge && model.jnt_type[j] != JointType::kSlide) {
        reject("equality", e, model.eq_name[e],
               "couples joint '" + model.jnt_name[j] + "', which is not a hinge or a slide");
      }
    }
  }
}

// A fixed tendon's path: joints only, each a hinge or a slide.
void check_fixed_path(const Model& model, int t) {
  const std::string& name = model.tendon_name[t];
  for (int w = model.tendon_adr[t]; w < model.tendon_adr[t] + model.tendon_num[t]; ++w) {
    if (model.wrap_type[w] != WrapType::kJoint) {
      reject("tendon", t, name, "mixes joints with sites, geoms or pulleys in its path");
    }
    const int j = model.wrap_objid[w];
    if (j < 0 || j >= model.njnt) reject("tendon", t, name, "names a joint that does not exist");
    if (model.jnt_type[j] != JointType::kHinge && model.jnt_type[j] != JointType::kSlide) {
      reject("tendon", t, name,
             "runs along joint '" + model.jnt_name[j] + "', which is not a hinge or a slide");
    }
  }
}

// A spatial tendon's path, by MuJoCo 2.2.2's compiler rules: at least two objects; sites, each
// with a neighbour that is not a pulley and never the same site twice in a row; a sphere or
// cylinder geom (wrap_type saying which) between two sites, its wrap_prm a side site or -1; a
// pulley neither last nor after another, its divisor positive (MuJoCo takes 0 and divides by it).
void check_spatial_path(const Model& model, int t) {
  const std::string& name = model.tendon_name[t];
  const int adr = model.tendon_adr[t], num = model.tendon_num[t];
  if (num < 2) reject("tendon", t, name, "is spatial with fewer than two objects in its path");
  auto type_at = [&](int i) { return model.wrap_type[adr + i]; };
  for (int i = 0; i < num; ++i) {
    const int w = adr + i;
    const int id = model.wrap_objid[w];
    const std::string at = " (path object " + std::to_string(i) + ")";
    switch (type_at(i)) {
      case WrapType::kSite: {
        if (id < 0 || id >= model.nsite) reject("tendon", t, name, "names a site that does not exist" + at);
        const bool alone_before = i == 0 || type_at(i - 1) == WrapType::kPulley;
        const bool alone_after = i == num - 1 || type_at(i + 1) == WrapType::kPulley;
        if (alone_before && alone_after) {
          reject("tendon", t, name, "has a site with no neighbour that is not a pulley" + at);
        }
        if (i + 1 < num && type_at(i + 1) == WrapType::kSite && model.wrap_objid[w + 1] == id) {
          reject("tendon", t, name, "names the same site twice in a row" + at);
        }
        break;
      }
      case WrapType::kSphere:
      case WrapType::kCylinder: {
        if (id < 0 || id >= model.ngeom) reject("tendon", t, name, "names a geom that does not exist" + at);
        const GeomType want = type_at(i) == WrapType::kSphere ? GeomType::kSphere : GeomType::kCylinder;
        if (model.geom_type[id] != want) {
          reject("tendon", t, name,
                 "wraps around geom " + std::to_string(id) + " as a " +
                     (want == GeomType::kSphere ? "sphere" : "cylinder") + ", which it is not" + at);
        }
        if (i == 0 || i == num - 1 || type_at(i - 1) != WrapType::kSite ||
            type_at(i + 1) != WrapType::kSite) {
          reject("tendon", t, name, "has a wrapping geom that is not between two sites" + at);
        }
        const double side = model.wrap_prm[w];
        if (!(side == std::round(side)) || side < -1 || side >= model.nsite) {
          reject("tendon", t, name, "has a side site that does not exist (wrap_prm)" + at);
        }
        break;
      }
      case WrapType::kPulley:
        if (i == num - 1) reject("tendon", t, name, "ends with a pulley");
        if (i > 0 && type_at(i - 1) == WrapType::kPulley) {
          reject("tendon", t, name, "has two pulleys in a row" + at);
        }
        if (!(model.wrap_prm[w] > 0) || !std::isfinite(model.wrap_prm[w])) {
          reject("tendon", t, name, "has a pulley whose divisor is not positive" + at);
        }
        break;
      case WrapType::kJoint:
        reject("tendon", t, name, "is spatial but has a joint in its path" + at);
      default:
        reject("tendon", t, name, "has an object of unknown type in its path" + at);
    }
  }
}

// Each tendon's path: consecutive objects of wrap_*, fixed (joints) or spatial (sites, wrapping
// geoms, pulleys) by its first object, as MuJoCo decides.
void check_tendons(const Model& model) {
  int next = 0;
  for (int t = 0; t < model.ntendon; ++t) {
    const std::string& name = model.tendon_name[t];
    const int adr = model.tendon_adr[t], num = model.tendon_num[t];
    if (adr != next || num < 1 || adr + num > model.nwrap) {
      reject("tendon", t, name,
             "has a path that is not the next tendon_num[t] >= 1 objects of wrap_* (tendon_adr "
             "must follow the previous tendon's path)");
    }
    next = adr + num;
    if (model.wrap_type[adr] == WrapType::kJoint) {
      check_fixed_path(model, t);
    } else {
      check_spatial_path(model, t);
    }
    if (model.tendon_limited[t] && !(model.tendon_range[t][0] < model.tendon_range[t][1])) {
      reject("tendon", t, name, "is limited but its range does not have lower < upper");
    }
  }
  if (next != model.nwrap) {
    throw ModelError("nwrap is " + std::to_string(model.nwrap) + " but the tendons' paths hold " +
                     std::to_string(next) + " objects.");
  }
}

// The option block, the actuators' kinds and the keyframes (none of them in the field table).
void check_options_actuators_keys(const Model& model) {
  if (!(model.opt.timestep > 0) || !std::isfinite(model.opt.timestep)) {
    throw ModelError("the timestep must be a positive number of seconds; it is " +
                     std::to_string(model.opt.timestep) + ".");
  }
  if (!model.opt.gravity.allFinite()) throw ModelError("gravity must be finite.");
  // MuJoCo 2.2.2 takes a negative viscosity or density as written: a medium that pushes
  if (!(model.opt.viscosity >= 0) || !std::isfinite(model.opt.viscosity) ||
      !(model.opt.density >= 0) || !std::isfinite(model.opt.density) ||
      !model.opt.wind.allFinite()) {
    throw ModelError("the medium's viscosity and density must be finite and not negative, and "
                     "the wind finite.");
  }
  // the flags: MuJoCo 2.2.2's bits only; the override's parameters finite
  if ((model.opt.disableflags & ~((1 << kDisableBits) - 1)) != 0 ||
      (model.opt.enableflags & ~((1 << kEnableBits) - 1)) != 0) {
    throw ModelError("opt.disableflags and opt.enableflags hold MuJoCo 2.2.2's bits only (" +
                     std::to_string(kDisableBits) + " and " + std::to_string(kEnableBits) +
                     "); they are " + std::to_string(model.opt.disableflags) + " and " +
                     std::to_string(model.opt.enableflags) + ".");
  }
  const auto finite_all = [](const auto& values) {
    for (const double x : values) {
      if (!std::isfinite(x)) return false;
    }
    return true;
  };
  if (!std::isfinite(model.opt.o_margin) || !finite_all(model.opt.o_solref) ||
      !finite_all(model.opt.o_solimp)) {
    throw ModelError("the contact override's o_margin, o_solref and o_solimp must be finite.");
  }
  if (model.opt.solver != Solver::kPGS && model.opt.solver != Solver::kCG &&
      model.opt.solver != Solver::kNewton) {
    throw ModelError("opt.solver " + std::to_string(static_cast<int>(model.opt.solver)) +
                     " is not one lever has (0 PGS, 1 CG, 2 Newton).");
  }
  if (model.opt.jacobian != JacobianLayout::kDense &&
      model.opt.jacobian != JacobianLayout::kSparse && model.opt.jacobian != JacobianLayout::kAuto) {
    throw ModelError("opt.jacobian " + std::to_string(static_cast<int>(model.opt.jacobian)) +
                     " is not one of MuJoCo's layouts (0 dense, 1 sparse, 2 auto).");
  }
  if (model.opt.iterations < 0 || !(model.opt.tolerance >= 0)) {
    throw ModelError("the solver's iterations and tolerance must not be negative.");
  }
  if (has_fluid(model.opt) && model.opt.integrator == Integrator::kImplicitFast) {
    throw ModelError("fluid forces (viscosity, density) with MuJoCo 3's implicitfast integrator: "
                     "lever has them with Euler, RK4 and MuJoCo 2.2.2's implicit only.");
  }
  int stateful = 0;
  for (int a = 0; a < model.nu; ++a) {
    const int dyntype = static_cast<int>(model.actuator_dyntype[a]);
    const int gaintype = static_cast<int>(model.actuator_gaintype[a]);
    const int biastype = static_cast<int>(model.actuator_biastype[a]);
    if (dyntype < 0 || dyntype > 4 || gaintype < 0 || gaintype > 3 || biastype < 0 ||
        biastype > 3) {
      reject("actuator", a, model.actuator_name[a],
             "needs dyntype none, integrator, filter, muscle or user, gaintype fixed, affine, "
             "muscle or user and biastype none, affine, muscle or user");
    }
    if (dyntype != 0) {
      ++stateful;
    } else if (stateful > 0) {
      reject("actuator", a, model.actuator_name[a],
             "has no dynamics but comes after one that has: stateless actuators come first");
    }
    if (model.actuator_actlimited[a] && dyntype == 0) {
      reject("actuator", a, model.actuator_name[a], "has an actrange but no dynamics");
    }
  }
  if (stateful != model.na) {
    throw ModelError("na = " + std::to_string(model.na) + " but " + std::to_string(stateful) +
                     " actuators have dynamics (one activation each).");
  }
  for (int k = 0; k < model.nkey; ++k) {
    if (!std::isfinite(model.key_time[k]) || !model.key_qpos.row(k).allFinite() ||
        !model.key_qvel.row(k).allFinite() || !model.key_ctrl.row(k).allFinite() ||
        !model.key_act.row(k).allFinite()) {
      reject("keyframe", k, model.key_name[k], "has a non-finite time, qpos, qvel, ctrl or act");
    }
  }
}

// The meshes the collision stage reads: each mesh geom's mesh exists, each mesh's vertices lie
// within mesh_vert (none for a mesh lever did not read), and its hull graph (if any) within mesh_graph, well formed: its vertices are
// the mesh's, each neighbour list ends with -1 before the lists end, and names hull vertices.
void check_meshes(const Model& model) {
  if (model.opt.mpr_iterations < 0 || !(model.opt.mpr_tolerance >= 0)) {
    throw ModelError("mpr_iterations and mpr_tolerance must not be negative.");
  }
  for (int g = 0; g < model.ngeom; ++g) {
    const int id = model.geom_dataid[g];
    if (id < -1 || id >= model.nmesh || (id >= 0 && model.geom_type[g] != GeomType::kMesh)) {
      reject("geom", g, model.geom_name[g], "has a geom_dataid that names no mesh of it");
    }
  }
  const auto fail = [](int m, const std::string& why) {
    throw ModelError("mesh " + std::to_string(m) + " " + why + ".", "mesh", m);
  };
  for (int m = 0; m < model.nmesh; ++m) {
    const int adr = model.mesh_vertadr[m], num = model.mesh_vertnum[m];
    if (adr < 0 || num < 0 || adr > model.nmeshvert - num) {
      fail(m, "has vertices outside mesh_vert");
    }
    const int face = model.mesh_faceadr[m], faces = model.mesh_facenum[m];
    if (face < 0 || faces < 0 || face > model.nmeshface - faces) {
      fail(m, "has triangles outside mesh_face");
    }
    for (int f = face; f < face + faces; ++f) {
      for (const int v : model.mesh_face[f]) {
        if (v < 0 || v >= num) fail(m, "has a triangle whose vertex is not one of its own");
      }
    }
    const int graph = model.mesh_graphadr[m];
    if (graph == -1) continue;
    const int size = model.nmeshgraph;
    if (graph < 0 || graph > size - 2) fail(m, "has a hull graph outside mesh_graph");
    const int* g = model.mesh_graph.data() + graph;
    const long numvert = g[0], numface = g[1];
    if (numvert < 1 || numface < 0 || 2 + 3 * numvert + 6 * numface > size - graph) {
      fail(m, "has a hull graph whose counts run past mesh_graph");
    }
    const long lists = numvert + 3 * numface;
    for (long v = 0; v < numvert; ++v) {
      const int vertex = g[2 + numvert + v], first = g[2 + v];
      if (vertex < 0 || vertex >= num || first < 0 || first >= lists) {
        fail(m, "has a hull vertex outside the mesh or its neighbour list");
      }
      long e = first;
      while (e < lists && g[2 + 2 * numvert + e] >= 0) {
        if (g[2 + 2 * numvert + e] >= numvert) fail(m, "has a hull neighbour that is no vertex");
        ++e;
      }
      if (e >= lists) fail(m, "has a hull neighbour list without its end (-1)");
    }
  }
}

// A sensor attached to an object of this type and id: one lever has and the sensor can read.
bool sensor_object_exists(const Model& model, ObjectType type, int id) {
  switch (type) {
    case ObjectType::kBody:
    case ObjectType::kXBody: return id >= 0 && id < model.nbody;
    case ObjectType::kGeom: return id >= 0 && id < model.ngeom;
    case ObjectType::kSite: return id >= 0 && id < model.nsite;
    case ObjectType::kJoint: return id >= 0 && id < model.njnt;
    case ObjectType::kActuator: return id >= 0 && id < model.nu;
    case ObjectType::kTendon: return id >= 0 && id < model.ntendon;
    default: return false;
  }
}

bool is_frame(ObjectType type) {
  return type == ObjectType::kBody || type == ObjectType::kXBody || type == ObjectType::kGeom ||
         type == ObjectType::kSite;
}

// Every sensor: a type lever evaluates, on an object of the kind it reads, with MuJoCo's layout
// (dim, datatype, stage) and its numbers one after another in sensordata.
void check_sensors(const Model& model) {
  int adr = 0;
  for (int s = 0; s < model.nsensor; ++s) {
    const std::string& name = model.sensor_name[s];
    const SensorType type = model.sensor_type[s];
    const int t = static_cast<int>(type);
    if (t < 0 || t > static_cast<int>(SensorType::kUser)) {
      reject("sensor", s, name, "has an unknown type " + std::to_string(t));
    }
    if (!sensor_type_supported(type)) {
      reject("sensor", s, name,
             std::string("is a ") + sensor_type_name(type) + " sensor, which lever does not have");
    }
    SensorLayout layout = sensor_layout(type);
    if (type == SensorType::kUser) {
      // its own dim, datatype and stage (MuJoCo's compiler: an axis has 3 numbers, a
      // quaternion 4), on an object of any kind lever has
      const int dim = model.sensor_dim[s];
      const SensorDataType datatype = model.sensor_datatype[s];
      const int stage = static_cast<int>(model.sensor_needstage[s]);
      const int kind = static_cast<int>(datatype);
      if (dim < 0 || kind < 0 || kind > static_cast<int>(SensorDataType::kQuaternion) ||
          (datatype == SensorDataType::kAxis && dim != 3) ||
          (datatype == SensorDataType::kQuaternion && dim != 4) || stage < 0 ||
          stage > static_cast<int>(SensorStage::kAcceleration)) {
        reject("sensor", s, name,
               "is a user sensor whose dim, datatype and needstage do not fit together");
      }
      layout = {dim, datatype, model.sensor_needstage[s], model.sensor_objtype[s]};
    }
    if (model.sensor_dim[s] != layout.dim || model.sensor_datatype[s] != layout.datatype ||
        model.sensor_needstage[s] != layout.stage) {
      reject("sensor", s, name,
             std::string("does not have a ") + sensor_type_name(type) +
                 " sensor's dim, datatype and needstage (" + std::to_string(layout.dim) + ", " +
                 std::to_string(static_cast<int>(layout.datatype)) + ", " +
                 std::to_string(static_cast<int>(layout.stage)) + ")");
    }
    if (model.sensor_adr[s] != adr) {
      reject("sensor", s, name,
             "starts at sensordata " + std::to_string(model.sensor_adr[s]) +
                 "; the sensors before it end at " + std::to_string(adr));
    }
    adr += layout.dim;
    const ObjectType objtype = model.sensor_objtype[s];
    const int id = model.sensor_objid[s];
    const bool right_kind = layout.object == ObjectType::kXBody ? is_frame(objtype)
                                                                : objtype == layout.object;
    if (layout.object != ObjectType::kUnknown &&
        (!right_kind || !sensor_object_exists(model, objtype, id))) {
      reject("sensor", s, name, "is not attached to an object of the kind it reads");
    }
    if (model.sensor_refid[s] >= 0 &&
        (!is_frame(model.sensor_reftype[s]) ||
         !sensor_object_exists(model, model.sensor_reftype[s], model.sensor_refid[s]))) {
      reject("sensor", s, name, "has a reference frame that is no body, geom or site");
    }
    if (objtype == ObjectType::kJoint && type != SensorType::kUser) {
      const JointType jt = model.jnt_type[id];
      const bool ball = type == SensorType::kBallQuat || type == SensorType::kBallAngVel;
      if (ball != (jt == JointType::kBall) ||
          (!ball && jt != JointType::kHinge && jt != JointType::kSlide)) {
        reject("sensor", s, name,
               ball ? "reads a ball joint, and its joint is not one"
                    : "reads a hinge or slide joint, and its joint is neither");
      }
      // a limit sensor of a joint whose limit was switched off reads 0, as in MuJoCo (its
      // compiler refuses one on a joint that never had a limit; so does lever's)
    }
    if (type == SensorType::kRangefinder) {
      for (int g = 0; g < model.ngeom; ++g) {
        const bool hfield = model.geom_type[g] == GeomType::kHfield;
        const bool unread_mesh = model.geom_type[g] == GeomType::kMesh &&
                                 (model.geom_dataid[g] < 0 || model.geom_dataid[g] >= model.nmesh ||
                                  model.mesh_facenum[model.geom_dataid[g]] == 0);
        if (hfield || unread_mesh) {
          reject("sensor", s, name,
                 std::string("is a rangefinder, and lever casts no rays at ") +
                     (hfield ? "height fields" : "a mesh geom without triangles") + " (geom " +
                     std::to_string(g) + ")");
        }
      }
    }
    if (model.sensor_cutoff[s] > 0 && (layout.datatype == SensorDataType::kAxis ||
                                       layout.datatype == SensorDataType::kQuaternion)) {
      reject("sensor", s, name, "has a cutoff, and its numbers are an axis or a quaternion");
    }
  }
  if (model.nsensordata != adr) {
    throw ModelError("nsensordata is " + std::to_string(model.nsensordata) +
                     "; the sensors' dims add up to " + std::to_string(adr) + ".");
  }
  if (!model.opt.magnetic.allFinite()) throw ModelError("the magnetic field must be finite.");
}

template <typename Vector>
bool finite(const Vector& v) {
  for (const double x : v) {
    if (!std::isfinite(x)) return false;
  }
  return true;
}

}  // namespace

void validate(const Model& model) {
  check_sizes(model);
  check_tree(model);
  check_options_actuators_keys(model);
  check_meshes(model);
  check_sensors(model);
  check_tendons(model);
  check_equalities(model);
  check_finite(model);
  check_ranges(model);
}

namespace detail {

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

}  // namespace detail

}  // namespace lever
