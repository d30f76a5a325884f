// The text of `lever check`: lesson 5.1's Output block, section by section, with the same
// wording and digits where the lesson has a line for it, and a line per joint, site and stop.
#include <algorithm>
#include <cmath>
#include <sstream>

#include <lever/check.hpp>
#include "format.hpp"

namespace lever::check {

namespace {

using fmt::fixed;
using fmt::general;
using fmt::sci;
using fmt::sig4;
using fmt::torque_unit;

const char* position_unit(bool hinge) { return hinge ? "rad" : "m"; }

std::string bool_text(bool b) { return b ? "true" : "false"; }

std::string range_text(const std::array<double, 2>& r) {
  return std::string("[") + general(r[0]) + " " + general(r[1]) + "]";
}

std::string pose_text(const Eigen::VectorXd& q) { return "q = " + fmt::list(q, 4); }

std::string names(const std::vector<std::string>& list) {
  std::string out;
  for (size_t i = 0; i < list.size(); ++i) {
    if (i) out += ", ";
    out += list[i];
  }
  return out;
}

// ---- (1) ---------------------------------------------------------------------------------------

// A servo's line: its law, what ctrl means, and the torque it can give (forcerange).
void print_servo(std::ostream& out, const MotorInfo& m) {
  out << "  servo " << m.name;
  if (m.name != m.joint) out << " (joint " << m.joint << ")";
  const bool position =
      m.gainprm[1] == 0 && m.gainprm[2] == 0 && m.gainprm[0] == m.kp && m.biasprm[0] == 0;
  if (position) {
    out << ": force = kp (ctrl - length) - kv velocity, kp " << general(m.kp) << " kv "
        << general(m.kv);
  } else {
    out << ": force = gain ctrl + bias, gainprm [" << general(m.gainprm[0]) << " "
        << general(m.gainprm[1]) << " " << general(m.gainprm[2]) << "] biasprm ["
        << general(m.biasprm[0]) << " " << general(m.biasprm[1]) << " " << general(m.biasprm[2])
        << "]";
  }
  if (m.gear != 1.0) out << ", gear " << general(m.gear);
  out << "; ctrl is a target";
  if (m.ctrllimited) out << " in ctrlrange " << range_text(m.ctrlrange);
  if (m.forcelimited) out << ", forcerange " << range_text(m.forcerange);
  out << ": joint torque " << range_text(m.joint_torque)
      << (m.forcelimited ? "" : " (at qpos0, from the ctrlrange: no forcerange)") << "\n";
}

void print_structure(std::ostream& out, const Structure& s) {
  out << "(1) what the compiled model contains:\n";
  for (const JointInfo& j : s.joints) {
    out << "  joint " << j.name << (j.hinge ? "" : " (" + j.type + ")") << " axis "
        << fmt::list(j.axis) << " range "
        << (j.limited ? range_text(j.range) + " " + position_unit(j.hinge) : "-") << " limited "
        << bool_text(j.limited) << " damping " << general(j.damping)
        << (j.hinge ? " N m s/rad" : " N s/m");
    if (j.armature != 0) out << " armature " << general(j.armature);
    if (j.stiffness != 0) out << " stiffness " << general(j.stiffness);
    if (j.qpos0 != 0) out << " qpos0 " << general(j.qpos0);
    out << "\n";
  }
  for (const MotorInfo& m : s.motors) {
    if (m.servo) {
      print_servo(out, m);
      continue;
    }
    out << "  motor " << m.name;
    if (m.name != m.joint) out << " (joint " << m.joint << ")";
    out << " gear " << general(m.gear) << " ctrlrange " << range_text(m.ctrlrange);
    const bool plain = m.gear == 1.0 && !m.forcelimited;
    if (plain) out << " N m";
    out << " ctrllimited " << bool_text(m.ctrllimited);
    if (m.forcelimited) out << " forcerange " << range_text(m.forcerange) << " forcelimited true";
    if (!plain) out << ": joint torque " << range_text(m.joint_torque);
    out << "\n";
  }
  std::vector<std::string> sites;
  for (size_t i = 0; i < s.sites.size(); ++i)
    sites.push_back(s.sites[i] + " (on " + s.site_bodies[i] + ")");
  out << "  sites: " << (sites.empty() ? "none" : names(sites)) << "\n";
  for (const BodyInfo& b : s.bodies) {
    out << "  body " << b.name << " mass " << fixed(b.mass, 3) << " kg, principal moments "
        << fmt::list(b.principal, 5) << " kg m^2"
        << (b.explicit_inertial ? " (<inertial>)"
            : b.mass > 0        ? " (from its geoms)"
                                : "")
        << "\n";
  }
}

// ---- (2) ---------------------------------------------------------------------------------------

std::string planar_description(const PlanarChain& c) {
  std::vector<std::string> links;
  for (size_t k = 0; k < c.lengths.size(); ++k) {
    std::string link = general(c.lengths[k]) + " m";
    if (std::abs(c.angles0[k]) > 1e-12) link += " at " + general(c.angles0[k]) + " rad";
    links.push_back(link);
  }
  return "a planar chain (" + names(c.joints) + " about " + fmt::list(c.normal, 6) + "; links " +
         names(links) + " from " + fmt::list(c.origin, 6) + ")";
}

void print_kinematics(std::ostream& out, const Kinematics& k) {
  out << "(2) forward kinematics of every site:\n";
  if (k.sites.empty()) out << "  the model has no sites\n";
  const std::string poses = std::to_string(k.poses) + " random poses within the joint ranges";
  for (const SiteKinematics& s : k.sites) {
    if (s.planar) {
      out << "  site " << s.site << ", " << planar_description(*s.planar) << ":\n"
          << "    " << poses << ": max |site_xpos - formula| = " << fmt::sci(s.planar->max_error)
          << " m\n"
          << "    the same poses, against a chain of transforms from the model's numbers: "
          << fmt::sci(s.max_error_transforms) << " m\n";
    } else {
      out << "  site " << s.site << ": " << poses
          << ": max |site_xpos - chain of transforms| = " << fmt::sci(s.max_error_transforms)
          << " m\n";
    }
  }
  if (!k.sites.empty()) {
    out << "  (figures near 1e-16 are rounding error; they are lever's own, so their digits differ "
           "from the lesson's MuJoCo run)\n";
  }
}

// ---- (3) ---------------------------------------------------------------------------------------

std::string ratio_text(const JointBudget& j) {
  if (!j.actuated()) return j.joint + " unactuated";
  if (std::isinf(j.limit)) return j.joint + " unbounded";
  if (!j.loaded) return j.joint + " - (gravity does not load it)";
  return j.joint + " " + fixed(j.ratio, 2) + " (" + general(j.limit) + " " + torque_unit(j.hinge) +
         ")";
}

// Servos: the limit above is their forcerange (ctrl is a target position, not a torque); holding
// the worst pose, a servo sits |tau| / kp off its target, and the target must lie in ctrlrange.
void print_servo_sag(std::ostream& out, const TorqueBudget& b) {
  std::vector<std::string> sags;
  for (const JointBudget& j : b.joints) {
    if (!j.servo || !j.loaded) continue;
    std::string text = j.joint + " " + fixed(j.sag * 1000.0, 2) + " mrad";
    if (j.target_outside)
      text += " (needs target " + fixed(j.hold_target, 4) + ", outside ctrlrange)";
    sags.push_back(text);
  }
  if (sags.empty()) return;
  out << "  servos: the limit is the forcerange (ctrl is a target position, not a torque)\n";
  out << fmt::wrap("  servo offset holding the worst pose, |gravity torque| / kp:", sags, "    ")
      << "\n";
  for (const JointBudget& j : b.joints) {
    if (!j.servo || !j.loaded || !j.target_outside) continue;
    out << "  " << j.joint << ": holding its worst pose needs a target beyond the ctrlrange: there "
        << "the servo sags off the pose (the clamp, section 6)\n";
  }
}

void print_worst_torques(std::ostream& out, const TorqueBudget& b) {
  out << "  worst-case gravity torque over the joint ranges:\n";
  for (const JointBudget& j : b.joints) {
    out << "    " << j.joint << " " << fixed(j.worst_torque, 3) << " " << torque_unit(j.hinge);
    out << (j.loaded ? " at " + pose_text(j.worst_pose) : " (gravity does not load it)") << "\n";
  }
  out << "    (searched: " << b.search << "; " << b.evaluations << " evaluations of qfrc_bias)\n";
  std::vector<std::string> ratios;
  for (const JointBudget& j : b.joints) ratios.push_back(ratio_text(j));
  out << fmt::wrap("  motor limit / gravity torque:", ratios, "    ") << "\n";
  print_servo_sag(out, b);
}

std::string payload_text(const JointBudget& j, double kg) {
  if (std::isnan(kg)) return j.joint + " unactuated";
  if (std::isinf(kg)) return j.joint + (std::isinf(j.limit) ? " unbounded" : " does not carry it");
  return j.joint + " allows " + fixed(kg, 2) + " kg";
}

void print_payloads(std::ostream& out, const TorqueBudget& b) {
  for (const SitePayload& p : b.payload) {
    std::vector<std::string> items;
    for (size_t j = 0; j < b.joints.size(); ++j)
      items.push_back(payload_text(b.joints[j], p.per_joint[j]));
    const std::string tail =
        p.binding_joint >= 0 ? " -> " + fixed(p.min, 2) + " kg" : " -> no motor limits it";
    out << fmt::wrap("  largest point payload at " + p.site + ", at the worst pose:", items, "    ",
                     tail)
        << "\n";
  }
}

void print_mass_matrices(std::ostream& out, const TorqueBudget& b) {
  for (const PoseInertia& p : b.poses) {
    std::vector<std::string> joints;
    for (const int j : p.joints) joints.push_back(b.joints[j].joint);
    const std::string where =
        b.poses.size() == 1 ? "this pose" : pose_text(p.q) + " (worst for " + names(joints) + ")";
    if (p.M.rows() <= 4) {
      out << "  M(q) at " << where << ": " << fmt::matrix(p.M, 4) << " kg m^2\n";
    } else {
      out << "  M(q) at " << where
          << ", diagonal (the whole matrix is in --json): " << fmt::list(p.M.diagonal(), 4) << "\n";
    }
  }
}

void print_spare(std::ostream& out, const TorqueBudget& b) {
  for (size_t i = 0; i < b.joints.size(); ++i) {
    const JointBudget& j = b.joints[i];
    if (!j.actuated() || std::isinf(j.limit)) continue;
    if (j.spare < 0) {
      out << "  spare " << j.joint << " torque " << fixed(j.spare, 2) << " " << torque_unit(j.hinge)
          << ": the motor cannot hold the arm up at its worst pose, let alone accelerate it\n";
      continue;
    }
    const std::string acc_unit = j.hinge ? " rad/s^2" : " m/s^2";
    std::string head = "  spare " + j.joint + " torque " + fixed(j.spare, 2) + " " +
                       torque_unit(j.hinge) + " gives " + fixed(std::abs(j.acceleration), 1) +
                       acc_unit;
    if (b.joints.size() == 1) {
      out << head << "\n";
      continue;
    }
    std::vector<std::string> needs;
    for (size_t k = 0; k < b.joints.size(); ++k) {
      if (k == i) continue;
      const JointBudget& o = b.joints[k];
      const double need = std::abs(j.rigid_torques[k]);
      std::string text = fixed(need, 2) + " " + torque_unit(o.hinge);
      text = b.joints.size() == 2 ? text + " at the " + o.joint : o.joint + " " + text;
      if (o.actuated() && need > std::max(o.torque_range[1], -o.torque_range[0])) {
        text += " (beyond its motor)";
      }
      needs.push_back(text);
    }
    const std::string rigid =
        b.joints.size() == 2 ? "the " + b.joints[1 - i].joint : "the other joints";
    out << fmt::wrap(head + " with " + rigid + " rigid, which needs", needs, "    ") << "\n";
  }
}

void print_budget(std::ostream& out, const TorqueBudget& b) {
  out << "(3) gravity torque and motor sizing:\n";
  out << "  " << b.formula_poses
      << " random poses at rest: max |qfrc_bias - formula| = " << fmt::sci(b.formula_max_error)
      << " N m (formula: dV/dq)\n";
  if (b.joints.empty()) return;
  print_worst_torques(out, b);
  print_payloads(out, b);
  print_mass_matrices(out, b);
  print_spare(out, b);
}

// ---- (4) ---------------------------------------------------------------------------------------

void print_body_inertia(std::ostream& out, const BodyInertia& b, bool inferred) {
  out << "  " << b.name << ": ";
  if (b.mass == 0 && !b.explicit_inertial) {
    out << "no mass (no <inertial>, no geom counted)\n";
    return;
  }
  if (!b.explicit_inertial) {
    out << "no <inertial>: " << fixed(b.mass, 3) << " kg, " << fmt::list(b.principal, 5)
        << " kg m^2, all from its geoms\n";
    return;
  }
  out << "explicit " << fixed(b.mass, 3) << " kg, principal moments " << fmt::list(b.principal, 5);
  if (inferred) {
    out << " | from geoms " << fixed(b.inferred_mass, 3) << " kg, "
        << fmt::list(b.inferred_principal, 5);
  }
  out << " kg m^2\n";
}

void print_inertia(std::ostream& out, const Inertia& in, const TorqueBudget& b) {
  out << "(4) explicit inertias versus inertias inferred from the geoms:\n";
  if (!in.inferred_available) {
    out << "  the model cannot be inferred from its geoms: " << in.inferred_error << "\n";
  }
  for (const BodyInertia& body : in.bodies) print_body_inertia(out, body, in.inferred_available);
  for (size_t j = 0; j < in.torques.size(); ++j) {
    const char* unit = torque_unit(b.joints[j].hinge);
    out << "  gravity torque at the worst pose: explicit "
        << fixed(in.torques[j].explicit_torque, 3) << " " << unit << ", from geoms "
        << fixed(in.torques[j].inferred_torque, 3) << " " << unit << " (" << in.torques[j].joint
        << ")\n";
  }
  const auto range = [](const std::array<int, 2>& r) {
    return std::to_string(r[0]) + " " + std::to_string(r[1]);
  };
  out << "  1 kg collision geom + 2 kg non-colliding geom in group 3, default inertiagrouprange ("
      << range(in.demo_default_range) << "): body mass " << fixed(in.demo_default_mass, 3)
      << " kg\n";
  out << "  1 kg collision geom + 2 kg non-colliding geom in group 3, inertiagrouprange=\""
      << range(in.demo_narrow_range) << "\": body mass " << fixed(in.demo_narrow_mass, 3)
      << " kg\n";
  if (in.bodies_without_inertial.empty()) {
    out << "  every body with mass has an explicit <inertial>, so no geom adds mass unseen\n";
  }
}

// ---- (5) ---------------------------------------------------------------------------------------

std::string milli(const StopRest& s, double x) {
  return fixed(1000 * x, 2) + (s.hinge ? " mrad" : " mm");
}

std::string past_text(const StopRest& s) {
  if (s.past >= 0) return milli(s, s.past) + " past the stop";
  return milli(s, -s.past) + " short of the stop (inside its margin of " + milli(s, s.margin) +
         ", where the limit already acts)";
}

// what ctrl = 0 means in the runs: zero torque for motors, a target of 0 for position servos
std::string zero_ctrl_text(const SoftStops& st) {
  return st.servo_held_joints.empty() ? "zero torque" : "ctrl 0";
}

// whether a position servo holds `joint` at its target in the runs
bool servo_held(const SoftStops& st, const std::string& joint) {
  return std::any_of(st.servo_held_joints.begin(), st.servo_held_joints.end(),
                     [&](const std::string& held) { return held.rfind(joint + " (", 0) == 0; });
}

void print_stop(std::ostream& out, const StopRest& s, const SoftStops& st) {
  const char* unit = position_unit(s.hinge);
  out << "  " << s.joint << ", " << (s.upper ? "upper" : "lower") << " stop " << general(s.stop)
      << " " << unit;
  if (!s.loadable) {
    out << ": gravity does not push the joint into it at any pose tried (nothing rests on it)\n";
    return;
  }
  out << (s.from_qpos0 ? ", falling from qpos0 (the lesson's run):\n"
                       : ", from " + pose_text(s.start) + ":\n");
  out << "    after " << fixed(s.time, 1) << " s with " << zero_ctrl_text(st);
  if (s.warnings > 0) out << " (" << s.warnings << " engine warnings: a state was reset)";
  if (!s.settled) {
    out << " (did not settle: max |qvel| " << fmt::sci(s.max_qvel) << " at the end)";
  }
  if (!s.rests_on_stop) {
    out << ": " << s.joint << " at " << fixed(s.q, 5) << " " << unit
        << (servo_held(st, s.joint)
                ? ", off the stop: its position servo holds it towards its target, 0 " +
                      std::string(unit) + "\n"
                : ", off the stop: with the other joints free, gravity does not hold it there\n");
    return;
  }
  out << ": " << s.joint << " at " << fixed(s.q, 5) << " " << unit << ", stop at "
      << general(s.stop) << " " << unit << " -> " << past_text(s) << "\n";
  const char* tu = torque_unit(s.hinge);
  out << "    active limit rows: " << s.rows << "; qfrc_constraint[" << s.joint
      << "] = " << fixed(s.qfrc_constraint, 4) << " " << tu << ", gravity torque qfrc_bias["
      << s.joint << "] = " << fixed(s.qfrc_bias, 4) << " " << tu;
  if (std::abs(s.qfrc_passive) > 1e-9) {  // a spring shares the load: constraint = bias - passive
    out << ", spring qfrc_passive[" << s.joint << "] = " << fixed(s.qfrc_passive, 4) << " " << tu;
  }
  out << "\n";
}

void print_stops(std::ostream& out, const SoftStops& st) {
  out << "(5) joint stops are soft constraints (" << zero_ctrl_text(st)
      << ": relaxed, polished by a static solve, then run until every |qvel| < "
      << general(st.settle_qvel) << " for " << general(st.settle_time) << " s):\n";
  if (!st.servo_held_joints.empty()) {
    // a servo's ctrl is its target position: 0 holds the joint at 0, it does not let it go
    std::string joints;
    for (const std::string& j : st.servo_held_joints) {
      if (!joints.empty()) joints += ", ";
      joints += j;
    }
    out << "  ctrl 0 is not zero torque here: a position servo's ctrl is its target, so ctrl 0 "
           "is a target of 0 and the servos pull their joints towards it: "
        << joints << "\n";
  }
  if (st.stops.empty()) out << "  no joint is limited\n";
  for (const StopRest& s : st.stops) print_stop(out, s, st);
}

// ---- (6) ---------------------------------------------------------------------------------------

void print_clamping(std::ostream& out, const Clamping& c, const TorqueBudget& b) {
  out << "(6) commands beyond ctrlrange are clamped:\n";
  if (c.ctrl.size() == 0) {
    out << "  the model has no motors\n";
    return;
  }
  out << "  ctrl = " << fmt::list(c.ctrl) << ": actuator_force = " << fmt::list(c.actuator_force)
      << (c.newton_metres ? " N m" : "")
      << (c.warnings == 0 ? " (no warning is raised)"
                          : " (" + std::to_string(c.warnings) + " engine warnings)")
      << "\n";
  for (const std::string& m : c.unbounded) {
    out << "  motor " << m << " has ctrllimited=\"false\": any command goes through\n";
  }
  if (c.any_servo()) {  // a servo's ctrl is a target: the clamp moves the target, not the force
    out << "  servos: ctrl is a target position, clamped to ctrlrange: target = "
        << fmt::list(c.target) << " at q = " << fmt::list(c.qpos) << ";\n"
        << "    gain target + bias = " << fmt::list(c.raw_force)
        << ", clamped to forcerange: actuator_force = " << fmt::list(c.actuator_force) << "\n";
  }
  const JointBudget* tightest = nullptr;
  for (const JointBudget& j : b.joints) {
    if (!j.actuated() || !j.loaded || !std::isfinite(j.ratio)) continue;
    if (!tightest || j.ratio < tightest->ratio) tightest = &j;
    if (j.ratio < 1.0) {  // the clamp is where this shows: the motor saturates holding the arm
      out << "  warning: the " << j.joint << " motor cannot hold its own arm: its limit "
          << general(j.limit) << " " << torque_unit(j.hinge) << " is below the worst-case gravity "
          << "torque " << fixed(std::abs(j.worst_torque), 3) << " " << torque_unit(j.hinge)
          << " (ratio " << fixed(j.ratio, 2) << "); commands beyond it are clamped silently\n";
    }
  }
  if (tightest && tightest->ratio >= 1.0) {
    out << "  every motor can hold its own arm: the smallest motor limit / gravity torque is "
        << fixed(tightest->ratio, 2) << " (" << tightest->joint << ")\n";
  }
}

// ---- (7) ---------------------------------------------------------------------------------------

std::string alignment_text(const JointAlignment& a) {
  return a.first + " and " + a.second + (a.collinear ? " collinear" : " parallel");
}

void print_jacobian_at(std::ostream& out, const JacobianAt& at,
                       const std::vector<std::string>& joints, bool with_pose) {
  out << "    " << at.where;
  if (with_pose) out << " (" << pose_text(at.q) << ")";
  out << ": sigma " << fmt::list(at.sigma, 4) << ", manipulability " << fmt::sig4(at.manipulability)
      << ", condition "
      << (std::isfinite(at.condition) && at.condition < 1e12 ? general(at.condition) : "inf")
      << "\n";
  // parallel axes as groups (a planar chain has every pair parallel), collinear pairs by name
  std::vector<std::string> aligned;
  std::vector<std::vector<std::string>> groups;
  const auto group_of = [&](const std::string& joint) -> int {
    for (size_t g = 0; g < groups.size(); ++g) {
      if (std::find(groups[g].begin(), groups[g].end(), joint) != groups[g].end()) return int(g);
    }
    return -1;
  };
  for (const JointAlignment& a : at.aligned) {
    if (a.collinear) aligned.push_back(alignment_text(a));
    const int g1 = group_of(a.first), g2 = group_of(a.second);
    if (g1 < 0 && g2 < 0) {
      groups.push_back({a.first, a.second});
    } else if (g1 < 0) {
      groups[g2].push_back(a.first);
    } else if (g2 < 0) {
      groups[g1].push_back(a.second);
    } else if (g1 != g2) {
      groups[g1].insert(groups[g1].end(), groups[g2].begin(), groups[g2].end());
      groups.erase(groups.begin() + g2);
    }
  }
  for (std::vector<std::string>& g : groups) {
    const bool named =
        g.size() == 2 &&
        std::any_of(at.aligned.begin(), at.aligned.end(), [&](const JointAlignment& a) {
          return a.collinear &&
                 ((a.first == g[0] && a.second == g[1]) || (a.first == g[1] && a.second == g[0]));
        });
    if (named) continue;  // already printed as collinear
    std::sort(g.begin(), g.end(), [&](const std::string& x, const std::string& y) {
      return std::find(joints.begin(), joints.end(), x) <
             std::find(joints.begin(), joints.end(), y);
    });
    aligned.push_back((g.size() == 2 ? g[0] + " and " + g[1] : "{" + names(g) + "}") + " parallel");
  }
  out << "      aligned axes: " << (aligned.empty() ? "none" : names(aligned));
  if (at.null_motion.size()) {
    // the joints that move in the direction that moves the site least
    std::vector<std::string> movers;
    for (Eigen::Index i = 0; i < at.null_motion.size() && i < Eigen::Index(joints.size()); ++i) {
      if (std::abs(at.null_motion[i]) >= 0.1)
        movers.push_back(joints[i] + " " + fixed(at.null_motion[i], 2));
    }
    out << "; least-moving joint motion: " << names(movers);
  }
  out << "\n";
}

void print_singular(std::ostream& out, const SingularPoses& sp, const Structure& st) {
  out << "(7) singular poses: the site Jacobian's singular values over the joint ranges:\n";
  if (sp.sites.empty()) {
    out << "  the model has no sites (or no joints)\n";
    return;
  }
  std::vector<std::string> joints;
  for (const JointInfo& j : st.joints) joints.push_back(j.name);
  for (const SiteSingularity& s : sp.sites) {
    out << "  site " << s.site << ": "
        << (s.rows == 6 ? "J = [jacp; jacr] (6 x nv)"
                        : "J = jacp (3 x nv: with fewer than 6 joints the arm cannot also orient "
                          "the site, so its position is the task)")
        << ", rank " << s.rank << " at generic poses, so " << s.rank
        << (s.rank == 1 ? " singular value counts" : " singular values count")
        << " (singular where the smallest vanishes)\n";
    for (const JacobianAt& at : s.states) print_jacobian_at(out, at, joints, at.where != "qpos0");
    out << "    most singular poses found:\n";
    for (const JacobianAt& at : s.worst) print_jacobian_at(out, at, joints, true);
  }
  out << "    (searched: " << sp.search << "; " << sp.evaluations
      << " Jacobians; axes parallel or collinear within " << general(sp.parallel_tolerance)
      << " rad and m)\n";
}

// ---- (8) ---------------------------------------------------------------------------------------

std::string timestep_text(double h, const StabilityScan& scan) {
  if (std::isinf(h)) return "stable up to the search's cap";
  if (h == 0.0) return "none (unstable at " + general(scan.from) + " s, the smallest searched)";
  return general(h) + " s";
}

// The stretches where a search found the step stable: "[a, b], [c, d]".
std::string stable_stretches(const StabilityScan& s, bool from_zero) {
  std::string out;
  const auto add = [&out](double a, double b) {
    out += (out.empty() ? "[" : ", [") + general(a) + ", " + general(b) + "]";
  };
  bool stable = s.stable_first;
  double start = from_zero ? 0.0 : s.from;
  for (const double change : s.changes) {
    if (stable) add(start, change);
    start = change;
    stable = !stable;
  }
  if (stable) add(start, s.to);
  return out.empty() ? "none" : out;
}

// A search whose stability changed more than once: where it is stable, and what the value
// reported chose.
std::string several_changes(const std::string& what, const StabilityScan& s, bool timestep) {
  return "      " + what + ": " + std::to_string(s.changes.size()) + " changes, stable on " +
         stable_stretches(s, !timestep) + (timestep ? " s" : " kg m^2") +
         (timestep ? "; reported: the largest timestep below which every one is stable\n"
                   : "; reported: the smallest armature above which every one is stable\n");
}

// How the searches were made, and every search that found more than one boundary.
void print_searches(std::ostream& out, const StepStability& st, const StabilityAt& s) {
  std::string notes;
  const auto note = [&](const std::string& what, const StabilityScan& scan, bool timestep) {
    if (scan.several()) notes += several_changes(what, scan, timestep);
  };
  note(st.integrator + " timestep", s.dt_scan_model, true);
  if (st.integrator != "Euler") note("Euler timestep", s.dt_scan_euler, true);
  note("Euler armature on every joint", s.armature_scan_all, false);
  for (size_t j = 0; j < s.armature_scan_each.size(); ++j) {
    note("Euler armature, " + st.joints[j] + " with the others heavy", s.armature_scan_each[j],
         false);
  }
  note("Euler armature, the common floor", s.armature_scan_floor, false);
  for (size_t j = 0; j < s.armature_scan_alone.size(); ++j) {
    note("Euler armature, " + st.joints[j] + " alone", s.armature_scan_alone[j], false);
  }
  const StabilityScan& grid = s.dt_scan_model;
  out << "    searched: timesteps " << general(grid.from) << " to " << general(grid.to)
      << " s, armatures 0 and " << general(s.armature_scan_all.from) << " to "
      << general(s.armature_scan_all.to) << " kg m^2, " << st.points_per_decade
      << " points a decade, each change of stability bisected to a relative "
      << general(grid.resolution) << "; "
      << (notes.empty() ? "every search found one change at most\n"
                        : "stability changes more than once in:\n" + notes);
}

std::string armature_text(double a) {
  return std::isinf(a) ? "none up to the cap" : fmt::rounded(a, 4);
}

void print_run(std::ostream& out, const StabilityRun& r) {
  out << "      " << r.integrator << ", armature " << r.armature << ": ";
  if (!r.bounded()) {
    out << "blows up at step " << r.blowup_step << " ("
        << (r.warnings > 0 ? std::to_string(r.warnings) + " engine warnings: a state was reset"
                           : "max |qvel| " + fmt::sig4(r.max_qvel))
        << ")\n";
  } else if (r.settled) {
    out << "settles: max |qvel| " << fmt::sig4(r.max_qvel) << ", " << fmt::sig4(r.final_qvel)
        << " over the last tenth of " << r.steps << " steps\n";
  } else {
    out << "does not settle: |qvel| still " << fmt::sig4(r.final_qvel) << " over the last tenth of "
        << r.steps << " steps";
    if (r.saturated > 0) {
      out << ", a force on its forcerange in " << r.saturated
          << " steps (the clamp caps the growth: a limit cycle)";
    }
    out << "\n";
  }
}

void print_stability(std::ostream& out, const StepStability& st) {
  out << "(8) stability of the step (timestep " << general(st.timestep) << " s, integrator "
      << st.integrator << "; rho: spectral radius of d[qpos'; qvel']/d[qpos; qvel] by central "
      << "differences of step):\n";
  if (st.states.empty()) {
    out << "  the model has no joints\n";
    return;
  }
  const bool euler = st.integrator == "Euler";
  for (const StabilityAt& s : st.states) {
    out << "  at " << s.where << ", ctrl " << fmt::list(s.ctrl, 4) << ":\n";
    out << "    the dynamics' own growth rate max Re(lambda) = " << fixed(s.growth, 3)
        << " 1/s; a step is stable when rho <= max(1, exp(h growth)) (1 + " << general(st.slack)
        << ")\n";
    out << "    " << st.integrator << " rho = " << fixed(s.rho_model, 4)
        << (s.stable_model ? " stable" : " UNSTABLE");
    if (!euler)
      out << "; explicit Euler rho = " << fixed(s.rho_euler, 4)
          << (s.stable_euler ? " stable" : " unstable");
    out << "\n    largest stable timestep: " << st.integrator << " "
        << timestep_text(s.max_dt_model, s.dt_scan_model);
    if (!euler) out << ", Euler " << timestep_text(s.max_dt_euler, s.dt_scan_euler);
    out << "\n";
    out << "    smallest armature for a stable Euler step at " << general(st.timestep)
        << " s: the same on every joint " << armature_text(s.armature_all) << " kg m^2\n";
    if (std::isfinite(s.armature_all) && s.armature_all > 0) {
      std::vector<std::string> each, alone;
      bool any_alone = false;
      for (size_t j = 0; j < st.joints.size(); ++j) {
        each.push_back(st.joints[j] + " " + armature_text(s.armature_each[j]));
        alone.push_back(st.joints[j] + " " + armature_text(s.armature_alone[j]));
        any_alone = any_alone || std::isfinite(s.armature_alone[j]);
      }
      out << fmt::wrap(
                 "      per joint, each with the others given " + general(st.ample) + " x that:",
                 each, "        ")
          << "\n";
      out << "      together (the joints couple): max(per joint, "
          << armature_text(s.armature_floor) << ") on each joint\n";
      if (any_alone) {
        out << fmt::wrap("      per joint alone, the others as in the model:", alone, "        ")
            << "\n";
      } else {
        out << "      no joint's armature alone makes it stable (the others as in the model)\n";
      }
      out << "    Euler rho with " << general(st.margin) << " x those: the same on every joint "
          << fixed(s.rho_euler_with, 4) << ", per joint together " << fixed(s.rho_euler_each, 4)
          << (s.stable_euler_each ? " stable" : " UNSTABLE") << "\n";
    }
    print_searches(out, st, s);
    out << "    simulated " << (s.runs.empty() ? 0 : s.runs.front().steps)
        << " steps from this state:\n";
    for (const StabilityRun& r : s.runs) print_run(out, r);
  }
}

// ---- (9) contacts ------------------------------------------------------------------------------

std::string numbers(const double* x, int n) {
  std::string s;
  for (int i = 0; i < n; ++i) {
    if (i > 0) s += ' ';
    s += general(x[i]);
  }
  return s;
}

void print_pairs(std::ostream& out, const Contacts& c) {
  out << "  geom pairs that can touch (contype/conaffinity, weld and parent filters, <exclude>; "
         "<pair>):\n";
  for (const ContactPairInfo& p : c.pairs) {
    out << "    " << p.geom1 << " - " << p.geom2 << (p.explicit_pair ? " (<pair>)" : "")
        << ": condim " << p.condim << ", friction " << numbers(p.friction.data(), 3) << ", solref "
        << numbers(p.solref.data(), 2) << ", solimp " << numbers(p.solimp.data(), 5) << ", margin "
        << general(p.margin) << ", gap " << general(p.gap);
    if (p.seen > 0) {
      out << "; " << p.seen << " contacts in the runs below, "
          << (p.agrees ? "each with these parameters" : "NOT all with these parameters");
    }
    out << "\n";
  }
}

void print_rest(std::ostream& out, const RestingDepth& r) {
  out << "  resting depth of a free body on a plane:";
  if (!r.skipped.empty()) {
    out << " skipped: " << r.skipped << "\n";
    return;
  }
  out << " body " << r.body << " (m = " << general(r.mass) << " kg) on " << r.plane << "\n";
  out << "    at rest a = 0 and v = 0, so each row pushes f = D aref = K d(p) p / R with\n"
         "    aref = -B v - K d(r) r (r = -p, the depth past the margin) and R = (1 - d)/d A;\n"
         "    the rows' normal forces carry the weight:\n"
         "      n_contacts n_rows K d(p)^2 p / ((1 - d(p)) A) = m g\n";
  out << "    K = 1/(dmax^2 timeconst^2 dampratio^2) = " << sig4(r.K) << " 1/s^2 (solref "
      << numbers(r.solref.data(), 2) << ", solimp " << numbers(r.solimp.data(), 5) << ")\n";
  if (r.condim == 1 || r.elliptic) {
    out << "    A = t = " << sig4(r.A) << " 1/kg (body_invweight0, translation), 1 row per contact";
    if (r.condim > 1)
      out << " (elliptic cone: the normal row; its friction rows push nothing at rest)";
    out << "\n";
  } else {
    out << "    A = 2 mu^2 (1 + mu^2) t / impratio = " << sig4(r.A) << " 1/kg (mu "
        << general(r.friction) << ", t = " << sig4(r.invweight)
        << " 1/kg from body_invweight0, impratio " << general(r.impratio) << "), " << r.rows
        << " pyramid edges per contact (condim " << r.condim << ")\n";
  }
  out << "    " << r.contacts << " contacts at rest, m g = " << fixed(r.mass * r.gravity, 4)
      << " N: p = " << sig4(r.predicted * 1e3) << " mm (d(p) = " << fixed(r.impedance, 4) << ")\n";
  out << "    simulation from " << r.start << ": " << (r.settled ? "at rest" : "NOT at rest")
      << " after " << fixed(r.time, 3) << " s (|qvel| " << sci(r.final_speed) << "), mean depth "
      << sig4(r.simulated * 1e3) << " mm (contacts within " << sci(r.spread)
      << " m of each other)\n";
  if (r.unsupported > 0) {
    out << "    (" << r.unsupported
        << " warnings in the run: geoms lever cannot collide came near each other)\n";
  }
  out << "    difference " << sci(r.simulated - r.predicted) << " m, bound " << sci(r.bound)
      << " m (the speed left, B |v| / (K d p) of the depth, and the spread): "
      << (r.agrees() ? "agrees" : "DISAGREES") << "\n";
}

void print_grip(std::ostream& out, const Grip& g) {
  out << "  grip: two fingers pressing with force F hold a box of mass m if 2 mu F >= m g:";
  if (!g.skipped.empty()) {
    out << " skipped: " << g.skipped << "\n";
    return;
  }
  out << "\n    body " << g.body << " (m = " << general(g.mass) << " kg), fingers " << g.fingers[0]
      << " and " << g.fingers[1] << ", mu = " << general(g.mu) << " (the mixed friction)\n";
  out << "    needed: F = m g / (2 mu) = " << fixed(g.needed, 4) << " N\n";
  out << "    the servos at full command " << general(g.full_command) << ": kp (command - "
      << fixed(g.touch, 5) << ") = " << fixed(g.servo_force, 4)
      << " N (clamped by forcerange; simulated: " << fixed(g.servo_force_closed, 4)
      << " N): " << fixed(g.servo_force / g.needed, 2) << " x needed, "
      << (g.holds_by_hand() ? "holds" : "CANNOT hold") << "\n";
  out << "    simulation: the box between the fingers, closed for " << general(g.close_time)
      << " s without gravity, then " << general(g.hold_time)
      << " s with it; a slip: the box's falling speed grows by more than "
      << general(g.speedup_threshold)
      << " m/s over the second half (a held box creeps at a "
         "steady speed: "
      << fixed(g.creep * 1e3, 3) << " mm at the full grip)\n";
  for (const GripTrial& t : g.trials) {
    out << "      F = " << fixed(t.closed_force, 4) << " N closed, " << fixed(t.force, 4)
        << " N while held: drop " << fixed(t.drop * 1e3, 3) << " mm, speed-up "
        << fixed(t.speedup, 4) << " m/s" << (t.slipped ? ": slipped" : "") << "\n";
  }
  if (!g.pads.empty()) {
    out << "    touch sensors on the fingers at the full grip (the normal force they feel) against "
           "the servo's push, closed | held:\n";
  }
  for (const GripPad& p : g.pads) {
    out << "      " << p.sensor << " on " << p.finger << ": " << fixed(p.closed, 4) << " N vs "
        << fixed(p.servo_closed, 4) << " N | " << fixed(p.held, 4) << " N vs "
        << fixed(p.servo_held, 4) << " N: " << (p.agrees() ? "agree" : "DISAGREE")
        << " (within " << general(100 * p.tolerance) << " %)\n";
  }
  if (g.slip_force == 0.0) {
    out << "    the box never slipped\n";
  } else if (!std::isfinite(g.hold_force)) {
    out << "    the box slipped at the full grip (" << fixed(g.slip_force, 4) << " N)\n";
  } else {
    out << "    slips between " << fixed(g.slip_force, 4) << " and " << fixed(g.hold_force, 4)
        << " N; m g / (2 mu) = " << fixed(g.needed, 4) << " N (difference "
        << fixed(0.5 * (g.slip_force + g.hold_force) - g.needed, 4) << " N, "
        << fixed(100 * (0.5 * (g.slip_force + g.hold_force) / g.needed - 1), 2) << " %)\n";
  }
}

void print_contacts(std::ostream& out, const Contacts& c) {
  out << "(9) contacts: the pairs that can touch, a body's resting depth, the grip force:";
  if (!c.skipped.empty()) {
    out << " skipped: " << c.skipped << "\n";
    return;
  }
  out << "\n";
  print_pairs(out, c);
  print_rest(out, c.rest);
  print_grip(out, c.grip);
}

void print_findings(std::ostream& out, const Report& r) {
  if (r.findings.empty()) {
    out << "findings: none: every claim checks out (exit status 0)\n";
    return;
  }
  out << "findings (" << r.findings.size() << "):\n";
  for (const std::string& f : r.findings) out << "  - " << f << "\n";
  out << "exit status " << r.exit_status() << "\n";
}

}  // namespace

std::string to_text(const Report& r) {
  std::ostringstream out;
  out << "lever check " << r.source << " (model \"" << r.model << "\")\n";
  // a section that does not apply says so under its heading
  const auto section = [&](int n, const char* title, const auto& print) {
    const std::string why = r.skipped(n);
    if (why.empty()) {
      print();
    } else {
      out << "(" << n << ") " << title << ": skipped: " << why << "\n";
    }
  };
  print_structure(out, r.structure);
  section(2, "forward kinematics of every site", [&] { print_kinematics(out, r.kinematics); });
  section(3, "gravity torque and motor sizing", [&] { print_budget(out, r.budget); });
  print_inertia(out, r.inertia, r.budget);
  section(5, "joint stops are soft constraints", [&] { print_stops(out, r.stops); });
  print_clamping(out, r.clamping, r.budget);
  section(7, "singular poses", [&] { print_singular(out, r.singular, r.structure); });
  section(8, "stability of the step", [&] { print_stability(out, r.stability); });
  print_contacts(out, r.contacts);
  print_findings(out, r);
  return out.str();
}

}  // namespace lever::check
