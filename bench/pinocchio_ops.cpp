#include "pinocchio_ops.hpp"

#include <algorithm>

namespace lever::bench {

#ifdef LEVER_BENCH_PINOCCHIO_VERSION
bool have_pinocchio() { return true; }
std::string pinocchio_peer_version() { return pinocchio_version(); }
#else
bool have_pinocchio() { return false; }
std::string pinocchio_peer_version() { return ""; }
#endif

Model dynamics_only(const Model& model) {
  Model m = model;
  std::fill(m.dof_damping.begin(), m.dof_damping.end(), 0.0);
  for (auto& gain : m.actuator_gainprm) gain.fill(0);
  for (auto& bias : m.actuator_biasprm) bias.fill(0);
  set_const(m);
  return m;
}

PinocchioRig::PinocchioRig(const Fixture& f, const State& s)
    : model(dynamics_only(f.model)),
      d(model),
      deriv(model),
      jacp(3, model.nv),
      jacr(3, model.nv) {
  d.qpos = s.qpos;
  d.qvel = s.qvel;
  d.qacc = s.qacc;
  d.ctrl = s.ctrl;
  d.qfrc_applied.setConstant(kPeerTorque);
#ifdef LEVER_BENCH_PINOCCHIO_VERSION
  if (f.chain) {
    peer = std::make_unique<PinocchioPeer>(*f.chain);
    const std::vector<double> tau(static_cast<std::size_t>(model.nv), kPeerTorque);
    peer->set_state(s.qpos.data(), s.qvel.data(), s.qacc.data(), tau.data());
  }
#endif
}

PinocchioRig::~PinocchioRig() = default;

// Pinocchio's side of an operation: a call on the peer, where it is built
#ifdef LEVER_BENCH_PINOCCHIO_VERSION
#define LEVER_PEER_CALL(call) [](PinocchioPeer& p) { p.call(); }
#else
#define LEVER_PEER_CALL(call) [](PinocchioPeer&) {}
#endif

const std::vector<PinocchioOperation>& pinocchio_operations() {
  using Op = PinocchioOperation;
  static const std::vector<Op> ops = {
      {"fk_bodies", [](const Fixture&, PinocchioRig& r) { body_poses(r.model, r.d); },
       LEVER_PEER_CALL(forward_kinematics)},
      {"bias_from_q", {}, LEVER_PEER_CALL(nonlinear_effects)},
      {"rnea_from_q", {}, LEVER_PEER_CALL(rnea)},
      {"crba_from_q", {}, LEVER_PEER_CALL(crba)},
      {"jac_site_from_q",
       [](const Fixture& f, PinocchioRig& r) {
         jac_site_from_q(r.model, r.d, f.site, r.jacp, r.jacr);
       },
       LEVER_PEER_CALL(frame_jacobian)},
      {"aba",
       [](const Fixture&, PinocchioRig& r) {
         body_kinematics(r.model, r.d);
         bias(r.model, r.d);
         crba(r.model, r.d);
         factor_mass(r.model, r.d);
         r.d.qacc = r.d.qfrc_applied - r.d.qfrc_bias;
         solve_mass(r.model, r.d, r.d.qacc);
       },
       LEVER_PEER_CALL(aba)},
      {"rnea_derivatives",
       [](const Fixture&, PinocchioRig& r) {
         body_kinematics(r.model, r.d);
         crba(r.model, r.d);
         rnea_derivatives(r.model, r.d, r.d.qacc, r.deriv);
       },
       LEVER_PEER_CALL(rnea_derivatives)},
      {"aba_derivatives",
       [](const Fixture&, PinocchioRig& r) { forward_derivatives(r.model, r.d, r.deriv); },
       LEVER_PEER_CALL(aba_derivatives)},
  };
  return ops;
}

void run_pinocchio(const PinocchioOperation& op, PinocchioRig& rig) { op.pinocchio(*rig.peer); }

}  // namespace lever::bench
