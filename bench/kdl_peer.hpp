// The Orocos KDL peer: a serial chain described with plain numbers, and KDL's solvers on it.
//
// This header deliberately mentions neither Eigen nor lever: kdl_peer.cpp, the only file that
// includes KDL's headers, shares Eigen objects with the prebuilt Debian library and is compiled
// with that library's Eigen alignment (EIGEN_MAX_ALIGN_BYTES=16), whatever flags the rest of
// the benchmark uses. Nothing with an Eigen member crosses this interface.
#pragma once

#include <array>
#include <memory>
#include <vector>

namespace lever::bench {

/// A serial chain, one link per joint, all frames as (position, row-major rotation matrix).
/// Link i's frame: its origin is on joint i's axis; at zero joint displacement (q = offset) it
/// sits at (tree_pos, tree_rot) in link i-1's frame (the world's for link 0), and the joint turns
/// or slides it about / along `axis` (link coordinates) through its own origin.
struct ChainSpec {
  struct Link {
    bool prismatic = false;
    std::array<double, 3> axis{0, 0, 1};  ///< unit, link coordinates
    double offset = 0;                    ///< joint coordinate at zero displacement (qpos0)
    double armature = 0;                  ///< rotor inertia, added to M's diagonal
    std::array<double, 3> tree_pos{};
    std::array<double, 9> tree_rot{1, 0, 0, 0, 1, 0, 0, 0, 1};
    double mass = 0;                      ///< everything rigidly attached to the link
    std::array<double, 3> com{};          ///< link coordinates
    std::array<double, 9> inertia_com{};  ///< about the centre of mass, link axes, row-major
  };
  std::vector<Link> links;
  std::array<double, 3> tip_pos{};  ///< the tip frame (a site) in the last link's frame
  std::array<double, 9> tip_rot{1, 0, 0, 0, 1, 0, 0, 0, 1};
  std::array<double, 3> gravity{0, 0, -9.81};
};

/// KDL's solvers on one chain, with their inputs and outputs (all sized once, here).
class KdlPeer {
 public:
  explicit KdlPeer(const ChainSpec& spec);
  ~KdlPeer();
  KdlPeer(const KdlPeer&) = delete;
  KdlPeer& operator=(const KdlPeer&) = delete;

  int nj() const;

  /// Joint positions, velocities, accelerations and torques (nj each) for the solvers below.
  void set_state(const double* q, const double* qdot, const double* qddot, const double* tau);

  // The operations timed; each returns KDL's error code (0: no error).
  int fk();                ///< ChainFkSolverPos_recursive::JntToCart: the tip frame
  int jacobian();          ///< ChainJntToJacSolver::JntToJac: the tip's 6 x nj Jacobian
  int rne_bias();          ///< ChainIdSolver_RNE::CartToJnt with qddot = 0: C qdot + g
  int rne();               ///< ChainIdSolver_RNE::CartToJnt: M qddot + C qdot + g
  int mass();              ///< ChainDynParam::JntToMass
  int gravity();           ///< ChainDynParam::JntToGravity
  int forward_dynamics();  ///< ChainFdSolver_RNE::CartToJnt: qddot from tau

  // Results of the last calls (copied out; for the correctness check, not for timing).
  std::vector<double> torques() const;          ///< rne_bias, rne or gravity
  std::vector<double> mass_matrix() const;      ///< nj x nj, row-major
  std::vector<double> qddot() const;            ///< forward_dynamics
  std::array<double, 12> tip_frame() const;     ///< position, then the rotation row-major
  std::vector<double> jacobian_matrix() const;  ///< 6 x nj row-major: rows vx vy vz wx wy wz

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace lever::bench
