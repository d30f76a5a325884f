// The Pinocchio peer: the fixture's serial chain (the KDL peer's ChainSpec) as a pinocchio::Model,
// and Pinocchio's algorithms on it.
//
// The model is built, not parsed: Pinocchio's MJCF parser (libpinocchio_parsers) includes
// urdfdom's headers, which pip's wheels do not ship. Every joint gets its own frame turned so that
// its axis is that frame's z (a revolute joint is JointModelRZ, a prismatic one JointModelPZ):
// Pinocchio's fastest joint types, what a URDF with z axes gives it.
//
// Like the KDL peer, this header mentions neither Eigen nor lever: pinocchio_peer.cpp, the only
// file that includes Pinocchio's headers, shares Eigen objects with the prebuilt libraries of pip's
// `pin` wheel and is compiled with their Eigen alignment (EIGEN_MAX_ALIGN_BYTES=16). Nothing with
// an Eigen member crosses this interface. Built only when CMake found Pinocchio
// (LEVER_BENCH_PINOCCHIO, bench/CMakeLists.txt).
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "kdl_peer.hpp"  // ChainSpec

namespace lever::bench {

/// Pinocchio's version, "4.1.0".
std::string pinocchio_version();

/// Pinocchio's algorithms on one model, with their inputs and outputs (sized once, here).
class PinocchioPeer {
 public:
  /// The chain's joints, bodies and tip frame (the frame of the Jacobian). Pinocchio's q is
  /// lever's qpos minus the links' offsets (qpos0), which set_state subtracts.
  explicit PinocchioPeer(const ChainSpec& spec);
  ~PinocchioPeer();
  PinocchioPeer(const PinocchioPeer&) = delete;
  PinocchioPeer& operator=(const PinocchioPeer&) = delete;

  int nq() const;
  int nv() const;

  /// lever's qpos, qvel, a joint acceleration and torque (nv each: a chain) for the calls below.
  void set_state(const double* q, const double* v, const double* a, const double* tau);

  // The operations timed, each from the state (Pinocchio's algorithms start from q).
  void rnea();                 ///< pinocchio::rnea: M a + C v + g (armature in M)
  void nonlinear_effects();    ///< pinocchio::nonLinearEffects: C v + g
  void crba();                 ///< pinocchio::crba: M (upper triangle; world convention)
  void aba();                  ///< pinocchio::aba: a from tau
  void forward_kinematics();   ///< pinocchio::forwardKinematics: every joint's placement
  void frame_jacobian();       ///< pinocchio::computeFrameJacobian, LOCAL_WORLD_ALIGNED
  void rnea_derivatives();     ///< pinocchio::computeRNEADerivatives: d tau / d q, d v; M
  void aba_derivatives();      ///< pinocchio::computeABADerivatives: d a / d q, d v; M^-1

  // Results of the last calls (copied out; for the correctness check, not for timing).
  std::vector<double> tau() const;           ///< rnea
  std::vector<double> bias() const;          ///< nonlinear_effects
  std::vector<double> mass_matrix() const;   ///< crba or rnea_derivatives: nv x nv row-major, whole
  std::vector<double> acceleration() const;  ///< aba
  std::vector<double> jacobian() const;      ///< 6 x nv row-major: rows vx vy vz wx wy wz (world)
  std::array<double, 12> frame_placement() const;  ///< after frame_jacobian: position, rotation row-major
  /// rnea_derivatives: d tau / d q, d tau / d v; aba_derivatives: d a / d q, d a / d v (nv x nv
  /// row-major each)
  std::vector<double> dtau_dq() const, dtau_dv() const, dacc_dq() const, dacc_dv() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace lever::bench
