// Data: sized once from the Model, so that evaluating and stepping never allocate.
#include <lever/data.hpp>

#include <algorithm>

#include "internal.hpp"

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
    : nefc_max(2 * model.njnt),
      nq(model.nq),
      nv(model.nv),
      nu(model.nu),
      nbody(model.nbody),
      njnt(model.njnt),
      ngeom(model.ngeom),
      nsite(model.nsite) {
  // every array of the field table, zero-filled at its size; then the values that are not zero
  detail::size_data_arrays(model, *this);
  qpos = model.qpos0;
  for (auto& q : xquat) q = Eigen::Vector4d(1, 0, 0, 0);
  for (auto* list : {&xmat, &ximat, &site_xmat}) {
    for (Mat3& R : *list) R.setIdentity();
  }
  std::fill(efc_id.begin(), efc_id.end(), -1);
  std::fill(efc_dof.begin(), efc_dof.end(), -1);

  // what is not in the table: lever's spatial inertias, and the workspace
  cinert.assign(nbody, RigidInertia{});
  qLD = Eigen::MatrixXd::Zero(nv, nv);
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
  const EntryCheck entry(model, data, "lever::reset");
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
