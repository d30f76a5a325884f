// Random kinematic trees written as MJCF, so that lever's loader and MuJoCo 2.2.2 compile the same
// tree (after RigidBodyDynamics.jl's rand_tree_mechanism, as random_tree.hpp, which builds
// hinge-and-slide trees in memory). Every body hangs from a random earlier body; a body on the
// world is free one time in three; any other body carries a ball joint one time in four, else
// 0 to 3 hinges and slides about random axes (a third of them exactly along a coordinate axis) at
// random anchors. Inertias are a random mass times random second moments (x2, y2, z2 >= 0), whose
// principal moments y2 + z2, x2 + z2, x2 + y2 satisfy the triangle inequality, in a random frame.
// Everything is drawn from one seed, so a seed alone rebuilds a tree.
#pragma once

#include <cstdint>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace lever::test {

namespace random_tree_mjcf_detail {

struct Joint {
  std::string type;  // "hinge", "slide", "ball", "free"
  double pos[3] = {0, 0, 0};
  double axis[3] = {0, 0, 1};
  double damping = 0, armature = 0;
};

struct Body {
  int parent = 0;
  double pos[3] = {0, 0, 0};
  double quat[4] = {1, 0, 0, 0};
  double ipos[3] = {0, 0, 0};
  double iquat[4] = {1, 0, 0, 0};
  double mass = 1;
  double inertia[3] = {0, 0, 0};
  std::vector<Joint> joints;
  double site[3] = {0, 0, 0};
};

inline double uniform(std::mt19937_64& rng, double lo, double hi) {
  return std::uniform_real_distribution<double>(lo, hi)(rng);
}

inline bool chance(std::mt19937_64& rng, double p) { return uniform(rng, 0, 1) < p; }

inline void vector_in(std::mt19937_64& rng, double half_width, double* v) {
  for (int i = 0; i < 3; ++i) v[i] = uniform(rng, -half_width, half_width);
}

// a random direction (written unnormalized: both compilers normalize it); a third of the time
// exactly +-x, +-y or +-z
inline void random_axis(std::mt19937_64& rng, double* axis) {
  if (chance(rng, 1.0 / 3.0)) {
    axis[0] = axis[1] = axis[2] = 0;
    axis[std::uniform_int_distribution<int>(0, 2)(rng)] = chance(rng, 0.5) ? 1.0 : -1.0;
    return;
  }
  std::normal_distribution<double> normal;
  double norm = 0;
  do {
    for (int i = 0; i < 3; ++i) axis[i] = normal(rng);
    norm = axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2];
  } while (norm < 1e-2);
}

// a random rotation (unnormalized, as a user writes one); a quarter of the time the identity
inline void random_quat(std::mt19937_64& rng, double* q) {
  q[0] = 1;
  q[1] = q[2] = q[3] = 0;
  if (chance(rng, 0.25)) return;
  std::normal_distribution<double> normal;
  double norm = 0;
  do {
    for (int i = 0; i < 4; ++i) q[i] = normal(rng);
    norm = q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3];
  } while (norm < 1e-2);
}

inline std::string numbers(const double* x, int n) {
  std::ostringstream out;
  out.precision(17);
  for (int i = 0; i < n; ++i) out << (i ? " " : "") << x[i];
  return out.str();
}

inline void write_body(std::ostringstream& xml, const std::vector<Body>& bodies, int b, int depth) {
  const std::string indent(static_cast<std::size_t>(2 * depth), ' ');
  const Body& body = bodies[static_cast<std::size_t>(b)];
  xml << indent << "<body name=\"body" << b << "\" pos=\"" << numbers(body.pos, 3) << "\" quat=\""
      << numbers(body.quat, 4) << "\">\n";
  xml << indent << "  <inertial pos=\"" << numbers(body.ipos, 3) << "\" quat=\""
      << numbers(body.iquat, 4) << "\" mass=\"" << numbers(&body.mass, 1) << "\" diaginertia=\""
      << numbers(body.inertia, 3) << "\"/>\n";
  for (const Joint& j : body.joints) {
    if (j.type == "free") {
      xml << indent << "  <freejoint/>\n";
      continue;
    }
    xml << indent << "  <joint type=\"" << j.type << "\" pos=\"" << numbers(j.pos, 3) << "\"";
    if (j.type != "ball") xml << " axis=\"" << numbers(j.axis, 3) << "\"";
    xml << " damping=\"" << numbers(&j.damping, 1) << "\" armature=\"" << numbers(&j.armature, 1)
        << "\"/>\n";
  }
  xml << indent << "  <site name=\"site" << b << "\" pos=\"" << numbers(body.site, 3)
      << "\" size=\"0.01\"/>\n";
  for (std::size_t c = 1; c < bodies.size(); ++c) {
    if (bodies[c].parent == b) write_body(xml, bodies, static_cast<int>(c), depth + 1);
  }
  xml << indent << "</body>\n";
}

}  // namespace random_tree_mjcf_detail

/// Largest number of bodies (world excluded) random_tree_mjcf draws.
constexpr int kRandomTreeMjcfMaxBodies = 8;

/// The MJCF text of a random tree of 1 to kRandomTreeMjcfMaxBodies bodies with at least one dof,
/// drawn from seed. No geoms (so no contacts), no limits, no actuators; gravity on; angles in
/// radians; one site per body.
inline std::string random_tree_mjcf(std::uint64_t seed) {
  using namespace random_tree_mjcf_detail;
  std::mt19937_64 rng(seed);
  const int count = std::uniform_int_distribution<int>(1, kRandomTreeMjcfMaxBodies)(rng);
  std::vector<Body> bodies(static_cast<std::size_t>(count) + 1);
  for (int b = 1; b <= count; ++b) {
    Body& body = bodies[static_cast<std::size_t>(b)];
    body.parent = std::uniform_int_distribution<int>(0, b - 1)(rng);
    vector_in(rng, 0.5, body.pos);
    random_quat(rng, body.quat);
    vector_in(rng, 0.2, body.ipos);
    random_quat(rng, body.iquat);
    body.mass = uniform(rng, 0.2, 2.0);
    const double second[3] = {body.mass * uniform(rng, 0.001, 0.05),
                              body.mass * uniform(rng, 0.001, 0.05),
                              body.mass * uniform(rng, 0.001, 0.05)};
    body.inertia[0] = second[1] + second[2];
    body.inertia[1] = second[0] + second[2];
    body.inertia[2] = second[0] + second[1];
    vector_in(rng, 0.3, body.site);
    const auto with_damping = [&](Joint j) {
      j.damping = chance(rng, 0.5) ? uniform(rng, 0.01, 1.0) : 0.0;
      j.armature = chance(rng, 0.5) ? uniform(rng, 0.001, 0.1) : 0.0;
      return j;
    };
    if (body.parent == 0 && chance(rng, 1.0 / 3.0)) {
      body.joints.push_back(Joint{"free"});
    } else if (chance(rng, 0.25)) {
      Joint ball{"ball"};
      if (!chance(rng, 0.25)) vector_in(rng, 0.2, ball.pos);
      body.joints.push_back(with_damping(ball));
    } else {
      // a welded body one time in five; the first body always moves, so that nv >= 1
      const int joints =
          (b > 1 && chance(rng, 0.2)) ? 0 : std::uniform_int_distribution<int>(1, 3)(rng);
      for (int k = 0; k < joints; ++k) {
        Joint j{chance(rng, 0.7) ? "hinge" : "slide"};
        if (!chance(rng, 0.25)) vector_in(rng, 0.2, j.pos);
        random_axis(rng, j.axis);
        body.joints.push_back(with_damping(j));
      }
    }
  }
  std::ostringstream xml;
  xml << "<mujoco model=\"random tree " << seed << "\">\n"
      << "  <compiler angle=\"radian\"/>\n"
      << "  <worldbody>\n";
  for (int b = 1; b <= count; ++b) {
    if (bodies[static_cast<std::size_t>(b)].parent == 0) write_body(xml, bodies, b, 2);
  }
  xml << "  </worldbody>\n</mujoco>\n";
  return xml.str();
}

}  // namespace lever::test
