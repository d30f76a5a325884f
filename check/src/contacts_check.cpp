// (9) Contacts, lesson 5.3's hand calculations: which geom pairs can touch and with what
// parameters, how deep a free body sinks into a plane at rest (solref/solimp's steady state), and
// the force two finger servos need to hold a box (2 mu F >= m g) against a simulation that lowers
// the grip until the box slips, and what touch sensors on the fingers read against the servos.
#include <algorithm>
#include <cmath>
#include <optional>

#include <lever/check.hpp>
#include <lever/data.hpp>
#include <lever/error.hpp>
#include <lever/forward.hpp>
#include <lever/kinematics.hpp>

#include "util.hpp"

namespace lever::check {

namespace {

constexpr double kMinVal = 1e-15;      // MuJoCo's mjMINVAL
constexpr double kMinImp = 1e-4;       // mjMINIMP: impedance is kept inside (0, 1)
constexpr double kMaxImp = 0.9999;     // mjMAXIMP
constexpr double kMinFriction = 1e-5;  // mjMINMU: the least friction a contact gets

// ---- which pairs can touch ----------------------------------------------------------------------

/// The body each body moves with: itself if it has joints, else its parent's (the world is 0).
std::vector<int> weld_bodies(const Model& m) {
  std::vector<int> weld(m.nbody, 0);
  for (int b = 1; b < m.nbody; ++b) weld[b] = m.body_jntnum[b] > 0 ? b : weld[m.body_parentid[b]];
  return weld;
}

bool excluded(const Model& m, int b1, int b2) {
  const int signature = ((std::min(b1, b2) + 1) << 16) + std::max(b1, b2) + 1;
  return std::binary_search(m.exclude_signature.begin(), m.exclude_signature.end(), signature);
}

bool named_by_pair(const Model& m, int g1, int g2) {
  for (int p = 0; p < m.npair; ++p) {
    if ((m.pair_geom1[p] == g1 && m.pair_geom2[p] == g2) ||
        (m.pair_geom1[p] == g2 && m.pair_geom2[p] == g1)) {
      return true;
    }
  }
  return false;
}

// the filters of a pair found by contype/conaffinity (a <pair> skips them)
bool passes_filters(const Model& m, const std::vector<int>& weld, int g1, int g2) {
  const auto flat = [](GeomType t) { return t == GeomType::kPlane || t == GeomType::kHfield; };
  if (flat(m.geom_type[g1]) && flat(m.geom_type[g2])) return false;  // planes never collide
  if (!(m.geom_contype[g1] & m.geom_conaffinity[g2]) &&
      !(m.geom_contype[g2] & m.geom_conaffinity[g1])) {
    return false;
  }
  const int b1 = m.geom_bodyid[g1], b2 = m.geom_bodyid[g2];
  const int w1 = weld[b1], w2 = weld[b2];
  if (w1 == w2) return false;  // one rigid body
  // a body and its parent do not collide, unless one of them is the world
  if (w1 != 0 && w2 != 0 && (w1 == weld[m.body_parentid[w2]] || w2 == weld[m.body_parentid[w1]]))
    return false;
  return !excluded(m, b1, b2) && !named_by_pair(m, g1, g2);
}

// a contact's parameters from its two geoms: the higher priority's, else friction and condim by
// max and solref/solimp weighted by solmix
ContactPairInfo mixed(const Model& m, int g1, int g2) {
  ContactPairInfo p;
  p.geom1 = geom_label(m, g1);
  p.geom2 = geom_label(m, g2);
  p.margin = std::max(m.geom_margin[g1], m.geom_margin[g2]);
  p.gap = std::max(m.geom_gap[g1], m.geom_gap[g2]);
  if (m.geom_priority[g1] != m.geom_priority[g2]) {
    const int g = m.geom_priority[g1] > m.geom_priority[g2] ? g1 : g2;
    p.condim = m.geom_condim[g];
    for (int i = 0; i < 3; ++i) p.friction[i] = m.geom_friction[g][i];
    p.solref = m.geom_solref[g];
    p.solimp = m.geom_solimp[g];
  } else {
    p.condim = std::max(m.geom_condim[g1], m.geom_condim[g2]);
    for (int i = 0; i < 3; ++i)
      p.friction[i] = std::max(m.geom_friction[g1][i], m.geom_friction[g2][i]);
    const double s1 = m.geom_solmix[g1], s2 = m.geom_solmix[g2];
    double w = 0.5;  // both solmix zero: an even mix
    if (s1 >= kMinVal && s2 >= kMinVal) {
      w = s1 / (s1 + s2);
    } else if (s1 >= kMinVal || s2 >= kMinVal) {
      w = s1 >= kMinVal ? 1.0 : 0.0;
    }
    const auto& r1 = m.geom_solref[g1];
    const auto& r2 = m.geom_solref[g2];
    for (int i = 0; i < 2; ++i) {
      // direct (negative) solref values cannot be averaged with time constants: the smaller wins
      p.solref[i] = r1[0] > 0 && r2[0] > 0 ? w * r1[i] + (1 - w) * r2[i] : std::min(r1[i], r2[i]);
    }
    for (int i = 0; i < 5; ++i)
      p.solimp[i] = w * m.geom_solimp[g1][i] + (1 - w) * m.geom_solimp[g2][i];
  }
  for (double& mu : p.friction) mu = std::max(kMinFriction, mu);
  return p;
}

struct PairTable {
  std::vector<ContactPairInfo> pairs;
  std::vector<std::array<int, 2>> geoms;  // the same pairs as geom ids, lower first

  int find(int g1, int g2) const {
    const std::array<int, 2> key{std::min(g1, g2), std::max(g1, g2)};
    for (size_t i = 0; i < geoms.size(); ++i)
      if (geoms[i] == key) return static_cast<int>(i);
    return -1;
  }
};

PairTable touching_pairs(const Model& m) {
  PairTable t;
  const std::vector<int> weld = weld_bodies(m);
  for (int g1 = 0; g1 < m.ngeom; ++g1) {
    for (int g2 = g1 + 1; g2 < m.ngeom; ++g2) {
      if (!passes_filters(m, weld, g1, g2)) continue;
      t.pairs.push_back(mixed(m, g1, g2));
      t.geoms.push_back({g1, g2});
    }
  }
  for (int p = 0; p < m.npair; ++p) {
    ContactPairInfo info;
    const int g1 = m.pair_geom1[p], g2 = m.pair_geom2[p];
    info.geom1 = geom_label(m, g1);
    info.geom2 = geom_label(m, g2);
    info.explicit_pair = true;
    info.condim = m.pair_dim[p];
    // pair_friction: tangent1, tangent2, torsional, rolling1, rolling2
    info.friction[0] = std::max(kMinFriction, m.pair_friction[p][0]);
    info.friction[1] = std::max(kMinFriction, m.pair_friction[p][2]);
    info.friction[2] = std::max(kMinFriction, m.pair_friction[p][3]);
    info.solref = m.pair_solref[p];
    info.solimp = m.pair_solimp[p];
    info.margin = m.pair_margin[p];
    info.gap = m.pair_gap[p];
    t.pairs.push_back(info);
    t.geoms.push_back({std::min(g1, g2), std::max(g1, g2)});
  }
  return t;
}

bool close(double a, double b) { return std::abs(a - b) <= 1e-12 * std::max(1.0, std::abs(b)); }

// every contact a simulation made belongs to a listed pair and got its parameters
void tally(const Model& m, const Data& d, PairTable& t, std::vector<std::string>& strays) {
  for (int i = 0; i < d.ncon; ++i) {
    const Contact& c = d.contact[i];
    const int k = t.find(c.geom1, c.geom2);
    if (k < 0) {
      const std::string what = geom_label(m, c.geom1) + " and " + geom_label(m, c.geom2);
      if (std::find(strays.begin(), strays.end(), what) == strays.end()) strays.push_back(what);
      continue;
    }
    ContactPairInfo& p = t.pairs[k];
    ++p.seen;
    bool same = c.dim == p.condim && close(c.friction[0], p.friction[0]) &&
                close(c.friction[2], p.friction[1]) && close(c.friction[3], p.friction[2]) &&
                close(c.includemargin, p.margin - p.gap);
    for (int j = 0; j < 2; ++j) same = same && close(c.solref[j], p.solref[j]);
    for (int j = 0; j < 5; ++j) same = same && close(c.solimp[j], p.solimp[j]);
    p.agrees = p.agrees && same;
  }
}

// ---- the soft contact's steady state ------------------------------------------------------------

/// solref and solimp as the solver uses them (timeconst at least two steps, impedances in (0, 1)).
void usable(const Model& m, std::array<double, 2>& solref, std::array<double, 5>& solimp) {
  if ((solref[0] > 0) != (solref[1] > 0)) solref = {0.02, 1.0};
  if (solref[0] > 0) solref[0] = std::max(solref[0], 2 * m.opt.timestep);
  for (int i : {0, 1, 3}) solimp[i] = std::clamp(solimp[i], kMinImp, kMaxImp);
  solimp[2] = std::max(0.0, solimp[2]);
  solimp[4] = std::max(1.0, solimp[4]);
}

/// solimp's impedance d at depth p past the margin: d0 at the surface, dmax from `width` deep on,
/// between them the spline of power `power` through its midpoint (MuJoCo's documentation).
double impedance_at(const std::array<double, 5>& s, double p) {
  const double d0 = s[0], dmax = s[1], width = s[2], mid = s[3], power = s[4];
  const double x = std::abs(p) / std::max(width, kMinVal);
  if (width <= kMinVal || x >= 1) return dmax;
  double y = x;
  if (power != 1) {
    y = x <= mid ? std::pow(x, power) / std::pow(mid, power - 1)
                 : 1 - std::pow(1 - x, power) / std::pow(1 - mid, power - 1);
  }
  return d0 + y * (dmax - d0);
}

/// The normal force n_contacts x rows rows push with at depth p, at rest (a = 0, v = 0).
double resting_force(const RestingDepth& r, double p) {
  const double d = impedance_at(r.solimp, p);
  return r.contacts * r.rows * r.K * d * d * p / ((1 - d) * r.A);
}

double solve_depth(const RestingDepth& r) {
  const double weight = r.mass * r.gravity;
  double lo = 0.0, hi = 1e-6;
  while (resting_force(r, hi) < weight && hi < 1e3) hi *= 2;
  for (int i = 0; i < 200 && hi - lo > 1e-16 * hi; ++i) {
    const double mid = 0.5 * (lo + hi);
    (resting_force(r, mid) < weight ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

int free_joint_of(const Model& m, int body) {
  for (int j = m.body_jntadr[body]; j >= 0 && j < m.body_jntadr[body] + m.body_jntnum[body]; ++j)
    if (m.jnt_type[j] == JointType::kFree) return j;
  return -1;
}

// the state a section starts from: the first keyframe, else qpos0 (a keyframe's ctrl with it)
std::string start_state(const Model& m, Data& d) {
  if (m.nkey > 0) {
    reset_keyframe(m, d, 0);
    return "keyframe " +
           (m.key_name.empty() || m.key_name[0].empty() ? std::string("0") : m.key_name[0]);
  }
  reset(m, d);
  return "qpos0";
}

/// Servos hold their joints where they are (ctrl = the actuator's length); motors push nothing.
void hold_servos(const Model& m, Data& d, const std::vector<int>& except) {
  forward(m, d);
  for (int a = 0; a < m.nu; ++a) {
    if (std::find(except.begin(), except.end(), a) != except.end()) continue;
    d.ctrl[a] = is_servo(m.actuator_kind[a]) ? d.actuator_length[a] : 0.0;
  }
}

// the warnings that make a run meaningless (a state reset, a singular M); a pair lever cannot
// collide that came near is reported by the loader's finding, and does not spoil the run
int spoiling_warnings(const Data& d) {
  return warning_count(d) - d.warning[static_cast<int>(Warning::kContactUnsupported)].number;
}

int unsupported_warnings(const Data& d) {
  return d.warning[static_cast<int>(Warning::kContactUnsupported)].number;
}

double body_speed(const Model& m, const Data& d, int joint) {
  const int dof = m.jnt_dofadr[joint];
  return d.qvel.segment(dof, 6).cwiseAbs().maxCoeff();
}

RestingDepth resting_depth(const Model& m, PairTable& table, std::vector<std::string>& strays) {
  RestingDepth r;
  // the first free body with a geom that can touch a plane
  int body = -1, plane = -1;
  for (size_t k = 0; k < table.geoms.size() && body < 0; ++k) {
    for (int side = 0; side < 2; ++side) {
      const int g = table.geoms[k][side], other = table.geoms[k][1 - side];
      if (m.geom_type[g] != GeomType::kPlane) continue;
      const int b = m.geom_bodyid[other];
      if (free_joint_of(m, b) >= 0) body = b, plane = g;
    }
  }
  if (body < 0) {
    r.skipped = "no free body can touch a plane";
    return r;
  }
  r.body = body_label(m, body);
  r.plane = geom_label(m, plane);
  const int joint = free_joint_of(m, body);

  Data d(m);
  r.start = start_state(m, d);
  const int steps = static_cast<int>(std::ceil(r.time_bound / m.opt.timestep));
  int quiet = 0;  // steps in a row below the settle speed: a bounce's top is not rest
  const int quiet_needed = static_cast<int>(std::ceil(0.1 / m.opt.timestep));
  for (int i = 0; i < steps && quiet < quiet_needed; ++i) {
    step(m, d);
    quiet = body_speed(m, d, joint) < r.settle_speed ? quiet + 1 : 0;
  }
  forward(m, d);
  tally(m, d, table, strays);
  r.time = d.time;
  r.final_speed = body_speed(m, d, joint);
  r.settled = quiet >= quiet_needed && spoiling_warnings(d) == 0;
  r.unsupported = unsupported_warnings(d);

  // the contacts between the body and the plane, and their depth past the margin
  double lo = kInf, hi = -kInf, sum = 0;
  int pair = -1;
  for (int i = 0; i < d.ncon; ++i) {
    const Contact& c = d.contact[i];
    const bool on_plane = (c.geom1 == plane && m.geom_bodyid[c.geom2] == body) ||
                          (c.geom2 == plane && m.geom_bodyid[c.geom1] == body);
    if (!on_plane || c.exclude) continue;
    const double depth = c.includemargin - c.dist;
    lo = std::min(lo, depth), hi = std::max(hi, depth), sum += depth;
    ++r.contacts;
    pair = table.find(c.geom1, c.geom2);
  }
  if (r.contacts == 0 || pair < 0) {
    r.skipped = "body " + r.body + " does not rest on " + r.plane + " after " +
                std::to_string(r.time) + " s from " + r.start;
    return r;
  }
  r.simulated = sum / r.contacts;
  r.spread = hi - lo;

  const ContactPairInfo& p = table.pairs[pair];
  r.condim = p.condim;
  r.friction = p.friction[0];
  r.solref = p.solref;
  r.solimp = p.solimp;
  usable(m, r.solref, r.solimp);
  r.impratio = m.opt.impratio;
  const Eigen::Vector3d normal = d.geom_xmat[plane].col(2);
  r.mass = m.body_subtreemass[body];
  r.gravity = std::abs(m.opt.gravity.dot(normal));
  const double dmax = r.solimp[1];
  r.K = r.solref[0] > 0 ? 1 / (dmax * dmax * r.solref[0] * r.solref[0] * r.solref[1] * r.solref[1])
                        : -r.solref[0] / (dmax * dmax);
  r.invweight = m.body_invweight0[body][0] + m.body_invweight0[m.geom_bodyid[plane]][0];
  r.elliptic = m.opt.cone == Cone::kElliptic;
  if (r.condim == 1 || r.elliptic) {
    // one normal row per contact; an elliptic cone's friction rows carry nothing at rest (their
    // aref is -B v = 0, and with the normal row pushing every row is in the cone's quadratic
    // zone, f = -D (J a - aref))
    r.rows = 1;
    r.A = r.invweight;
  } else {
    // a pyramid's 2 (condim - 1) edges share R = 2 mu^2 R_normal / impratio, where the normal
    // row's approximate inverse inertia is t (1 + mu^2): the edge n + mu t_1 moves both ways
    r.rows = 2 * (r.condim - 1);
    const double mu = r.friction;
    r.A = 2 * mu * mu * (1 + mu * mu) * r.invweight / std::max(kMinVal, r.impratio);
  }
  r.predicted = solve_depth(r);
  r.impedance = impedance_at(r.solimp, r.predicted);
  // What the hand calculation leaves out, each bounded: (1) the rest is not exact: a speed v
  // left changes each row's aref by B v, so the force by B v / (K d p) relative, and the depth
  // by at most that (the force grows at least linearly with p); (2) the contacts need not be
  // equally deep (spread): the force is convex in p, so the mean depth differs from the depth of
  // equal sharing by at most the spread. The rest is rounding (1e-12 relative).
  const double B = r.solref[1] > 0 ? 2 / (dmax * r.solref[0]) : -r.solref[1] / dmax;
  r.bound =
      r.predicted * (B * r.final_speed / (r.K * r.impedance * r.predicted) + 1e-12) + r.spread;
  return r;
}

// ---- the grip
// ------------------------------------------------------------------------------------

struct Finger {
  int actuator = -1, joint = -1;
  std::vector<int> geoms;  // the finger's geoms that can touch the box
  double closing = 1.0;    // +1: the command closes the finger as it grows
  double kp = 0.0;         // force per unit of command
};

struct GripSetup {
  const Model& with_gravity;
  Model without_gravity;
  Data start;  // the box placed between the open fingers, everything at rest
  int body = -1, free_joint = -1;
  std::vector<Finger> fingers;
  std::vector<double> touch;  // each finger's actuator length holding the box at full command
  Eigen::Vector3d down;       // unit vector along gravity
};

double finger_gap(const Data& d, const Finger& f, int body) {
  double sum = 0;
  for (int g : f.geoms) sum += (d.geom_xpos[g] - d.xipos[body]).norm();
  return sum / static_cast<double>(f.geoms.size());
}

// the fingers' servo force, mean over the fingers
double finger_force(const GripSetup& s, const Data& d) {
  double sum = 0;
  for (const Finger& f : s.fingers) sum += std::abs(d.actuator_force[f.actuator]);
  return sum / static_cast<double>(s.fingers.size());
}

// A finger's touch sensor and where its numbers are.
struct PadSensor {
  int adr = -1;     // its one number in sensordata
  int finger = -1;  // index into GripSetup::fingers
};

// the touch sensors whose sites move with a finger's joint
std::vector<PadSensor> finger_pads(const Model& m, const std::vector<Finger>& fingers,
                                   Grip& g) {
  const std::vector<int> weld = weld_bodies(m);
  std::vector<PadSensor> pads;
  for (int s = 0; s < m.nsensor; ++s) {
    if (m.sensor_type[s] != SensorType::kTouch) continue;
    const int body = weld[m.site_bodyid[m.sensor_objid[s]]];
    for (size_t f = 0; f < fingers.size(); ++f) {
      if (body != m.jnt_bodyid[fingers[f].joint]) continue;
      pads.push_back({m.sensor_adr[s], static_cast<int>(f)});
      GripPad pad;
      pad.sensor = m.sensor_name[s].empty() ? "#" + std::to_string(s) : m.sensor_name[s];
      pad.finger = motor_label(m, fingers[f].actuator);
      g.pads.push_back(pad);
    }
  }
  return pads;
}

// close the fingers without gravity at `commands`, then let gravity act: how far the box drops;
// with `pads`, what the fingers' touch sensors read against their servos (into `read`)
GripTrial run_trial(GripSetup& s, const std::vector<double>& commands, const Grip& g,
                    PairTable& table, std::vector<std::string>& strays, Data* closed = nullptr,
                    const std::vector<PadSensor>& pads = {}, std::vector<GripPad>* read = nullptr) {
  const auto servo = [&s](const Data& d, const PadSensor& p) {
    return std::abs(d.actuator_force[s.fingers[static_cast<size_t>(p.finger)].actuator]);
  };
  Data d = s.start;
  for (size_t i = 0; i < s.fingers.size(); ++i) d.ctrl[s.fingers[i].actuator] = commands[i];
  const int close_steps = static_cast<int>(std::lround(g.close_time / s.with_gravity.opt.timestep));
  const int hold_steps = static_cast<int>(std::lround(g.hold_time / s.with_gravity.opt.timestep));
  for (int i = 0; i < close_steps; ++i) step(s.without_gravity, d);
  forward(s.without_gravity, d);
  GripTrial t;
  t.command = commands[0];
  t.closed_force = finger_force(s, d);
  if (closed) *closed = d;
  for (size_t k = 0; read && k < pads.size(); ++k) {
    (*read)[k].closed = d.sensordata[pads[k].adr];
    (*read)[k].servo_closed = servo(d, pads[k]);
  }
  const double before = s.down.dot(d.xipos[s.body]);
  // the free joint's first three velocities are its centre's, in the world frame
  const int dof = s.with_gravity.jnt_dofadr[s.free_joint];
  double speed_half = 0;
  int counted = 0;
  for (int i = 0; i < hold_steps; ++i) {
    step(s.with_gravity, d);
    if (i + 1 == hold_steps / 2) speed_half = s.down.dot(d.qvel.segment<3>(dof));
    // the force is judged while the slip is: the fingers' force over the second half
    if (i + 1 > hold_steps / 2) {
      t.force += finger_force(s, d), ++counted;
      for (size_t k = 0; read && k < pads.size(); ++k) {
        (*read)[k].held += d.sensordata[pads[k].adr];
        (*read)[k].servo_held += servo(d, pads[k]);
      }
    }
  }
  t.force /= std::max(1, counted);
  for (size_t k = 0; read && k < pads.size(); ++k) {
    (*read)[k].held /= std::max(1, counted);
    (*read)[k].servo_held /= std::max(1, counted);
  }
  forward(s.with_gravity, d);
  tally(s.with_gravity, d, table, strays);
  t.drop = s.down.dot(d.xipos[s.body]) - before;
  t.speedup = s.down.dot(d.qvel.segment<3>(dof)) - speed_half;
  t.slipped = t.speedup > g.speedup_threshold || t.drop > g.fall || spoiling_warnings(d) > 0;
  return t;
}

// the commands that ask each finger's servo for `force` once it holds the box
std::vector<double> commands_for(const GripSetup& s, double force) {
  std::vector<double> c;
  for (size_t i = 0; i < s.fingers.size(); ++i)
    c.push_back(s.touch[i] + s.fingers[i].closing * force / s.fingers[i].kp);
  return c;
}

Grip grip(const Model& m, PairTable& table, std::vector<std::string>& strays) {
  Grip g;
  // the free body and the servos whose bodies carry geoms that can touch it: the fingers
  const std::vector<int> weld = weld_bodies(m);
  int body = -1;
  std::vector<Finger> fingers;
  for (int b = 1; b < m.nbody && body < 0; ++b) {
    if (free_joint_of(m, b) < 0) continue;
    std::vector<Finger> found;
    for (int a = 0; a < m.nu; ++a) {
      if (actuator_scalar_dof(m, a) < 0) continue;
      const int j = m.actuator_trnid[a][0];
      if (!is_servo(m.actuator_kind[a]) || m.jnt_type[j] == JointType::kFree ||
          m.jnt_type[j] == JointType::kBall)
        continue;
      Finger f{a, j, {}, 1.0, 0.0};
      for (size_t k = 0; k < table.geoms.size(); ++k) {
        for (int side = 0; side < 2; ++side) {
          const int mine = table.geoms[k][side], theirs = table.geoms[k][1 - side];
          if (m.geom_bodyid[theirs] == b && weld[m.geom_bodyid[mine]] == m.jnt_bodyid[j])
            f.geoms.push_back(mine);
        }
      }
      if (!f.geoms.empty()) found.push_back(f);
    }
    if (found.size() == 2) body = b, fingers = found;
  }
  if (body < 0) {
    g.skipped =
        "no free body with exactly two servo-driven fingers (actuated hinge or slide joints whose "
        "bodies carry geoms that can touch it)";
    return g;
  }
  g.body = body_label(m, body);
  for (const Finger& f : fingers) g.fingers.push_back(motor_label(m, f.actuator));
  g.mass = m.body_subtreemass[body];
  g.gravity = m.opt.gravity.norm();
  g.mu = kInf;
  for (size_t k = 0; k < table.geoms.size(); ++k) {
    const int b1 = m.geom_bodyid[table.geoms[k][0]], b2 = m.geom_bodyid[table.geoms[k][1]];
    for (const Finger& f : fingers) {
      for (int fg : f.geoms) {
        const int fb = m.geom_bodyid[fg];
        if ((b1 == body && b2 == fb) || (b2 == body && b1 == fb))
          g.mu = std::min(g.mu, table.pairs[k].friction[0]);
      }
    }
  }
  g.needed = g.mass * g.gravity / (2 * g.mu);
  if (g.gravity == 0.0) {
    g.skipped = "the model has no gravity: nothing pulls the box out of the grip";
    return g;
  }

  // the start: the box between the fingers (at the mean of their touching geoms), at rest
  GripSetup s{m, m, Data(m), body, free_joint_of(m, body), fingers, {}, m.opt.gravity.normalized()};
  s.without_gravity.opt.gravity.setZero();
  const int free = free_joint_of(m, body);
  start_state(m, s.start);
  s.start.qvel.setZero();
  std::vector<int> finger_actuators;
  for (const Finger& f : fingers) finger_actuators.push_back(f.actuator);
  hold_servos(m, s.start, finger_actuators);
  kinematics(m, s.start);
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  int count = 0;
  for (const Finger& f : fingers)
    for (int geom : f.geoms) centre += s.start.geom_xpos[geom], ++count;
  centre /= count;
  const int adr = m.jnt_qposadr[free];
  // the body's origin moves by what moves its centre of mass there
  s.start.qpos.segment(adr, 3) += centre - s.start.xipos[body];
  kinematics(m, s.start);

  // each finger closes towards the end of its ctrlrange that brings its geoms nearer the box
  for (Finger& f : s.fingers) {
    if (!m.actuator_ctrllimited[f.actuator]) {
      g.skipped = "finger servo " + motor_label(m, f.actuator) + " has no ctrlrange: no full grip";
      return g;
    }
    Data moved = s.start;
    moved.qpos[m.jnt_qposadr[f.joint]] += 1e-4;
    kinematics(m, moved);
    const double gear = m.actuator_gear[f.actuator][0];
    const bool nearer = finger_gap(moved, f, body) < finger_gap(s.start, f, body);
    f.closing = (nearer == (gear > 0)) ? 1.0 : -1.0;
    f.kp = actuator_gain(m, f.actuator, 0.0, 0.0);
    if (!(f.kp > 0)) {
      g.skipped = "finger servo " + motor_label(m, f.actuator) + " has no positive gain";
      return g;
    }
  }
  g.servo_kp = s.fingers[0].kp;

  std::vector<double> full;
  for (const Finger& f : s.fingers) {
    const auto& range = m.actuator_ctrlrange[f.actuator];
    full.push_back(f.closing > 0 ? range[1] : range[0]);
  }
  g.full_command = full[0];
  Data closed(m);
  const std::vector<PadSensor> pads = finger_pads(m, s.fingers, g);
  GripTrial first = run_trial(s, full, g, table, strays, &closed, pads, &g.pads);
  // the hand calculation of the servo's force at the full command: kp x its error, clamped
  g.servo_force = kInf;
  for (const Finger& f : s.fingers) {
    const double length = closed.actuator_length[f.actuator];
    s.touch.push_back(length);
    double force = f.kp * std::abs(full[&f - s.fingers.data()] - length);
    if (m.actuator_forcelimited[f.actuator]) {
      const auto& range = m.actuator_forcerange[f.actuator];
      force = std::min(force, f.closing > 0 ? range[1] : -range[0]);
    }
    g.servo_force = std::min(g.servo_force, force);
  }
  g.touch = s.touch[0];
  g.creep = first.drop;
  g.trials.push_back(first);
  g.servo_force_closed = first.closed_force;
  if (first.slipped) {
    g.slip_force = first.force;
    return g;
  }
  g.hold_force = first.force;
  // the force asked of the servos (kp x the command's offset from where the full grip held the
  // box) steers the search; the force they push with once closed is what is reported
  double asked_hold = first.closed_force, asked_slip = 0.0;
  const auto record = [&](double asked) {
    const GripTrial t = run_trial(s, commands_for(s, asked), g, table, strays);
    g.trials.push_back(t);
    if (t.slipped) {
      asked_slip = asked;
      g.slip_force = t.force;
    } else {
      asked_hold = asked;
      g.hold_force = t.force;
    }
  };
  // lower the grip by steps of 30 % until the box slips, then bisect between hold and slip
  for (int i = 0; i < 40 && asked_slip == 0.0; ++i) record(0.7 * asked_hold);
  for (int i = 0; i < 30 && asked_slip > 0 && g.hold_force - g.slip_force > g.resolution * g.needed;
       ++i) {
    record(0.5 * (asked_hold + asked_slip));
  }
  return g;
}

}  // namespace

Contacts check_contacts(const Model& model) {
  Contacts c;
  if (model.opt.disabled(kDisableContact) || model.opt.disabled(kDisableConstraint)) {
    c.skipped = "contacts are disabled (<flag contact=\"disable\">)";
    return c;
  }
  PairTable table = touching_pairs(model);
  if (table.pairs.empty()) {
    c.skipped = "no two geoms can touch";
    return c;
  }
  std::vector<std::string> strays;
  // a simulation the engine refuses (more contacts than nconmax) skips that part, saying why
  try {
    c.rest = resting_depth(model, table, strays);
  } catch (const Error& e) {
    c.rest = RestingDepth{};
    c.rest.skipped = std::string("the simulation failed: ") + e.what();
  }
  try {
    c.grip = grip(model, table, strays);
  } catch (const Error& e) {
    c.grip = Grip{};
    c.grip.skipped = std::string("the simulation failed: ") + e.what();
  }
  c.pairs = table.pairs;
  c.strays = strays;
  return c;
}

}  // namespace lever::check
