// lever's analytic derivatives against MuJoCo 2.2.2 in the same process: its mjd_transitionFD
// (centred), and its mj_inverse and mj_forward differenced here.
//
// MuJoCo 2.2.2 has no analytic derivatives of the dynamics in its API: mjd_transitionFD (finite
// differences of mj_step, declared in mujoco.h) is the reference for A and B; mjd_smooth_vel
// (d qfrc_smooth / d qvel, for its implicit integrator) is exported but not declared in its
// public header, so it is not used. mjd_inverseFD does not exist before 2.3.
//
// Step and bound: centred differences with eps = 1e-5. Their error is truncation, eps^2/6 |f'''|
// (1.7e-11 of the scale of f and its derivatives), plus rounding, rho |f| / eps, where rho is the
// relative rounding error of MuJoCo's own output. For accelerations out of a solve with M, rho is
// 2.2e-16 times M's conditioning: it reaches about 1e-14 on chain20 (measured: a step of 1e-6 gave
// differences of 1e-8 of |qacc| there), i.e. 1e-9 of the scale with eps = 1e-5. The bound, 1e-8 of
// max(1, |f|, |f'|), is ten times that. The states are kept away from every non-differentiable
// point (limit margins, clamp edges), and so away from MuJoCo's iterative constraint solver,
// which has no rows at these states.
//
// MuJoCo 2.2.2's mjd_transitionFD is not a faithful derivative of mj_step under RK4 (nor, for an
// actuator whose gain is affine in velocity, under implicit: see the implicit case below): for its
// qvel and ctrl columns it steps with mj_stepSkip(mjSTAGE_POS / mjSTAGE_VEL), which reuses the
// position (and velocity) stage left in mjData by the previous call, and after an RK4 step that
// stage is RK4's last stage (qpos + h k3, qvel + h a3), not the state being differenced. Its qvel
// and ctrl columns then differ from mj_step's own derivative by about 1e-5 relative (arm2:
// d qpos'/d qvel = 0.00199902 from mj_step, 0.00199900 from mjd_transitionFD). Under RK4 those
// columns are therefore compared with mj_step differenced here; its qpos columns (computed with
// no stage skipped) are compared with lever's as usual.
#include <catch2/catch.hpp>
#include <lever/diff/twin.hpp>

#include <lever/derivatives.hpp>
#include <lever/harness/from_mujoco.hpp>
#include <lever/identify.hpp>
#include <lever/lever.hpp>
#include <lever/mjcf.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

#include <lever/harness/models.hpp>
#include "../support/random_tree_mjcf.hpp"
#include "smooth_states.hpp"

namespace lever::test {

namespace {

constexpr double kEps = 1e-5;
constexpr double kBound = 1e-8;
constexpr int kMujocoStates = 20;

using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

void check_close(const Eigen::MatrixXd& lever, const Eigen::MatrixXd& mujoco, double value_scale,
                 const std::string& what, double* worst) {
  REQUIRE(lever.rows() == mujoco.rows());
  REQUIRE(lever.cols() == mujoco.cols());
  const double scale = std::max({1.0, value_scale, largest(mujoco)});
  for (Eigen::Index r = 0; r < lever.rows(); ++r) {
    for (Eigen::Index c = 0; c < lever.cols(); ++c) {
      const double ratio = std::abs(lever(r, c) - mujoco(r, c)) / (kBound * scale);
      *worst = std::max(*worst, ratio);
      if (!(ratio <= 1)) {
        std::ostringstream s;
        s.precision(17);
        s << what << "(" << r << ", " << c << "): lever " << lever(r, c) << " vs mujoco "
          << mujoco(r, c) << " (" << ratio << " of the bound " << kBound * scale << ")";
        FAIL(s.str());
      }
    }
  }
}

// MuJoCo's output (n values written by eval) differenced along each element of x (size m).
template <class Eval>
Eigen::MatrixXd mujoco_differences(mjtNum* x, int m, int n, const mjtNum* out, Eval eval) {
  Eigen::MatrixXd D(n, m);
  Eigen::VectorXd plus(n), minus(n);
  for (int c = 0; c < m; ++c) {
    const mjtNum x0 = x[c];
    x[c] = x0 + kEps;
    eval();
    for (int r = 0; r < n; ++r) plus[r] = out[r];
    x[c] = x0 - kEps;
    eval();
    for (int r = 0; r < n; ++r) minus[r] = out[r];
    x[c] = x0;
    D.col(c) = (plus - minus) / (2 * kEps);
  }
  return D;
}

// MuJoCo's output (n values written by eval) differenced along qpos's tangent: column c moves
// qpos with mj_integratePos by +-eps along dof c (what mjd_transitionFD does).
template <class Eval>
Eigen::MatrixXd mujoco_tangent_differences(const mjModel* m, mjData* d, int n, const mjtNum* out,
                                           Eval eval) {
  const int nv = m->nv, nq = m->nq;
  Eigen::MatrixXd D(n, nv);
  Eigen::VectorXd plus(n), minus(n), qpos0(nq), dpos(nv);
  for (int i = 0; i < nq; ++i) qpos0[i] = d->qpos[i];
  for (int c = 0; c < nv; ++c) {
    dpos.setZero();
    dpos[c] = 1;
    for (const double t : {kEps, -kEps}) {
      for (int i = 0; i < nq; ++i) d->qpos[i] = qpos0[i];
      mj_integratePos(m, d->qpos, dpos.data(), t);
      eval();
      for (int r = 0; r < n; ++r) (t > 0 ? plus : minus)[r] = out[r];
    }
    D.col(c) = (plus - minus) / (2 * kEps);
  }
  for (int i = 0; i < nq; ++i) d->qpos[i] = qpos0[i];
  return D;
}

// mj_step differenced here, centred, along qvel (A's right columns) and ctrl (B), each coordinate
// stepped from the saved state s (mj_step moves qpos and qvel); the next qpos read in tangent
// space with mj_differentiatePos, from the minus side to the plus side (as mjd_transitionFD).
void mj_step_differences(diff::Twin& twin, const State& s, Eigen::MatrixXd& Av,
                         Eigen::MatrixXd& Bu) {
  const int nv = twin.model.nv, nu = twin.model.nu, nq = twin.model.nq;
  const mjModel* m = twin.m.get();
  mjData* d = twin.d.get();
  Av.resize(2 * nv, nv);
  Bu.resize(2 * nv, nu);
  Eigen::VectorXd plus(nq + nv), minus(nq + nv), column(2 * nv);
  const auto restore = [&] {
    for (int i = 0; i < nq; ++i) d->qpos[i] = s.qpos[i];
    for (int i = 0; i < nv; ++i) d->qvel[i] = s.qvel[i];
    for (int a = 0; a < nu; ++a) d->ctrl[a] = s.ctrl[a];
    d->time = s.time;
  };
  for (int c = 0; c < nv + nu; ++c) {
    for (const double delta : {kEps, -kEps}) {
      restore();
      if (c < nv)
        d->qvel[c] += delta;
      else
        d->ctrl[c - nv] += delta;
      mj_step(m, d);
      Eigen::VectorXd& next = delta > 0 ? plus : minus;
      for (int i = 0; i < nq; ++i) next[i] = d->qpos[i];
      for (int i = 0; i < nv; ++i) next[nq + i] = d->qvel[i];
    }
    mj_differentiatePos(m, column.data(), 2 * kEps, minus.data(), plus.data());
    column.tail(nv) = (plus.tail(nv) - minus.tail(nv)) / (2 * kEps);
    if (c < nv)
      Av.col(c) = column;
    else
      Bu.col(c - nv) = column;
  }
  restore();
}

// Every model file that cannot make contacts (contacts.cpp tests the others at chosen states: a
// random state would cross contact boundaries inside its differences; ball and free
// joints included), servo_affine.xml (every term of a general actuator; tests/derivatives only),
// and a few random MJCF trees (ball joints, free roots: tests/support/random_tree_mjcf.hpp),
// written to temporary files for MuJoCo to compile.
constexpr int kRandomTreeFiles = 5;
std::vector<std::string> derivative_model_files() {
  std::vector<std::string> files = all_model_files();
  std::erase_if(files, [](const std::string& f) { return mjcf::load_file(f).contacts_possible; });
  files.push_back(model_path("tests/derivatives/servo_affine.xml"));
  const std::uint64_t first = seed_for("derivatives_random_tree_mjcf");
  for (int t = 0; t < kRandomTreeFiles; ++t) {
    const std::uint64_t seed = first + static_cast<std::uint64_t>(t);
    const std::string file = (std::filesystem::temp_directory_path() /
                              ("lever_derivatives_tree_" + std::to_string(seed) + ".xml"))
                                 .string();
    std::ofstream(file) << random_tree_mjcf(seed);
    files.push_back(file);
  }
  return files;
}

}  // namespace

TEST_CASE("derivatives: A and B agree with MuJoCo's mjd_transitionFD (centred)",
          "[derivatives][mujoco]") {
  REQUIRE(mj_version() == 222);
  for (const Integrator integrator :
       {Integrator::kEuler, Integrator::kRK4, Integrator::kImplicit}) {
    for (const std::string& file : derivative_model_files()) {
      INFO(file << " " << integrator_name(integrator));
      diff::Twin twin(file, diff::Path::kEngine);
      twin.set_integrator(integrator);
      const Model& model = twin.model;
      const int nv = model.nv, nu = model.nu;
      const double h = model.opt.timestep;
      Derivatives deriv(model);
      Data probe(model);
      RowMajor A(2 * nv, 2 * nv), B(2 * nv, std::max(nu, 1));
      std::mt19937_64 rng(seed_for(file) + 11);
      double worst = 0;
      int compared = 0, missing_columns = 0;
      for (int k = 0; k < kMujocoStates; ++k) {
        const State s = smooth_state(model, rng, false);
        // a clamp switching inside a difference (at any RK4 stage: the stages move the state by
        // h/2 qacc, which a stiff servo makes large) is a non-differentiable point: not compared
        if (!differences_see_same_switches(model, probe, s, kEps)) continue;
        ++compared;
        twin.set_state(s);
        step_derivatives(model, twin.data, deriv);
        REQUIRE(twin.data.nefc == 0);
        // MuJoCo 2.2.2's mjd_transitionFD writes zeros over nq + nv + na numbers of B's row of
        // 2 nv + na when a ctrl can be nudged neither way (outside its ctrlrange): with
        // quaternions (nq > nv) past the row, and past B's last row into the state it saved and
        // then restores (measured on floating.xml: A's qvel columns off by 1e4). In those states
        // its B is not asked for (no ctrl columns, nothing overwritten), and lever's B is compared
        // with mj_step differenced instead.
        bool mujoco_overwrites = false;
        for (int a = 0; a < nu && model.nq > nv; ++a) {
          const auto& range = model.actuator_ctrlrange[a];
          const double u = s.ctrl[a];
          const auto in = [&](double x) { return x >= range[0] && x <= range[1]; };
          mujoco_overwrites =
              mujoco_overwrites || (model.actuator_ctrllimited[a] && !(in(u) && in(u + kEps)) &&
                                    !(in(u - kEps) && in(u)));
        }
        const bool mujoco_B = nu > 0 && !mujoco_overwrites;
        mjd_transitionFD(twin.m.get(), twin.d.get(), kEps, 1, A.data(),
                         mujoco_B ? B.data() : nullptr, nullptr, nullptr);
        const double scale = std::max(s.qpos.cwiseAbs().maxCoeff(), s.qvel.cwiseAbs().maxCoeff());
        if (integrator == Integrator::kEuler) {
          check_close(deriv.A, A, scale, "A", &worst);
          if (mujoco_B) check_close(deriv.B, B.leftCols(nu), scale, "B", &worst);
          if (nu > 0 && !mujoco_B) {
            Eigen::MatrixXd Av, Bu;
            mj_step_differences(twin, s, Av, Bu);
            check_close(deriv.B, Bu, scale, "B (mj_step differenced)", &worst);
          }
          continue;
        }
        Eigen::MatrixXd Av, Bu;
        mj_step_differences(twin, s, Av, Bu);
        if (integrator == Integrator::kRK4) {
          // mjd_transitionFD's qpos columns; mj_step differenced for the rest (see the top)
          check_close(deriv.A.leftCols(nv), A.leftCols(nv), scale, "A (qpos columns)", &worst);
          check_close(deriv.A.rightCols(nv), Av, scale, "A (qvel columns, mj_step differenced)",
                      &worst);
          if (nu > 0) check_close(deriv.B, Bu, scale, "B (mj_step differenced)", &worst);
          continue;
        }
        // implicit: A from mjd_transitionFD; B from mj_step differenced, and mjd_transitionFD's
        // B is lever's B without the term of D's dependence on ctrl. Its ctrl columns step with
        // mj_stepSkip(mjSTAGE_VEL), whose mj_implicitSkip reuses the LU factor of M - h D from
        // the unperturbed step, so D's gainprm[2] ctrl is held at the unperturbed ctrl. For an
        // actuator with an affine gain, the term it drops is d a / d ctrl_k = K^-1 h gear^2
        // gainprm[2] a_dof e_dof, i.e. B's column k less [h^2; h] times that.
        check_close(deriv.A, A, scale, "A", &worst);
        if (nu == 0) continue;
        check_close(deriv.B, Bu, scale, "B (mj_step differenced)", &worst);
        if (!mujoco_B) continue;
        Eigen::MatrixXd B_held_D = deriv.B;
        for (int a = 0; a < nu; ++a) {
          if (model.actuator_gaintype[a] != GainType::kAffine) continue;
          const double p2 = model.actuator_gainprm[a][2];
          if (p2 == 0) continue;
          const double gear = model.actuator_gear[a][0];
          const int dof = model.jnt_dofadr[model.actuator_trnid[a][0]];
          Eigen::VectorXd term = Eigen::VectorXd::Zero(nv);
          term[dof] = h * gear * p2 * gear * deriv.work.qacc_step[dof];
          const Eigen::VectorXd da = deriv.work.K.partialPivLu().solve(term);
          B_held_D.col(a).head(nv) -= h * h * da;
          B_held_D.col(a).tail(nv) -= h * da;
          // the dropped term is far above the bound: the two Bs are told apart
          const double bound = kBound * std::max({1.0, scale, largest(B.leftCols(nu))});
          if ((h * da).cwiseAbs().maxCoeff() > 100 * bound) ++missing_columns;
        }
        check_close(B_held_D, B.leftCols(nu), scale, "B (mjd_transitionFD, D held)", &worst);
      }
      int velocity_gains = 0;  // actuators whose gain is affine in velocity
      for (int a = 0; a < nu; ++a) {
        velocity_gains +=
            model.actuator_gaintype[a] == GainType::kAffine && model.actuator_gainprm[a][2] != 0;
      }
      CHECK(compared >= kMujocoStates * 3 / 4);
      // the dropped term is real: in every compared state, every such column shows it
      if (integrator == Integrator::kImplicit) CHECK(missing_columns == velocity_gains * compared);
      UNSCOPED_INFO(file << ": worst " << worst << " of the bound");
    }
  }
}

TEST_CASE("derivatives: d rnea agrees with MuJoCo's mj_inverse differenced",
          "[derivatives][mujoco]") {
  for (const std::string& file : derivative_model_files()) {
    INFO(file);
    diff::Twin twin(file, diff::Path::kEngine);
    const Model& model = twin.model;
    const int nv = model.nv;
    mjData* d = twin.d.get();
    Derivatives deriv(model);
    std::mt19937_64 rng(seed_for(file) + 13);
    double worst = 0;
    for (int k = 0; k < kMujocoStates; ++k) {
      const State s = smooth_state(model, rng, false);
      const Eigen::VectorXd qacc = random_qacc(model, rng);
      twin.set_state(s);
      kinematics(model, twin.data);
      rnea_derivatives(model, twin.data, qacc, deriv);
      // qfrc_inverse = rnea - qfrc_passive (no limit rows here): their sum, MuJoCo's own passive
      // forces (springs, ball springs by the quaternion difference, damping) added back, is rnea
      for (int i = 0; i < nv; ++i) d->qacc[i] = qacc[i];
      Eigen::VectorXd rnea_mujoco(nv);
      const auto inverse = [&] {
        mj_inverse(twin.m.get(), d);
        for (int i = 0; i < nv; ++i) rnea_mujoco[i] = d->qfrc_inverse[i] + d->qfrc_passive[i];
      };
      inverse();
      REQUIRE(d->nefc == 0);
      const double scale = largest(rnea_mujoco);
      check_close(deriv.dtau_dq,
                  mujoco_tangent_differences(twin.m.get(), d, nv, rnea_mujoco.data(), inverse),
                  scale, "d rnea / d qpos", &worst);
      check_close(deriv.dtau_dv, mujoco_differences(d->qvel, nv, nv, rnea_mujoco.data(), inverse),
                  scale, "d rnea / d qvel", &worst);
    }
    UNSCOPED_INFO(file << ": worst " << worst << " of the bound");
  }
}

TEST_CASE("derivatives: d qacc agrees with MuJoCo's mj_forward differenced",
          "[derivatives][mujoco]") {
  for (const std::string& file : derivative_model_files()) {
    INFO(file);
    diff::Twin twin(file, diff::Path::kEngine);
    const Model& model = twin.model;
    const int nv = model.nv, nu = model.nu;
    mjData* d = twin.d.get();
    Derivatives deriv(model);
    std::mt19937_64 rng(seed_for(file) + 17);
    double worst = 0;
    for (int k = 0; k < kMujocoStates; ++k) {
      const State s = smooth_state(model, rng, false);
      twin.set_state(s);
      forward_derivatives(model, twin.data, deriv);
      const auto forward = [&] { mj_forward(twin.m.get(), d); };
      forward();
      REQUIRE(d->nefc == 0);
      const double scale = largest(Eigen::Map<Eigen::VectorXd>(d->qacc, nv));
      check_close(deriv.dqacc_dq, mujoco_tangent_differences(twin.m.get(), d, nv, d->qacc, forward),
                  scale, "d qacc / d qpos", &worst);
      check_close(deriv.dqacc_dv, mujoco_differences(d->qvel, nv, nv, d->qacc, forward), scale,
                  "d qacc / d qvel", &worst);
      if (nu > 0) {
        check_close(deriv.dqacc_du, mujoco_differences(d->ctrl, nu, nv, d->qacc, forward), scale,
                    "d qacc / d ctrl", &worst);
      }
    }
    UNSCOPED_INFO(file << ": worst " << worst << " of the bound");
  }
}

}  // namespace lever::test

namespace lever::test {

TEST_CASE("identify: the written model loads in MuJoCo and its mj_inverse is the truth's",
          "[derivatives][identify][mujoco]") {
  // the truth (arm2 with link 2 twice as heavy) and the identified model both go through
  // write_model, so MuJoCo compiles each from its own file
  const std::string arm2 = model_path("models/arm2.xml");
  const Model prior = mjcf::load_file(arm2);
  Model truth = prior;
  truth.body_mass[2] = 1.6;
  truth.body_ipos[2] << 0.25, 0, 0;
  truth.body_inertia[2] *= 2.0;
  set_const(truth);
  const auto temp = [](const char* name) {
    return (std::filesystem::temp_directory_path() / (std::string("lever_mj_") + name)).string();
  };
  const std::string truth_file = temp("truth.xml"), identified_file = temp("identified.xml");
  identify::write_model(arm2, truth, truth_file);

  // noise-free data from lever's simulation of the truth: random states, forward's qacc
  std::mt19937_64 rng(5);
  Data data(truth);
  identify::Trajectory t;
  const int samples = 300;
  t.time.setZero(samples);
  t.qpos.resize(2, samples);
  t.qvel.resize(2, samples);
  t.qacc.resize(2, samples);
  t.force.resize(2, samples);
  for (int k = 0; k < samples; ++k) {
    apply(smooth_state(truth, rng, true), data);
    forward(truth, data);
    t.qpos.col(k) = data.qpos;
    t.qvel.col(k) = data.qvel;
    t.qacc.col(k) = data.qacc;
    t.force.col(k) = data.qfrc_actuator + data.qfrc_applied + data.qfrc_constraint;
  }
  const identify::Result r = identify::identify(prior, t);
  REQUIRE(r.not_physical.empty());
  identify::write_model(arm2, identify::identified_model(prior, r), identified_file);

  const MjModelPtr mt = mujoco_load(truth_file), mi = mujoco_load(identified_file);
  const MjDataPtr dt = mujoco_data(mt.get()), di = mujoco_data(mi.get());
  for (int k = 0; k < 50; ++k) {
    const State s = smooth_state(truth, rng, false);
    const Eigen::VectorXd qacc = random_qacc(truth, rng);
    for (mjData* d : {dt.get(), di.get()}) {
      for (int i = 0; i < 2; ++i) {
        d->qpos[i] = s.qpos[i];
        d->qvel[i] = s.qvel[i];
        d->qacc[i] = qacc[i];
      }
    }
    mj_inverse(mt.get(), dt.get());
    mj_inverse(mi.get(), di.get());
    const Eigen::Map<const Eigen::Vector2d> a(dt->qfrc_inverse), b(di->qfrc_inverse);
    // the identified model differs from the truth within the identification's 1e-8 target, so
    // its inverse dynamics can differ by that much, not by the 1e-12 agreement bound
    CHECK((a - b).cwiseAbs().maxCoeff() <= 1e-8 * std::max(1.0, a.cwiseAbs().maxCoeff()));
  }
  std::filesystem::remove(truth_file);
  std::filesystem::remove(identified_file);
}

}  // namespace lever::test
