#include "check.hpp"

#include <lever/harness/tolerance.hpp>

#include "pinocchio_ops.hpp"

#include <lever/batch.hpp>
#include <lever/lever.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <stdexcept>
#include <string>

namespace lever::bench {

namespace {

// max |a - b| / max |b| (absolute where b is all zero)
template <class A, class B>
double rel_error(const A& a, const B& b, std::size_t n) {
  double diff = 0, scale = 0;
  for (std::size_t i = 0; i < n; ++i) {
    diff = std::max(diff, std::abs(a[i] - b[i]));
    scale = std::max(scale, std::abs(b[i]));
  }
  return scale > 0 ? diff / scale : diff;
}

std::vector<double> flat(const Eigen::MatrixXd& m) {  // row-major copy
  std::vector<double> out;
  for (Eigen::Index r = 0; r < m.rows(); ++r) {
    for (Eigen::Index c = 0; c < m.cols(); ++c) out.push_back(m(r, c));
  }
  return out;
}

struct Table {
  std::ostream& out;
  bool ok = true;
  void row(const std::string& what, const std::string& model, const std::string& quantity,
           double error, double tolerance) {
    const bool pass = error <= tolerance;  // NaN fails
    ok = ok && pass;
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.2e", error);
    out << "| " << what << " | " << model << " | " << quantity << " | " << buf << " | " << tolerance
        << " | " << (pass ? "ok" : "**FAIL**") << " |\n";
  }
};

// 1. lever against KDL on random states
void check_kdl(const Fixture& f, Table& table) {
  constexpr double kTol = 1e-9;
  constexpr int kStates = 25;
  const Model& m = f.model;
  KdlPeer kdl(*f.chain);
  Data d(m);
  const auto nv = static_cast<std::size_t>(m.nv);
  Eigen::MatrixXd jacp(3, m.nv), jacr(3, m.nv);
  Eigen::VectorXd tau(m.nv), tau_rnea(m.nv), qacc(m.nv), zero = Eigen::VectorXd::Zero(m.nv);
  std::mt19937_64 rng(12345);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  double e_mass = 0, e_grav = 0, e_bias = 0, e_rne = 0, e_fd = 0, e_pos = 0, e_rot = 0, e_jac = 0;
  for (int k = 0; k < kStates; ++k) {
    State s = random_state(m, 777 + static_cast<unsigned long long>(k));
    for (int j = 0; j < m.njnt; ++j) {  // anywhere in the range, not only its middle
      const int a = m.jnt_qposadr[j];
      if (m.jnt_limited[j])
        s.qpos[a] =
            m.jnt_range[j][0] + 0.5 * (u(rng) + 1) * (m.jnt_range[j][1] - m.jnt_range[j][0]);
    }
    for (int i = 0; i < m.nv; ++i) tau[i] = 5 * u(rng);
    kdl.set_state(s.qpos.data(), s.qvel.data(), s.qacc.data(), tau.data());

    d.qpos = s.qpos;
    d.qvel = s.qvel;
    kinematics(m, d);
    crba(m, d);
    kdl.mass();
    e_mass = std::max(e_mass, rel_error(kdl.mass_matrix(), flat(d.M), nv * nv));

    bias(m, d);
    kdl.rne_bias();
    e_bias = std::max(e_bias, rel_error(kdl.torques(), d.qfrc_bias, nv));

    rnea(m, d, s.qacc, tau_rnea);
    kdl.rne();
    e_rne = std::max(e_rne, rel_error(kdl.torques(), tau_rnea, nv));

    // forward dynamics: qacc = M^-1 (tau - bias)
    factor_mass(m, d);
    qacc = tau - d.qfrc_bias;
    solve_mass(m, d, qacc);
    kdl.forward_dynamics();
    e_fd = std::max(e_fd, rel_error(kdl.qddot(), qacc, nv));

    if (f.site >= 0) {
      kdl.fk();
      const std::array<double, 12> tip = kdl.tip_frame();
      e_pos =
          std::max(e_pos, rel_error(tip.data(), d.site_xpos[static_cast<std::size_t>(f.site)], 3));
      e_rot = std::max(
          e_rot, rel_error(tip.data() + 3, flat(d.site_xmat[static_cast<std::size_t>(f.site)]), 9));
      jac_site(m, d, f.site, jacp, jacr);
      Eigen::MatrixXd jac(6, m.nv);
      jac << jacp, jacr;
      kdl.jacobian();
      e_jac = std::max(e_jac, rel_error(kdl.jacobian_matrix(), flat(jac), 6 * nv));
    }

    d.qvel = zero;
    bias(m, d);
    kdl.gravity();
    e_grav = std::max(e_grav, rel_error(kdl.torques(), d.qfrc_bias, nv));
  }
  const std::string what = "KDL bridge (" + std::to_string(kStates) + " states)";
  table.row(what, f.name, "M (JntToMass, armature as KDL joint inertia)", e_mass, kTol);
  table.row(what, f.name, "gravity torques (JntToGravity)", e_grav, kTol);
  table.row(what, f.name, "bias C qdot + g (RNE, qddot = 0)", e_bias, kTol);
  table.row(what, f.name, "inverse dynamics (RNE)", e_rne, kTol);
  table.row(what, f.name, "forward dynamics (ChainFdSolver_RNE)", e_fd, kTol);
  if (f.site >= 0) {
    table.row(what, f.name, "tip position (FK)", e_pos, kTol);
    table.row(what, f.name, "tip rotation (FK)", e_rot, kTol);
    table.row(what, f.name, "tip Jacobian", e_jac, kTol);
  }
}

// 2. lever against MuJoCo on the timed states
void check_mujoco(const Fixture& f, const State& s, const std::string& label, Table& table) {
  const Model& m = f.model;
  const mjModel* mj = f.mj.get();
  Data d(m);
  d.qpos = s.qpos;
  d.qvel = s.qvel;
  d.ctrl = s.ctrl;
  forward(m, d);
  MjDataPtr md = mujoco_data(f, s);
  // a contact scene's accelerations come from MuJoCo's iterative solver: compare with it run to
  // convergence (tolerance 0), where its answer is unique, on the mixed scale of the project's
  // bound (at rest qacc is rounding noise around 0, so a relative error means nothing)
  MjModelPtr converged(nullptr, mj_deleteModel);
  if (f.scene) {
    converged.reset(mj_copyModel(nullptr, mj));
    converged->opt.tolerance = 0;
    converged->opt.iterations = 1000;
    mj = converged.get();
  }
  mj_forward(mj, md.get());
  std::vector<mjtNum> M(static_cast<std::size_t>(mj->nv * mj->nv));
  mj_fullM(mj, M.data(), md->qM);
  const auto nv = static_cast<std::size_t>(m.nv);
  const std::string what =
      "lever = MuJoCo (" + label + ", " + std::to_string(d.nefc) + " constraint rows)";
  table.row(what, f.name, "M", rel_error(flat(d.M), M, nv * nv), 1e-9);
  table.row(what, f.name, "qfrc_bias", rel_error(d.qfrc_bias, md->qfrc_bias, nv), 1e-9);
  if (f.scene) {
    double mixed = 0;
    for (std::size_t i = 0; i < nv; ++i) {
      mixed = std::max(mixed, std::abs(d.qacc[static_cast<Eigen::Index>(i)] - md->qacc[i]) /
                                  std::max(1.0, std::abs(md->qacc[i])));
    }
    table.row(what, f.name, "qacc (MuJoCo converged; |diff| / max(1, |qacc|))", mixed, 1e-9);
  } else {
    table.row(what, f.name, "qacc", rel_error(d.qacc, md->qacc, nv), 1e-6);
  }
  if (f.sensors) {
    table.row(what, f.name, "sensordata",
              rel_error(d.sensordata, md->sensordata, static_cast<std::size_t>(m.nsensordata)),
              1e-9);
  }
  if (d.nefc != md->nefc) table.row(what, f.name, "nefc differs", 1.0, 0.0);
}

// 3. the batch API against one state at a time
void check_batch(const Fixture& f, Table& table) {
  const Model& m = f.model;
  constexpr int kStates = 37;  // odd, so the blocks differ in size
  constexpr int kSteps = 3;
  Eigen::MatrixXd qpos(m.nq, kStates), qvel(m.nv, kStates), ctrl(m.nu, kStates);
  for (int k = 0; k < kStates; ++k) {
    // every third state with its first limited joint past the stop: limit rows in the batch
    State s = random_state(m, 99 + static_cast<unsigned long long>(k));
    if (k % 3 == 0 && f.limit_joint >= 0)
      s.qpos[m.jnt_qposadr[f.limit_joint]] = m.jnt_range[f.limit_joint][0] - 1e-3;
    qpos.col(k) = s.qpos;
    qvel.col(k) = s.qvel;
    ctrl.col(k) = s.ctrl;
  }
  // one state at a time
  Eigen::MatrixXd qacc_ref(m.nv, kStates), qpos_ref = qpos, qvel_ref = qvel;
  Data d(m);
  for (int k = 0; k < kStates; ++k) {
    d.qpos = qpos.col(k);
    d.qvel = qvel.col(k);
    d.ctrl = ctrl.col(k);
    forward(m, d);
    qacc_ref.col(k) = d.qacc;
    for (int i = 0; i < kSteps; ++i) step(m, d);
    qpos_ref.col(k) = d.qpos;
    qvel_ref.col(k) = d.qvel;
  }
  for (const int threads : {1, 2}) {
    BatchRunner runner(m, threads);
    Eigen::MatrixXd qacc(m.nv, kStates), p = qpos, v = qvel;
    runner.forward(qpos, qvel, ctrl, qacc);
    runner.step(p, v, ctrl, kSteps);
    const std::string what = "BatchRunner, " + std::to_string(threads) + " thread(s), " +
                             std::to_string(kStates) + " states";
    table.row(what, f.name, "qacc = forward() (exact)", (qacc - qacc_ref).cwiseAbs().maxCoeff(),
              0.0);
    table.row(what, f.name, "state after 3 step() (exact)",
              std::max((p - qpos_ref).cwiseAbs().maxCoeff(), (v - qvel_ref).cwiseAbs().maxCoeff()),
              0.0);
  }
}

// 4. lever against Pinocchio on random states, to the project's bound (lever/harness/tolerance.hpp):
// per quantity and state, max |lever - Pinocchio| / (1e-12 max(1, the quantity's magnitude))
#ifdef LEVER_BENCH_PINOCCHIO_VERSION
template <class A, class B>
double excess(const A& ours, const B& theirs, std::size_t n) {
  double worst = 0, magnitude = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (std::isfinite(theirs[i])) magnitude = std::max(magnitude, std::abs(theirs[i]));
  }
  for (std::size_t i = 0; i < n; ++i) {
    worst = std::max(worst, test::excess(ours[i], theirs[i], magnitude));
  }
  return worst;
}

void check_pinocchio(const Fixture& f, Table& table) {
  constexpr double kBound = 1;  // excess() is in units of the bound
  constexpr int kStates = 10;
  PinocchioRig rig(f, f.state);
  const Model& m = rig.model;
  Data& d = rig.d;
  PinocchioPeer& pin = *rig.peer;
  const auto nv = static_cast<std::size_t>(m.nv);
  Eigen::VectorXd tau_rnea(m.nv), tau(m.nv);
  std::mt19937_64 rng(4242);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const auto op = [](const std::string& name) -> const PinocchioOperation& {
    for (const PinocchioOperation& o : pinocchio_operations())
      if (o.name == name) return o;
    throw std::logic_error("no operation " + name);
  };
  double e_pos = 0, e_rot = 0, e_jac = 0, e_nle = 0, e_rnea = 0, e_M = 0, e_aba = 0, e_fwd = 0;
  double e_tq = 0, e_tv = 0, e_tM = 0, e_aq = 0, e_av = 0;
  for (int k = 0; k < kStates; ++k) {
    State s = random_state(m, 31337 + static_cast<unsigned long long>(k));
    for (int j = 0; j < m.njnt; ++j) {  // anywhere in the range, not only its middle
      const int a = m.jnt_qposadr[j];
      if (m.jnt_limited[j])
        s.qpos[a] =
            m.jnt_range[j][0] + 0.5 * (u(rng) + 1) * (m.jnt_range[j][1] - m.jnt_range[j][0]);
    }
    for (int i = 0; i < m.nv; ++i) tau[i] = 5 * u(rng);
    pin.set_state(s.qpos.data(), s.qvel.data(), s.qacc.data(), tau.data());
    d.qpos = s.qpos;
    d.qvel = s.qvel;
    d.qacc = s.qacc;
    d.qfrc_applied = tau;

    if (f.site >= 0) {
      op("jac_site_from_q").lever(f, rig);
      pin.frame_jacobian();
      const std::array<double, 12> tip = pin.frame_placement();
      const auto site = static_cast<std::size_t>(f.site);
      e_pos = std::max(e_pos, excess(d.site_xpos[site], tip.data(), 3));
      e_rot = std::max(e_rot, excess(flat(d.site_xmat[site]), tip.data() + 3, 9));
      Eigen::MatrixXd jac(6, m.nv);
      jac << rig.jacp, rig.jacr;
      e_jac = std::max(e_jac, excess(flat(jac), pin.jacobian(), 6 * nv));
    }
    kinematics(m, d);
    bias(m, d);
    pin.nonlinear_effects();
    e_nle = std::max(e_nle, excess(d.qfrc_bias, pin.bias(), nv));
    rnea(m, d, s.qacc, tau_rnea);
    pin.rnea();
    e_rnea = std::max(e_rnea, excess(tau_rnea, pin.tau(), nv));
    crba(m, d);
    pin.crba();
    e_M = std::max(e_M, excess(flat(d.M), pin.mass_matrix(), nv * nv));

    op("aba").lever(f, rig);
    pin.aba();
    e_aba = std::max(e_aba, excess(d.qacc, pin.acceleration(), nv));
    forward(m, d);  // the whole forward dynamics: qfrc_applied is the only force besides bias
    e_fwd = std::max(e_fwd, excess(d.qacc, pin.acceleration(), nv));
    if (d.nefc != 0) table.row("lever = Pinocchio", f.name, "a constraint row in forward()", 1, 0);

    d.qacc = s.qacc;
    op("rnea_derivatives").lever(f, rig);
    pin.rnea_derivatives();
    e_tq = std::max(e_tq, excess(flat(rig.deriv.dtau_dq), pin.dtau_dq(), nv * nv));
    e_tv = std::max(e_tv, excess(flat(rig.deriv.dtau_dv), pin.dtau_dv(), nv * nv));
    e_tM = std::max(e_tM, excess(flat(d.M), pin.mass_matrix(), nv * nv));

    op("aba_derivatives").lever(f, rig);
    pin.aba_derivatives();
    e_aq = std::max(e_aq, excess(flat(rig.deriv.dqacc_dq), pin.dacc_dq(), nv * nv));
    e_av = std::max(e_av, excess(flat(rig.deriv.dqacc_dv), pin.dacc_dv(), nv * nv));
  }
  const std::string what = "lever = Pinocchio " + pinocchio_peer_version() + " (" +
                           std::to_string(kStates) + " states; in units of the 1e-12 bound)";
  if (f.site >= 0) {
    table.row(what, f.name, "tip position (computeFrameJacobian's placement)", e_pos, kBound);
    table.row(what, f.name, "tip rotation", e_rot, kBound);
    table.row(what, f.name, "tip Jacobian, world axes (computeFrameJacobian)", e_jac, kBound);
  }
  table.row(what, f.name, "bias C v + g (nonLinearEffects)", e_nle, kBound);
  table.row(what, f.name, "inverse dynamics (rnea)", e_rnea, kBound);
  table.row(what, f.name, "M (crba)", e_M, kBound);
  table.row(what, f.name, "a from tau (aba; lever's CRBA and LTDL)", e_aba, kBound);
  table.row(what, f.name, "a from tau (aba; lever's forward())", e_fwd, kBound);
  table.row(what, f.name, "d tau / d q (computeRNEADerivatives)", e_tq, kBound);
  table.row(what, f.name, "d tau / d v (computeRNEADerivatives)", e_tv, kBound);
  table.row(what, f.name, "M (computeRNEADerivatives)", e_tM, kBound);
  table.row(what, f.name, "d a / d q (computeABADerivatives; forward_derivatives)", e_aq, kBound);
  table.row(what, f.name, "d a / d v (computeABADerivatives; forward_derivatives)", e_av, kBound);
}
#endif

}  // namespace

bool run_checks(const std::vector<std::unique_ptr<Fixture>>& fixtures, std::ostream& out) {
  out << "| check | model | quantity | max rel. error | tolerance | |\n";
  out << "|---|---|---|---:|---:|---|\n";
  Table table{out};
  for (const auto& f : fixtures) {
    // a contact scene and the sensor model have no KDL peer and no batch: MuJoCo's check only
    if (f->scene || f->sensors) continue;
    if (f->chain) {
      check_kdl(*f, table);
    } else {
      out << "| KDL bridge | " << f->name << " | not a serial chain (" << f->kdl_note
          << "): no KDL peer | | | |\n";
    }
  }
  for (const auto& f : fixtures) {
    check_mujoco(*f, f->state, "timed state", table);
    if (f->limit) check_mujoco(*f, *f->limit, "timed limit state", table);
  }
  for (const auto& f : fixtures) {
    if (!f->scene && !f->sensors) check_batch(*f, table);
  }
#ifdef LEVER_BENCH_PINOCCHIO_VERSION
  for (const auto& f : fixtures) {
    if (f->chain) check_pinocchio(*f, table);
  }
#else
  out << "| Pinocchio | | not in this build (make bench installs it: LEVER_BENCH_PINOCCHIO) | | | |\n";
#endif
  return table.ok;
}

}  // namespace lever::bench
