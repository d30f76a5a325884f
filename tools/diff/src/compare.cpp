#include <lever/diff/compare.hpp>
#include <lever/dynamics.hpp>
#include <lever/forward.hpp>
#include <lever/kinematics.hpp>
#include <string>
#include <vector>

namespace lever::diff {

namespace {

// ---- labels: what element i of a flattened array is -----------------------------------------

std::string quoted(const std::vector<std::string>& names, int i) {
  std::string out = names[i].empty() ? std::string("#") : "'" + names[i] + "' #";
  out += std::to_string(i);
  return out;
}

const char* axis_name(int c) { return c == 0 ? "x" : c == 1 ? "y" : c == 2 ? "z" : "w"; }

std::string dof_label(const Model& model, int i) {
  return "dof " + std::to_string(i) + " (joint " + quoted(model.jnt_name, model.dof_jntid[i]) + ")";
}

// objects with `per` numbers each: a vector (3), a quaternion (4) or a row-major 3x3 matrix (9)
Labeler per_object(const std::vector<std::string>& names, const char* kind, int per) {
  return [&names, kind, per](int i) {
    const int object = i / per, c = i % per;
    std::string where = std::string(kind) + " " + quoted(names, object) + ", ";
    if (per == 9) return where + "(" + std::to_string(c / 3) + ", " + std::to_string(c % 3) + ")";
    if (per == 4) return where + "component " + std::to_string(c);
    return where + axis_name(c);
  };
}

Labeler per_dof(const Model& model) {
  return [&model](int i) { return dof_label(model, i); };
}

Labeler per_actuator(const Model& model) {
  return [&model](int i) { return "actuator " + quoted(model.actuator_name, i); };
}

// nv x nv, row-major
Labeler mass_matrix(const Model& model) {
  return [&model](int i) {
    return "row " + dof_label(model, i / model.nv) + ", column " + dof_label(model, i % model.nv);
  };
}

// one 3 x nv Jacobian per site, row-major
Labeler jacobian(const Model& model) {
  return [&model](int i) {
    const int per_site = 3 * model.nv, s = i / per_site, r = (i % per_site) / model.nv;
    return "site " + quoted(model.site_name, s) + ", " + axis_name(r) + " row, column " +
           dof_label(model, i % model.nv);
  };
}

Labeler limit_row(const Model& model, const Data& data) {
  return [&model, &data](int r) {
    return "row " + std::to_string(r) + " (joint " + quoted(model.jnt_name, data.efc_id[r]) +
           (data.efc_sign[r] > 0 ? ", lower stop)" : ", upper stop)");
  };
}

// ---- flattening lever's arrays into MuJoCo's layouts --------------------------------------

std::vector<double> flat(const std::vector<Eigen::Vector3d>& v) {
  std::vector<double> out;
  for (const auto& x : v) out.insert(out.end(), x.data(), x.data() + 3);
  return out;
}

// lever stores rotations row by row, as MuJoCo does (lever::Mat3)
const double* flat(const std::vector<Mat3>& v) { return v.empty() ? nullptr : v[0].data(); }

std::vector<double> row_major(const Eigen::MatrixXd& A) {
  std::vector<double> out;
  for (Eigen::Index r = 0; r < A.rows(); ++r) {
    for (Eigen::Index c = 0; c < A.cols(); ++c) out.push_back(A(r, c));
  }
  return out;
}

// A unit quaternion and its negative are the same rotation: take lever's with MuJoCo's sign.
std::vector<double> quaternions_signed_like(const std::vector<Eigen::Vector4d>& ours,
                                            const mjtNum* theirs) {
  std::vector<double> out;
  for (std::size_t b = 0; b < ours.size(); ++b) {
    const Eigen::Vector4d ref(theirs + 4 * b);
    const double sign = ours[b].dot(ref) < 0 ? -1.0 : 1.0;
    for (int c = 0; c < 4; ++c) out.push_back(sign * ours[b][c]);
  }
  return out;
}

// ---- groups of quantities -------------------------------------------------------------------

void compare_kinematics(const Twin& t, int k, Report& r) {
  const Model& model = t.model;
  const Data& data = t.data;
  const mjData* d = t.d.get();
  const int nb = model.nbody, ns = model.nsite;
  r.compare("xpos", k, flat(data.xpos).data(), d->xpos, 3 * nb,
            per_object(model.body_name, "body", 3));
  r.compare("xquat", k, quaternions_signed_like(data.xquat, d->xquat).data(), d->xquat, 4 * nb,
            per_object(model.body_name, "body", 4));
  r.compare("xmat", k, flat(data.xmat), d->xmat, 9 * nb, per_object(model.body_name, "body", 9));
  r.compare("xipos", k, flat(data.xipos).data(), d->xipos, 3 * nb,
            per_object(model.body_name, "body", 3));
  r.compare("ximat", k, flat(data.ximat), d->ximat, 9 * nb, per_object(model.body_name, "body", 9));
  r.compare("site_xpos", k, flat(data.site_xpos).data(), d->site_xpos, 3 * ns,
            per_object(model.site_name, "site", 3));
  r.compare("site_xmat", k, flat(data.site_xmat), d->site_xmat, 9 * ns,
            per_object(model.site_name, "site", 9));
}

void compare_smooth_dynamics(const Twin& t, int k, Report& r) {
  const Model& model = t.model;
  const Data& data = t.data;
  const mjModel* m = t.m.get();
  const mjData* d = t.d.get();
  const int nv = model.nv;
  std::vector<double> full_m(static_cast<std::size_t>(nv) * nv);
  mj_fullM(m, full_m.data(), d->qM);
  r.compare("M", k, row_major(data.M).data(), full_m.data(), nv * nv, mass_matrix(model));
  r.compare("qfrc_bias", k, data.qfrc_bias.data(), d->qfrc_bias, nv, per_dof(model));
  r.compare("qfrc_passive", k, data.qfrc_passive.data(), d->qfrc_passive, nv, per_dof(model));
  r.compare("actuator_force", k, data.actuator_force.data(), d->actuator_force, model.nu,
            per_actuator(model));
  r.compare("qfrc_actuator", k, data.qfrc_actuator.data(), d->qfrc_actuator, nv, per_dof(model));
  r.compare("qacc_smooth", k, data.qacc_smooth.data(), d->qacc_smooth, nv, per_dof(model));
  r.compare("qacc", k, data.qacc.data(), d->qacc, nv, per_dof(model));
  r.compare("qfrc_constraint", k, data.qfrc_constraint.data(), d->qfrc_constraint, nv,
            per_dof(model));
}

// Limit rows: the same rows (count, joint, side) first; their numbers only if those agree.
void compare_limit_rows(const Twin& t, int k, Report& r) {
  const Model& model = t.model;
  const Data& data = t.data;
  const mjModel* m = t.m.get();
  const mjData* d = t.d.get();
  for (const char* q :
       {"nefc", "efc_id", "efc_J", "efc_pos", "efc_margin", "efc_imp", "efc_K", "efc_B", "efc_R",
        "efc_D", "efc_diagApprox", "efc_vel", "efc_aref", "efc_b", "efc_force"}) {
    r.declare(q);
  }
  r.compare("nefc", k, data.nefc, d->nefc);
  if (data.nefc != d->nefc) return;
  bool same_rows = true;
  for (int i = 0; i < data.nefc; ++i) {
    const bool limit = d->efc_type[i] == mjCNSTR_LIMIT_JOINT;
    r.compare("efc_id", k, data.efc_id[i], limit ? d->efc_id[i] : -1, "row " + std::to_string(i));
    same_rows = same_rows && limit && data.efc_id[i] == d->efc_id[i];
  }
  const int n = data.nefc, nv = model.nv;
  if (!same_rows || n == 0) return;

  const Labeler row = limit_row(model, data);
  if (!mj_isSparse(m)) {
    std::vector<double> jac(static_cast<std::size_t>(n) * nv, 0.0);
    for (int i = 0; i < n; ++i) jac[i * nv + data.efc_dof[i]] = data.efc_sign[i];
    r.compare("efc_J", k, jac.data(), d->efc_J, n * nv,
              [&](int i) { return row(i / nv) + ", column " + dof_label(model, i % nv); });
  }
  std::vector<double> stiffness(n), damping(n), impedance(n);
  for (int i = 0; i < n; ++i) {
    stiffness[i] = d->efc_KBIP[4 * i];
    damping[i] = d->efc_KBIP[4 * i + 1];
    impedance[i] = d->efc_KBIP[4 * i + 2];
  }
  r.compare("efc_pos", k, data.efc_pos.data(), d->efc_pos, n, row);
  r.compare("efc_margin", k, data.efc_margin.data(), d->efc_margin, n, row);
  r.compare("efc_imp", k, data.efc_imp.data(), impedance.data(), n, row);
  r.compare("efc_K", k, data.efc_K.data(), stiffness.data(), n, row);
  r.compare("efc_B", k, data.efc_B.data(), damping.data(), n, row);
  r.compare("efc_R", k, data.efc_R.data(), d->efc_R, n, row);
  r.compare("efc_D", k, data.efc_D.data(), d->efc_D, n, row);
  r.compare("efc_diagApprox", k, data.efc_diagApprox.data(), d->efc_diagApprox, n, row);
  r.compare("efc_vel", k, data.efc_vel.data(), d->efc_vel, n, row);
  r.compare("efc_aref", k, data.efc_aref.data(), d->efc_aref, n, row);
  r.compare("efc_b", k, data.efc_b.data(), d->efc_b, n, row);
  r.compare("efc_force", k, data.efc_force.data(), d->efc_force, n, row);
}

void compare_energy(const Twin& t, int k, Report& r) {
  r.compare("energy (potential)", k, t.data.energy[0], t.d->energy[0]);
  r.compare("energy (kinetic)", k, t.data.energy[1], t.d->energy[1]);
}

void compare_site_jacobians(const Twin& t, int k, Report& r) {
  const Model& model = t.model;
  const int nv = model.nv, ns = model.nsite;
  std::vector<double> ours_p(3 * nv * ns), ours_r(3 * nv * ns);
  std::vector<double> mj_p(3 * nv * ns), mj_r(3 * nv * ns);
  Eigen::MatrixXd jacp(3, nv), jacr(3, nv);
  for (int s = 0; s < ns; ++s) {
    jac_site(model, t.data, s, jacp, jacr);
    const std::vector<double> p = row_major(jacp), q = row_major(jacr);
    std::copy(p.begin(), p.end(), ours_p.begin() + 3 * nv * s);
    std::copy(q.begin(), q.end(), ours_r.begin() + 3 * nv * s);
    mj_jacSite(t.m.get(), t.d.get(), mj_p.data() + 3 * nv * s, mj_r.data() + 3 * nv * s, s);
  }
  r.compare("jacp", k, ours_p.data(), mj_p.data(), 3 * nv * ns, jacobian(model));
  r.compare("jacr", k, ours_r.data(), mj_r.data(), 3 * nv * ns, jacobian(model));
}

}  // namespace

void compare_model_constants(const Twin& t, Report& r) {
  const Model& model = t.model;
  const mjModel* m = t.m.get();
  std::vector<double> body_invweight0;
  for (const auto& w : model.body_invweight0)
    body_invweight0.insert(body_invweight0.end(), w.begin(), w.end());
  // model constants: the "state" number 0 stands for qpos0
  r.compare("dof_invweight0", 0, model.dof_invweight0.data(), m->dof_invweight0, model.nv,
            per_dof(model));
  r.compare("dof_M0", 0, model.dof_M0.data(), m->dof_M0, model.nv, per_dof(model));
  r.compare("body_invweight0", 0, body_invweight0.data(), m->body_invweight0, 2 * model.nbody,
            [&model](int i) {
              return "body " + quoted(model.body_name, i / 2) +
                     (i % 2 ? ", rotational" : ", translational");
            });
  r.compare("body_subtreemass", 0, model.body_subtreemass.data(), m->body_subtreemass, model.nbody,
            [&model](int i) { return "body " + quoted(model.body_name, i); });
}

void compare_forward(Twin& t, const test::State& s, int k, Report& r) {
  t.set_state(s);
  forward(t.model, t.data);
  compute_energy(t.model, t.data);
  mj_forward(t.m.get(), t.d.get());
  compare_kinematics(t, k, r);
  compare_smooth_dynamics(t, k, r);
  compare_limit_rows(t, k, r);
  compare_energy(t, k, r);
  compare_site_jacobians(t, k, r);
}

void compare_inverse(Twin& t, const test::State& s, const Eigen::VectorXd& qacc,
                     const std::string& label, int k, Report& r) {
  t.set_state(s);
  t.data.qacc = qacc;
  for (int i = 0; i < t.model.nv; ++i) t.d->qacc[i] = qacc[i];
  inverse(t.model, t.data);
  mj_inverse(t.m.get(), t.d.get());
  r.compare("qfrc_inverse (" + label + ")", k, t.data.qfrc_inverse.data(), t.d->qfrc_inverse,
            t.model.nv, per_dof(t.model));
}

void compare_step(Twin& t, const test::State& s, Integrator integrator, int k, Report& r) {
  const Integrator own = t.model.opt.integrator;
  t.set_integrator(integrator);
  t.set_state(s);
  step(t.model, t.data);
  mj_step(t.m.get(), t.d.get());
  const std::string name = integrator == Integrator::kRK4 ? "RK4" : "Euler";
  r.compare("qpos after one " + name + " step", k, t.data.qpos.data(), t.d->qpos, t.model.nq,
            per_dof(t.model));
  r.compare("qvel after one " + name + " step", k, t.data.qvel.data(), t.d->qvel, t.model.nv,
            per_dof(t.model));
  r.compare("time after one " + name + " step", k, t.data.time, t.d->time);
  t.set_integrator(own);
}

void compare_state(Twin& t, const test::State& s, const Eigen::VectorXd& random_qacc, int k,
                   Report& r) {
  compare_forward(t, s, k, r);
  const Eigen::VectorXd forward_qacc = Eigen::Map<const Eigen::VectorXd>(t.d->qacc, t.model.nv);
  compare_inverse(t, s, forward_qacc, "at the forward qacc", k, r);
  compare_inverse(t, s, random_qacc, "at a random qacc", k, r);
  compare_step(t, s, Integrator::kEuler, k, r);
  compare_step(t, s, Integrator::kRK4, k, r);
}

}  // namespace lever::diff
