// Random kinematic trees built in memory, for the property tests (after RigidBodyDynamics.jl's
// rand_tree_mechanism): every body hangs from a random earlier body (so trees branch), carries
// 0 to 3 hinge or slide joints about random axes (exactly axis-aligned ones, which set_const
// gives kernels of their own, and general ones) at random anchors, and a random rigid-body
// inertia. The arrays are filled as lever::mjcf's compiler fills them, then set_const derives
// the rest. Everything is drawn from one seed, so a seed alone rebuilds a tree.
#pragma once

#include <Eigen/Core>

#include <cmath>
#include <cstdint>
#include <random>
#include <string>

#include <lever/lever.hpp>

namespace lever::test {

namespace random_tree_detail {

inline double uniform(std::mt19937_64& rng, double lo, double hi) {
  return std::uniform_real_distribution<double>(lo, hi)(rng);
}

inline bool chance(std::mt19937_64& rng, double p) { return uniform(rng, 0, 1) < p; }

inline Eigen::Vector3d vector_in(std::mt19937_64& rng, double half_width) {
  return {uniform(rng, -half_width, half_width), uniform(rng, -half_width, half_width),
          uniform(rng, -half_width, half_width)};
}

// A random unit vector; a third of the time exactly +-x, +-y or +-z.
inline Eigen::Vector3d random_axis(std::mt19937_64& rng) {
  if (chance(rng, 1.0 / 3.0)) {
    Eigen::Vector3d axis = Eigen::Vector3d::Zero();
    axis[std::uniform_int_distribution<int>(0, 2)(rng)] = chance(rng, 0.5) ? 1.0 : -1.0;
    return axis;
  }
  std::normal_distribution<double> normal;
  Eigen::Vector3d axis;
  do {
    axis = {normal(rng), normal(rng), normal(rng)};
  } while (axis.norm() < 1e-3);
  return axis.normalized();
}

// A random unit quaternion (w, x, y, z); a quarter of the time the identity, so that the
// kernels' unrotated paths run too.
inline Eigen::Vector4d random_quat(std::mt19937_64& rng) {
  if (chance(rng, 0.25)) return {1, 0, 0, 0};
  std::normal_distribution<double> normal;
  Eigen::Vector4d q;
  do {
    q = {normal(rng), normal(rng), normal(rng), normal(rng)};
  } while (q.norm() < 1e-3);
  return q.normalized();
}

}  // namespace random_tree_detail

/// Largest number of bodies (world excluded) random_tree draws.
constexpr int kRandomTreeMaxBodies = 12;

/// A random tree of 1 to kRandomTreeMaxBodies bodies, with at least one dof, drawn from seed.
/// No joint limits (limit rows are exercised by the model files) and no actuators; one site per
/// body, at a random point, for the Jacobian properties.
inline Model random_tree(std::uint64_t seed) {
  using namespace random_tree_detail;
  std::mt19937_64 rng(seed);
  Model m;
  m.name = "random tree " + std::to_string(seed);
  const int bodies = std::uniform_int_distribution<int>(1, kRandomTreeMaxBodies)(rng);
  for (int b = 1; b <= bodies; ++b) {
    const int parent = std::uniform_int_distribution<int>(0, b - 1)(rng);
    // a welded body one time in five; the first body always moves, so that nv >= 1
    const int joints =
        (b > 1 && chance(rng, 0.2)) ? 0 : std::uniform_int_distribution<int>(1, 3)(rng);
    // this body, its joints (one dof each) and its site counted, the arrays sized, then written
    const int first_joint = m.njnt;
    m.nbody = b + 1;
    m.njnt += joints;
    m.nv += joints;
    m.nq = m.nv;
    m.nsite = b;
    size_model(m);
    m.body_name[b] = "body" + std::to_string(b);
    m.body_parentid[b] = parent;
    m.body_rootid[b] = parent == 0 ? b : m.body_rootid[parent];
    m.body_jntnum[b] = joints;
    m.body_jntadr[b] = joints ? first_joint : -1;
    m.body_dofnum[b] = joints;
    m.body_dofadr[b] = joints ? first_joint : -1;
    m.body_geomnum[b] = 0;
    m.body_geomadr[b] = -1;
    m.body_pos[b] = vector_in(rng, 0.5);
    m.body_quat[b] = random_quat(rng);
    m.body_ipos[b] = vector_in(rng, 0.2);
    m.body_iquat[b] = random_quat(rng);
    const double mass = uniform(rng, 0.2, 2.0);
    m.body_mass[b] = mass;
    // principal moments from the second moments of a mass distribution (x2, y2, z2 >= 0):
    // Ixx = y2 + z2 and so on, which satisfy the triangle inequality by construction
    const Eigen::Vector3d second =
        mass * Eigen::Vector3d(uniform(rng, 0.001, 0.05), uniform(rng, 0.001, 0.05),
                               uniform(rng, 0.001, 0.05));
    m.body_inertia[b] = {second.y() + second.z(), second.x() + second.z(), second.x() + second.y()};
    m.body_explicit_inertial[b] = 1;

    // the dof this body's first dof hangs from: the last dof on the path to the world
    int parent_dof = -1;
    for (int a = parent; a > 0 && parent_dof < 0; a = m.body_parentid[a]) {
      if (m.body_dofnum[a] > 0) parent_dof = m.body_dofadr[a] + m.body_dofnum[a] - 1;
    }
    for (int k = 0; k < joints; ++k) {
      const int j = first_joint + k;
      m.jnt_name[j] = "joint" + std::to_string(j);
      m.jnt_type[j] = chance(rng, 0.7) ? JointType::kHinge : JointType::kSlide;
      m.jnt_qposadr[j] = j;
      m.jnt_dofadr[j] = j;
      m.jnt_bodyid[j] = b;
      m.jnt_solref[j] = {0.02, 1.0};
      m.jnt_solimp[j] = {0.9, 0.95, 0.001, 0.5, 2.0};
      m.jnt_pos[j] = chance(rng, 0.25) ? Eigen::Vector3d::Zero() : vector_in(rng, 0.2);
      m.jnt_axis[j] = random_axis(rng);
      // a joint spring one time in three
      m.jnt_stiffness[j] = chance(rng, 1.0 / 3.0) ? uniform(rng, 0.1, 5.0) : 0.0;
      m.dof_bodyid[j] = b;
      m.dof_jntid[j] = j;
      m.dof_parentid[j] = k == 0 ? parent_dof : j - 1;
      m.dof_armature[j] = chance(rng, 0.5) ? uniform(rng, 0.001, 0.1) : 0.0;
      m.dof_damping[j] = chance(rng, 0.5) ? uniform(rng, 0.01, 1.0) : 0.0;
      // no limits and no friction-loss rows (left zero): the trees test the smooth terms
      m.dof_solref[j] = {0.02, 1.0};
      m.dof_solimp[j] = {0.9, 0.95, 0.001, 0.5, 2.0};
    }
    const int s = b - 1;
    m.site_name[s] = "site" + std::to_string(b);
    m.site_bodyid[s] = b;
    m.site_pos[s] = vector_in(rng, 0.3);
    m.site_quat[s] = random_quat(rng);
    m.site_size[s] = Eigen::Vector3d::Constant(0.01);
    m.site_type[s] = GeomType::kSphere;
  }
  for (int j = 0; j < m.njnt; ++j) {
    if (m.jnt_stiffness[j] > 0) m.qpos_spring[j] = uniform(rng, -0.5, 0.5);
  }
  set_const(m);
  return m;
}

}  // namespace lever::test
