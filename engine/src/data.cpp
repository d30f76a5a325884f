// Data: sized once from the Model, so that evaluating and stepping never allocate.
#include <lever/data.hpp>

namespace lever {

const char* warning_name(Warning w) {
  switch (w) {
    case Warning::kInertia: return "mass matrix is too close to singular";
    case Warning::kBadQpos: return "qpos is NaN or larger than 1e10 (step resets the state)";
    case Warning::kBadQvel: return "qvel is NaN or larger than 1e10 (step resets the state)";
    case Warning::kBadQacc: return "qacc is NaN or larger than 1e10 (step resets the state)";
    case Warning::kBadCtrl: return "ctrl is NaN or larger than 1e10: controls set to zero";
    case Warning::kBadQfrcApplied: return "qfrc_applied is NaN or larger than 1e10";
    case Warning::kCount: break;
  }
  return "unknown warning";
}

Data::Data(const Model& model)
    : qpos(model.qpos0), nefc_max(2 * model.njnt), nq(model.nq), nv(model.nv), nu(model.nu) {
  const int nbody = model.nbody;
  const int nsite = model.nsite;

  qvel = Eigen::VectorXd::Zero(nv);
  ctrl = Eigen::VectorXd::Zero(nu);
  qfrc_applied = Eigen::VectorXd::Zero(nv);

  xpos.assign(nbody, Eigen::Vector3d::Zero());
  xquat.assign(nbody, Eigen::Vector4d(1, 0, 0, 0));
  xmat.assign(nbody, Eigen::Matrix3d::Identity());
  xipos.assign(nbody, Eigen::Vector3d::Zero());
  ximat.assign(nbody, Eigen::Matrix3d::Identity());
  site_xpos.assign(nsite, Eigen::Vector3d::Zero());
  site_xmat.assign(nsite, Eigen::Matrix3d::Identity());
  xanchor.assign(model.njnt, Eigen::Vector3d::Zero());
  xaxis.assign(model.njnt, Eigen::Vector3d::Zero());
  subtree_com.assign(nbody, Eigen::Vector3d::Zero());
  cdof.assign(nv, Motion::Zero());
  cinert.assign(nbody, RigidInertia{});
  cvel.assign(nbody, Motion::Zero());
  cdof_dot.assign(nv, Motion::Zero());

  M = Eigen::MatrixXd::Zero(nv, nv);
  qLD = Eigen::MatrixXd::Zero(nv, nv);
  qLDiagInv = Eigen::VectorXd::Zero(nv);
  actuator_length = Eigen::VectorXd::Zero(nu);

  // Limit rows: sized for the most rows the model can have; nefc says how many are live.
  efc_id.assign(nefc_max, -1);
  efc_dof.assign(nefc_max, -1);
  efc_sign.assign(nefc_max, 0.0);
  for (Eigen::VectorXd* v : {&efc_pos, &efc_margin, &efc_diagApprox, &efc_R, &efc_D, &efc_imp,
                             &efc_K, &efc_B, &efc_vel, &efc_aref, &efc_b, &efc_force}) {
    *v = Eigen::VectorXd::Zero(nefc_max);
  }
  efc_state.assign(nefc_max, ConstraintState::kSatisfied);

  actuator_velocity = Eigen::VectorXd::Zero(nu);
  actuator_force = Eigen::VectorXd::Zero(nu);
  for (Eigen::VectorXd* v : {&qfrc_passive, &qfrc_bias, &qfrc_actuator, &qfrc_smooth, &qacc_smooth,
                             &qfrc_constraint, &qacc, &qfrc_inverse}) {
    *v = Eigen::VectorXd::Zero(nv);
  }

  work.crb.assign(nbody, RigidInertia{});
  work.cacc.assign(nbody, Motion::Zero());
  work.cfrc.assign(nbody, Force::Zero());
  work.LD2 = Eigen::MatrixXd::Zero(nv, nv);
  work.LD2DiagInv = Eigen::VectorXd::Zero(nv);
  work.vec1 = work.vec2 = work.vec3 = Eigen::VectorXd::Zero(nv);
  work.MinvJ = Eigen::MatrixXd::Zero(nv, nefc_max);
  work.A = Eigen::MatrixXd::Zero(nefc_max, nefc_max);
  work.L = Eigen::MatrixXd::Zero(nefc_max, nefc_max);
  work.lcp_f = work.lcp_w = Eigen::VectorXd::Zero(nefc_max);
  work.lcp_active.assign(nefc_max, 0);
  work.lcp_index.assign(nefc_max, 0);
  work.rk_qpos0 = work.rk_dq = Eigen::VectorXd::Zero(nq);
  work.rk_qvel0 = work.rk_dv = Eigen::VectorXd::Zero(nv);
  for (int i = 0; i < 4; ++i) {
    work.rk_qvel[i] = Eigen::VectorXd::Zero(nv);
    work.rk_qacc[i] = Eigen::VectorXd::Zero(nv);
  }
}

int warning_count(const Data& data) {
  int n = 0;
  for (const WarningStat& w : data.warning) n += w.number;
  return n;
}

std::string warning_text(const Data& data) {
  std::string text;
  for (int k = 0; k < static_cast<int>(Warning::kCount); ++k) {
    const WarningStat& w = data.warning[k];
    if (w.number == 0) continue;
    text += std::string(warning_name(static_cast<Warning>(k))) + " (" + std::to_string(w.number) +
            (w.number == 1 ? " time" : " times") + ", last at index " + std::to_string(w.lastinfo) +
            ")\n";
  }
  return text;
}

void reset(const Model& model, Data& data) {
  data.time = 0.0;
  data.qpos = model.qpos0;
  data.qvel.setZero();
  data.ctrl.setZero();
  data.qfrc_applied.setZero();
  data.qacc.setZero();
  data.nefc = 0;
  data.warning = {};
}

}  // namespace lever
