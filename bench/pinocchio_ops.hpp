// The operations timed against Pinocchio, lever's side and Pinocchio's, in one table that the
// benchmarks (bench/benchmarks.cpp), the instruction counts (bench/profile.cpp) and the checks
// (bench/check.cpp) share. Every operation starts from the state (q, v, a or tau), as Pinocchio's
// algorithms do, and each side computes the same outputs (what neither reads is not computed:
// lever's body_kinematics is kinematics without the geom and site frames).
//
//   fk_bodies          forwardKinematics: each joint's placement
//                                                      (lever: body_poses, each body's frame)
//   bias_from_q        nonLinearEffects                (lever: body_kinematics, bias)
//   rnea_from_q        rnea                            (lever: body_kinematics, rnea)
//   crba_from_q        crba                            (lever: body_kinematics, crba)
//   jac_site_from_q    computeFrameJacobian, world axes, and the frame's placement
//                                                      (lever: jac_site_from_q, the site's frame
//                                                       and Jacobian)
//   aba                aba: a from tau                 (lever: body_kinematics, bias, crba,
//                                                       factor_mass, solve_mass; lever has no ABA)
//   rnea_derivatives   computeRNEADerivatives: d tau / d q, d v, and M
//                                                      (lever: body_kinematics, crba,
//                                                       rnea_derivatives)
//   aba_derivatives    computeABADerivatives: d a / d q, d v, and M^-1
//                                                      (lever: forward_derivatives with tau as
//                                                       qfrc_applied, on the model without its
//                                                       damping and actuator forces: the same
//                                                       quantity; lever keeps M's factor, not M^-1)
// bias_from_q, rnea_from_q and crba_from_q's lever side is benchmarks.cpp's own (the rows MuJoCo
// and KDL are timed against too); the others' is here.
#pragma once

#include <lever/derivatives.hpp>
#include <lever/lever.hpp>

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "fixture.hpp"

#ifdef LEVER_BENCH_PINOCCHIO_VERSION
#include "pinocchio_peer.hpp"
#else
namespace lever::bench {
class PinocchioPeer {};  // not built: no Pinocchio (bench/CMakeLists.txt)
}
#endif

namespace lever::bench {

/// Whether this build has the Pinocchio peer, and its version ("" without it).
bool have_pinocchio();
std::string pinocchio_peer_version();

/// The joint torque every peer's aba and aba_derivatives get: 0.5 on every dof, as KDL's forward.
constexpr double kPeerTorque = 0.5;

/// The model lever's aba_derivatives runs on: the fixture's, without joint damping and with every
/// actuator's gain and bias zero, so that qacc = M^-1 (qfrc_applied - bias) as in Pinocchio's aba.
Model dynamics_only(const Model& model);

/// Everything one operation runs on, fresh from a state.
struct PinocchioRig {
  PinocchioRig(const Fixture& f, const State& s);
  ~PinocchioRig();
  Model model;   ///< dynamics_only(f.model)
  Data d;        ///< holds the state; qfrc_applied = kPeerTorque
  Derivatives deriv;
  Eigen::MatrixXd jacp, jacr;
  std::unique_ptr<PinocchioPeer> peer;  ///< null without Pinocchio or without a serial chain
};

struct PinocchioOperation {
  std::string name;
  /// lever's side, or empty where benchmarks.cpp times it already
  std::function<void(const Fixture&, PinocchioRig&)> lever;
  std::function<void(PinocchioPeer&)> pinocchio;
};

/// The table above.
const std::vector<PinocchioOperation>& pinocchio_operations();

/// Run one of the table's operations on Pinocchio (a rig with a peer).
void run_pinocchio(const PinocchioOperation& op, PinocchioRig& rig);

}  // namespace lever::bench
