// The analytic derivatives against finite differences of lever itself, on every model and on
// random trees.
//
// rnea and the step: central differences with h = 1e-5. They err by truncation, h^2/6 |f'''|,
// and rounding, about eps |f| / h (eps = 2.2e-16): with third derivatives of the order of the
// function and of its first derivatives (trigonometric in qpos, quadratic in qvel, linear in
// qacc and ctrl, with qvel up to 2 rad/s), both are about 2e-11 of that magnitude.
//
// qacc (forward): the five-point stencil, f' = [8 (f(x+h) - f(x-h)) - (f(x+2h) - f(x-2h))] / 12h,
// with h = 1e-4. On the random trees the central difference's truncation is too large: their
// light, offset bodies give qacc third derivatives ~1e3 times qacc (its error there shrinks
// exactly as h^2, 1.5e-4 of the scale at h = 1e-3, 1.5e-8 at h = 1e-5). And qacc is solved
// through M, whose condition number reaches 3e4 on these trees, so its rounding exceeds
// eps |f| / h: measured, the stencil errs by up to 1.7e-8 of the scale at h = 1e-5 and 1.4e-9
// at h = 1e-4, where its truncation, h^4/30 |f^(5)|, is ~1e-11.
//
// The bound, 1e-8 of max(1, |f|, |f'|) per column, sits above these errors and far below any
// missing or wrong term (which is of the order of the derivative itself). The
// analytic-against-analytic checks use the project's 1e-12.
#include <catch2/catch.hpp>

#include <lever/derivatives.hpp>
#include <lever/lever.hpp>
#include <lever/mjcf.hpp>
#include <lever/regressor.hpp>

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>
#include <sstream>
#include <string>

#include <lever/harness/tolerance.hpp>
#include "../property/property_models.hpp"
#include "smooth_states.hpp"

namespace lever::test {

namespace {

constexpr double kStep = 1e-5;
constexpr double kFivePointStep = 1e-4;  // qacc: see above
constexpr double kDifferenceBound = 1e-8;
constexpr int kSelfStates = 40;

// The models that cannot make contacts (contacts.cpp tests the others at chosen states, where the
// contacts keep their active set inside the differences).
std::vector<ModelCase> without_contacts(std::vector<ModelCase> cases) {
  std::erase_if(cases, [](const ModelCase& c) { return c.model.contacts_possible; });
  return cases;
}

// Every model without contacts (ball and free joints included), servo_affine.xml (every term of a
// general actuator; tests/derivatives only), the random trees and the random MJCF trees (ball
// joints and free roots).
std::vector<ModelCase> derivative_models() {
  std::vector<ModelCase> cases = without_contacts(every_model());
  const std::string file = model_path("tests/derivatives/servo_affine.xml");
  cases.push_back({"servo_affine.xml", seed_for(file), mjcf::load_file(file)});
  for (ModelCase& c : random_trees()) cases.push_back(std::move(c));
  for (ModelCase& c : random_mjcf_trees()) cases.push_back(std::move(c));
  return cases;
}

// Differences of out() along qpos's tangent: column c moves qpos to qpos (+) t e_c with
// integrate_pos (for a ball, a turn about its body's axis c), as mjd_transitionFD does. Central
// (step kStep), or the five-point stencil (step kFivePointStep) when five_point.
Eigen::MatrixXd tangent_differences(const Model& model, Eigen::Ref<Eigen::VectorXd> qpos,
                                    int n_out, const std::function<void(Eigen::VectorXd&)>& out,
                                    bool five_point = false) {
  const int nv = model.nv;
  const Eigen::VectorXd q0 = qpos;
  const double h = five_point ? kFivePointStep : kStep;
  Eigen::MatrixXd D(n_out, nv);
  Eigen::VectorXd plus(n_out), minus(n_out), plus2(n_out), minus2(n_out);
  const auto at = [&](int c, double t, Eigen::VectorXd& value) {
    qpos = q0;
    integrate_pos(model, qpos, Eigen::VectorXd::Unit(nv, c), t);
    out(value);
  };
  for (int c = 0; c < nv; ++c) {
    at(c, h, plus);
    at(c, -h, minus);
    if (five_point) {
      at(c, 2 * h, plus2);
      at(c, -2 * h, minus2);
      D.col(c) = (8 * (plus - minus) - (plus2 - minus2)) / (12 * h);
    } else {
      D.col(c) = (plus - minus) / (2 * h);
    }
  }
  qpos = q0;
  return D;
}

// Largest |element|.

// Central differences of out(x) (writing into a vector) along each coordinate of x.
Eigen::MatrixXd central_differences(Eigen::Ref<Eigen::VectorXd> x, int n_out,
                                    const std::function<void(Eigen::VectorXd&)>& out) {
  Eigen::MatrixXd D(n_out, x.size());
  Eigen::VectorXd plus(n_out), minus(n_out);
  for (Eigen::Index c = 0; c < x.size(); ++c) {
    const double x0 = x[c];
    x[c] = x0 + kStep;
    out(plus);
    x[c] = x0 - kStep;
    out(minus);
    x[c] = x0;
    D.col(c) = (plus - minus) / (2 * kStep);
  }
  return D;
}

// Five-point differences of out(x) (writing into a vector) along each coordinate of x.
Eigen::MatrixXd five_point_differences(Eigen::Ref<Eigen::VectorXd> x, int n_out,
                                       const std::function<void(Eigen::VectorXd&)>& out) {
  const double h = kFivePointStep;
  Eigen::MatrixXd D(n_out, x.size());
  Eigen::VectorXd plus(n_out), minus(n_out), plus2(n_out), minus2(n_out);
  for (Eigen::Index c = 0; c < x.size(); ++c) {
    const double x0 = x[c];
    x[c] = x0 + h;
    out(plus);
    x[c] = x0 - h;
    out(minus);
    x[c] = x0 + 2 * h;
    out(plus2);
    x[c] = x0 - 2 * h;
    out(minus2);
    x[c] = x0;
    D.col(c) = (8 * (plus - minus) - (plus2 - minus2)) / (12 * h);
  }
  return D;
}

// Every element of the analytic matrix within the bound of the differenced one; the bound's
// scale is max(1, |f|, |f'|) over the whole matrix.
void check_close(const Eigen::MatrixXd& analytic, const Eigen::MatrixXd& differenced,
                 double value_scale, const std::string& what) {
  REQUIRE(analytic.rows() == differenced.rows());
  REQUIRE(analytic.cols() == differenced.cols());
  const double scale = std::max({1.0, value_scale, largest(differenced)});
  for (Eigen::Index r = 0; r < analytic.rows(); ++r) {
    for (Eigen::Index c = 0; c < analytic.cols(); ++c) {
      const double diff = std::abs(analytic(r, c) - differenced(r, c));
      if (!(diff <= kDifferenceBound * scale)) {
        std::ostringstream s;
        s.precision(17);
        s << what << "(" << r << ", " << c << "): analytic " << analytic(r, c) << " vs differenced "
          << differenced(r, c) << " (|diff| " << diff << ", bound " << kDifferenceBound * scale
          << ")";
        FAIL(s.str());
      }
    }
  }
}

// s's quaternions replaced by what an evaluation normalizes them to (kinematics normalizes qpos
// in place, as MuJoCo's does), so that "the state is left as it was" can be asked exactly.
void normalized_as_evaluated(const Model& model, Data& data, State& s) {
  data.qpos = s.qpos;
  kinematics(model, data);
  s.qpos = data.qpos;
}

// The limit rows of the current evaluation, as (joint, side, state) codes: the active set.
std::vector<int> active_set(const Data& data) {
  std::vector<int> rows;
  rows.reserve(static_cast<std::size_t>(data.nefc));
  for (int r = 0; r < data.nefc; ++r) {
    rows.push_back(4 * data.efc_id[r] + (data.efc_sign[r] > 0 ? 0 : 2) +
                   (data.efc_state[r] == ConstraintState::kActive ? 1 : 0));
  }
  return rows;
}

}  // namespace

TEST_CASE("derivatives: d rnea / d qpos and d qvel match central differences",
          "[derivatives][rnea]") {
  for (ModelCase& c : without_contacts(every_model_and_random_trees())) {
    INFO(c.name);
    const Model& model = c.model;
    Data data(model);
    Derivatives deriv(model);
    std::mt19937_64 rng(c.seed);
    Eigen::VectorXd tau(model.nv);
    for (int k = 0; k < kSelfStates; ++k) {
      apply(random_state(model, rng), data);
      const Eigen::VectorXd qacc = random_qacc(model, rng);
      kinematics(model, data);
      rnea_derivatives(model, data, qacc, deriv);
      const Eigen::MatrixXd dq = deriv.dtau_dq, dv = deriv.dtau_dv;
      rnea(model, data, qacc, tau);
      const double tau_scale = largest(tau);

      const auto rnea_at = [&](Eigen::VectorXd& out) {
        kinematics(model, data);
        rnea(model, data, qacc, out);
      };
      check_close(dq, tangent_differences(model, data.qpos, model.nv, rnea_at), tau_scale,
                  "dtau_dq");
      check_close(dv, central_differences(data.qvel, model.nv, rnea_at), tau_scale, "dtau_dv");
    }
  }
}

TEST_CASE("derivatives: d rnea / d qvel is linear in qvel: exact against its own halves",
          "[derivatives][rnea]") {
  // tau is quadratic in qvel, so d tau / d qvel (at qacc = 0, no gravity) is linear in qvel:
  // D(v1 + v2) = D(v1) + D(v2) holds to rounding, a check between analytic results (1e-12).
  for (ModelCase& c : without_contacts(every_model_and_random_trees())) {
    INFO(c.name);
    Model model = c.model;
    model.opt.gravity.setZero();
    Data data(model);
    Derivatives deriv(model);
    std::mt19937_64 rng(c.seed + 1);
    const Eigen::VectorXd zero = Eigen::VectorXd::Zero(model.nv);
    for (int k = 0; k < 10; ++k) {
      apply(random_state(model, rng), data);
      kinematics(model, data);
      const Eigen::VectorXd v1 = data.qvel, v2 = random_qacc(model, rng) / 10;
      data.qvel = v1;
      rnea_derivatives(model, data, zero, deriv);
      const Eigen::MatrixXd D1 = deriv.dtau_dv;
      data.qvel = v2;
      rnea_derivatives(model, data, zero, deriv);
      const Eigen::MatrixXd D2 = deriv.dtau_dv;
      data.qvel = v1 + v2;
      rnea_derivatives(model, data, zero, deriv);
      const Eigen::MatrixXd sum = D1 + D2;
      const double scale = std::max(largest(sum), largest(deriv.dtau_dv));
      CHECK((deriv.dtau_dv - sum).cwiseAbs().maxCoeff() <= allowed(scale));
    }
  }
}

TEST_CASE("derivatives: d qacc / d qpos, d qvel, d ctrl match central differences of forward",
          "[derivatives][forward]") {
  for (ModelCase& c : derivative_models()) {
    INFO(c.name);
    const Model& model = c.model;
    Data data(model);
    Derivatives deriv(model);
    std::mt19937_64 rng(c.seed);
    int compared = 0, with_rows = 0;
    for (int k = 0; k < kSelfStates; ++k) {
      apply(smooth_state(model, rng, true), data);
      forward_derivatives(model, data, deriv);
      const std::vector<int> rows = active_set(data);
      const double acc_scale = largest(data.qacc);
      bool same_rows = true;  // a row switching inside the step is a non-differentiable point
      const auto qacc_at = [&](Eigen::VectorXd& out) {
        forward(model, data);
        same_rows = same_rows && active_set(data) == rows;
        out = data.qacc;
      };
      const Eigen::MatrixXd dq = tangent_differences(model, data.qpos, model.nv, qacc_at, true);
      const Eigen::MatrixXd dv = five_point_differences(data.qvel, model.nv, qacc_at);
      const Eigen::MatrixXd du = five_point_differences(data.ctrl, model.nv, qacc_at);
      if (!same_rows) continue;
      ++compared;
      if (!rows.empty()) ++with_rows;
      check_close(deriv.dqacc_dq, dq, acc_scale, "dqacc_dq");
      check_close(deriv.dqacc_dv, dv, acc_scale, "dqacc_dv");
      check_close(deriv.dqacc_du, du, acc_scale, "dqacc_du");
    }
    CHECK(compared >= kSelfStates * 3 / 4);
    bool limited = false;
    for (int j = 0; j < model.njnt; ++j) limited = limited || model.jnt_limited[j];
    if (limited) CHECK(with_rows > 0);  // the limit rows' terms were exercised
  }
}

TEST_CASE("derivatives: the step's A and B match central differences of step",
          "[derivatives][step]") {
  // also with passive forces, gravity and the ctrl clamp switched off (<option><flag>), which
  // the step's terms honour as forward() does (Euler and implicit: RK4 adds nothing new)
  for (const int flags : {0, kDisablePassive | kDisableGravity | kDisableClampctrl}) {
    for (const Integrator integrator :
         {Integrator::kEuler, Integrator::kRK4, Integrator::kImplicit}) {
      if (flags != 0 && integrator == Integrator::kRK4) continue;
      for (ModelCase& c : derivative_models()) {
        INFO(c.name << " " << integrator_name(integrator) << ", disableflags " << flags);
        Model& model = c.model;
        model.opt.integrator = integrator;
        model.opt.disableflags = flags;
        Data data(model), probe(model);
        Derivatives deriv(model);
        std::mt19937_64 rng(c.seed + 7);
        const int states = states_for(c, kSelfStates);
        int compared = 0;
        for (int k = 0; k < states; ++k) {
          State s = smooth_state(model, rng, true);
          normalized_as_evaluated(model, data, s);
          // a limit row or a clamp switching inside a difference (at any RK4 stage) is a
          // non-differentiable point: such states are not compared
          const bool smooth = differences_see_same_switches(model, probe, s, kStep);
          apply(s, data);
          step_derivatives(model, data, deriv);
          // the state is left as it was
          REQUIRE(data.qpos == s.qpos);
          REQUIRE(data.qvel == s.qvel);
          REQUIRE(data.time == s.time);
          if (!smooth) continue;

          // in mjd_transitionFD's tangent layout: qpos moved by integrate_pos, the next qpos read
          // by differentiate_pos (centred: from the minus side to the plus side, as MuJoCo does)
          const int nv = model.nv, nq = model.nq;
          Eigen::VectorXd qpos = s.qpos, qvel = s.qvel, ctrl = s.ctrl;
          const auto step_from_inputs = [&](Eigen::VectorXd& out) {  // out: [qpos'; qvel'] (nq + nv)
            data.qpos = qpos;
            data.qvel = qvel;
            data.ctrl = ctrl;
            data.time = s.time;
            step(model, data);
            out << data.qpos, data.qvel;
          };
          Eigen::MatrixXd A(2 * nv, 2 * nv), B(2 * nv, model.nu);
          Eigen::VectorXd plus(nq + nv), minus(nq + nv);
          const auto column = [&](Eigen::Ref<Eigen::VectorXd> into) {
            differentiate_pos(model, into.head(nv), 2 * kStep, minus.head(nq), plus.head(nq));
            into.tail(nv) = (plus.tail(nv) - minus.tail(nv)) / (2 * kStep);
          };
          for (int col = 0; col < nv; ++col) {
            for (const double t : {kStep, -kStep}) {
              qpos = s.qpos;
              integrate_pos(model, qpos, Eigen::VectorXd::Unit(nv, col), t);
              step_from_inputs(t > 0 ? plus : minus);
            }
            qpos = s.qpos;
            column(A.col(col));
          }
          for (int col = 0; col < 2 * nv + model.nu; ++col) {
            if (col < nv) continue;
            double& input = col < 2 * nv ? qvel[col - nv] : ctrl[col - 2 * nv];
            const double x0 = input;
            input = x0 + kStep;
            step_from_inputs(plus);
            input = x0 - kStep;
            step_from_inputs(minus);
            input = x0;
            column(col < 2 * nv ? A.col(col) : B.col(col - 2 * nv));
          }
          ++compared;
          const double scale = std::max(largest(s.qpos), largest(s.qvel));
          check_close(deriv.A, A, scale, "A");
          check_close(deriv.B, B, scale, "B");
        }
        CHECK(compared >= states * 3 / 4);
      }
    }
  }
}

TEST_CASE("derivatives: an undamped Euler step's A and B are assembled from d qacc exactly",
          "[derivatives][step]") {
  // x' = [q + h v + h^2 qacc; v + h qacc] without damping: A and B follow from forward's
  // derivatives by arithmetic alone (1e-12).
  Model model = mjcf::load_file(model_path("models/arm2.xml"));
  for (double& b : model.dof_damping) b = 0.0;
  set_const(model);
  Data data(model);
  Derivatives deriv(model);
  std::mt19937_64 rng(3);
  const double h = model.opt.timestep;
  for (int k = 0; k < 20; ++k) {
    apply(smooth_state(model, rng, true), data);
    step_derivatives(model, data, deriv);
    const Eigen::MatrixXd& Dq = deriv.dqacc_dq;
    const int nv = model.nv;
    const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(nv, nv);
    Eigen::MatrixXd A(2 * nv, 2 * nv);
    A << I + h * h * Dq, h * (I + h * deriv.dqacc_dv), h * Dq, I + h * deriv.dqacc_dv;
    CHECK((deriv.A - A).cwiseAbs().maxCoeff() <= allowed(largest(A)));
  }
}

TEST_CASE("derivatives: the implicit step's A and B are Euler's assembly of K^-1 times its terms",
          "[derivatives][step][implicit]") {
  // x' = [q + h v'; v'] with v' = v + h a: A and B follow from d a / d (q, v, u) by arithmetic
  // (1e-12), and d a / d ctrl carries the term of D's dependence on ctrl (an affine gain's
  // gainprm[2] ctrl), which a ctrl column of the step's own differences also shows (above).
  Model model = mjcf::load_file(model_path("tests/derivatives/servo_affine.xml"));
  REQUIRE(model.opt.integrator == Integrator::kImplicit);
  Data data(model);
  Derivatives deriv(model);
  std::mt19937_64 rng(5);
  const double h = model.opt.timestep;
  const int nv = model.nv;
  for (int k = 0; k < 20; ++k) {
    apply(smooth_state(model, rng, false), data);
    step_derivatives(model, data, deriv);
    const auto& w = deriv.work;
    const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(nv, nv);
    // d a / d (qpos, qvel, ctrl), side by side where the step solved them
    const Eigen::MatrixXd Da_q = w.right_hand_sides.leftCols(nv);
    const Eigen::MatrixXd Da_v = w.right_hand_sides.middleCols(nv, nv);
    Eigen::MatrixXd A(2 * nv, 2 * nv);
    A << I + h * h * Da_q, h * (I + h * Da_v), h * Da_q, I + h * Da_v;
    CHECK((deriv.A - A).cwiseAbs().maxCoeff() <= allowed(largest(A)));
    // K a = qfrc_smooth + qfrc_constraint, as the step solves it
    const Eigen::VectorXd f = data.qfrc_smooth + data.qfrc_constraint;
    CHECK((w.K * w.qacc_step - f).cwiseAbs().maxCoeff() <=
          allowed(std::max(largest(f), largest(w.K) * largest(w.qacc_step))));
  }
}

TEST_CASE("derivatives: wrong sizes and unsupported integrators are errors", "[derivatives]") {
  const Model arm2 = mjcf::load_file(model_path("models/arm2.xml"));
  const Model arm3 = mjcf::load_file(model_path("models/arm3.xml"));
  Data data(arm2);
  Derivatives other(arm3);
  CHECK_THROWS_AS(forward_derivatives(arm2, data, other), StateError);
  Derivatives deriv(arm2);
  CHECK_THROWS_AS(rnea_derivatives(arm2, data, Eigen::VectorXd::Zero(5), deriv), StateError);
  Model odd = arm2;
  odd.opt.integrator = static_cast<Integrator>(3);  // MuJoCo 3's implicitfast: not in the enum
  CHECK_THROWS_WITH(step_derivatives(odd, data, deriv), Catch::Contains("not supported yet"));
}

}  // namespace lever::test

namespace lever::test {

TEST_CASE("derivatives: a ball sharing its body is refused, saying why",
          "[derivatives][refusal]") {
  using Catch::Matchers::Contains;
  const auto refused_by_all = [](const Model& model, const std::string& why) {
    Data data(model);
    Derivatives deriv(model);
    const Eigen::VectorXd qacc = Eigen::VectorXd::Zero(model.nv);
    const Eigen::VectorXd qpos = data.qpos;
    CHECK_THROWS_WITH(step_derivatives(model, data, deriv), Contains(why));
    CHECK_THROWS_WITH(forward_derivatives(model, data, deriv), Contains(why));
    CHECK_THROWS_WITH(rnea_derivatives(model, data, qacc, deriv), Contains(why));
    CHECK(data.qpos == qpos);  // nothing done
  };
  // a ball followed by a hinge in one body: the hinge would turn the ball's axes (MuJoCo's cdof)
  refused_by_all(mjcf::load_string(R"(<mujoco><worldbody><body>
      <joint type="ball"/><joint type="hinge" axis="0 1 0"/>
      <geom type="sphere" size=".1" contype="0" conaffinity="0"/></body></worldbody></mujoco>)",
                                   "ball_hinge"),
                 "shares its body with other joints");
  // identification's regressor still covers hinges and slides only
  const Model floating = mjcf::load_file(model_path("tests/models/floating.xml"));
  CHECK_THROWS_WITH(base_parameters(floating, 10, 1), Contains("ball or free joints"));
}

}  // namespace lever::test
