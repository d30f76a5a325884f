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
    m.body_name.push_back("body" + std::to_string(b));
    m.body_parentid.push_back(parent);
    m.body_rootid.push_back(parent == 0 ? b : m.body_rootid[parent]);
    m.body_mocapid.push_back(-1);
    // a welded body one time in five; the first body always moves, so that nv >= 1
    const int joints =
        (b > 1 && chance(rng, 0.2)) ? 0 : std::uniform_int_distribution<int>(1, 3)(rng);
    m.body_jntnum.push_back(joints);
    m.body_jntadr.push_back(joints ? m.njnt : -1);
    m.body_dofnum.push_back(joints);
    m.body_dofadr.push_back(joints ? m.nv : -1);
    m.body_geomnum.push_back(0);
    m.body_geomadr.push_back(-1);
    m.body_pos.push_back(vector_in(rng, 0.5));
    m.body_quat.push_back(random_quat(rng));
    m.body_ipos.push_back(vector_in(rng, 0.2));
    m.body_iquat.push_back(random_quat(rng));
    const double mass = uniform(rng, 0.2, 2.0);
    m.body_mass.push_back(mass);
    // principal moments from the second moments of a mass distribution (x2, y2, z2 >= 0):
    // Ixx = y2 + z2 and so on, which satisfy the triangle inequality by construction
    const Eigen::Vector3d second =
        mass * Eigen::Vector3d(uniform(rng, 0.001, 0.05), uniform(rng, 0.001, 0.05),
                               uniform(rng, 0.001, 0.05));
    m.body_inertia.push_back(
        {second.y() + second.z(), second.x() + second.z(), second.x() + second.y()});
    m.body_explicit_inertial.push_back(1);
    m.body_line.push_back(0);

    // the dof this body's first dof hangs from: the last dof on the path to the world
    int parent_dof = -1;
    for (int a = parent; a > 0 && parent_dof < 0; a = m.body_parentid[a]) {
      if (m.body_dofnum[a] > 0) parent_dof = m.body_dofadr[a] + m.body_dofnum[a] - 1;
    }
    for (int k = 0; k < joints; ++k) {
      const int j = m.njnt;
      m.jnt_name.push_back("joint" + std::to_string(j));
      m.jnt_type.push_back(chance(rng, 0.7) ? JointType::kHinge : JointType::kSlide);
      m.jnt_qposadr.push_back(j);
      m.jnt_dofadr.push_back(j);
      m.jnt_bodyid.push_back(b);
      m.jnt_limited.push_back(0);
      m.jnt_solref.push_back({0.02, 1.0});
      m.jnt_solimp.push_back({0.9, 0.95, 0.001, 0.5, 2.0});
      m.jnt_pos.push_back(chance(rng, 0.25) ? Eigen::Vector3d::Zero() : vector_in(rng, 0.2));
      m.jnt_axis.push_back(random_axis(rng));
      // a joint spring one time in three
      m.jnt_stiffness.push_back(chance(rng, 1.0 / 3.0) ? uniform(rng, 0.1, 5.0) : 0.0);
      m.jnt_range.push_back({0.0, 0.0});
      m.jnt_margin.push_back(0.0);
      m.dof_bodyid.push_back(b);
      m.dof_jntid.push_back(j);
      m.dof_parentid.push_back(k == 0 ? parent_dof : j - 1);
      m.dof_armature.push_back(chance(rng, 0.5) ? uniform(rng, 0.001, 0.1) : 0.0);
      m.dof_damping.push_back(chance(rng, 0.5) ? uniform(rng, 0.01, 1.0) : 0.0);
      m.dof_frictionloss.push_back(0.0);  // no friction-loss rows: the trees test the smooth terms
      m.dof_solref.push_back({0.02, 1.0});
      m.dof_solimp.push_back({0.9, 0.95, 0.001, 0.5, 2.0});
      ++m.njnt;
      ++m.nv;
    }
    m.site_name.push_back("site" + std::to_string(b));
    m.site_bodyid.push_back(b);
    m.site_pos.push_back(vector_in(rng, 0.3));
    m.site_quat.push_back(random_quat(rng));
    m.site_size.push_back(Eigen::Vector3d::Constant(0.01));
    m.site_type.push_back(GeomType::kSphere);
  }
  m.nbody = bodies + 1;
  m.nsite = bodies;
  m.nq = m.nv;
  m.qpos0 = Eigen::VectorXd::Zero(m.nq);
  m.qpos_spring = Eigen::VectorXd::Zero(m.nq);
  for (int j = 0; j < m.njnt; ++j) {
    if (m.jnt_stiffness[j] > 0) m.qpos_spring[j] = uniform(rng, -0.5, 0.5);
  }
  m.key_qpos.resize(0, m.nq);
  m.key_qvel.resize(0, m.nv);
  m.key_ctrl.resize(0, m.nu);
  set_const(m);
  return m;
}

}  // namespace lever::test
