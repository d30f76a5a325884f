// lever derivatives: the analytic derivatives of the dynamics and of one step at one state.
//
//   lever derivatives MODEL [--key NAME] [--qpos a,b,..] [--qvel ..] [--ctrl ..] [--settle N]
//                           [--json]
//
// Runs lever::step_derivatives, forward_derivatives and applied_force_derivatives at the state
// (after N steps under the constant ctrl with --settle: a grasp or a resting pose to differentiate
// at); docs/derivatives.md says what each matrix holds. --json: one object with, flattened
// row-major,
//   A          2nv + na square  d [qpos'; qvel'; act'] / d [qpos; qvel; act]  (mjd_transitionFD's
//                               A; with ball or free joints qpos is differenced in its tangent
//                               space, nv numbers; act: the stateful actuators' activations)
//   B          2nv + na x nu    d [qpos'; qvel'; act'] / d ctrl                (mjd_transitionFD's B)
//   dqacc_dq, dqacc_dv (nv x nv), dqacc_du (nv x nu)         forward dynamics
//   dqacc_dact (nv x na)                                      d qacc / d act
//   dqacc_dapplied (nv x nv)                                  d qacc / d qfrc_applied
//   dtau_dq, dtau_dv (nv x nv)                                rnea at qacc
//   M          nv x nv                                        d rnea / d qacc
//   nefc, active_set_changes: the constraint rows at the state (held), and whether their active
//   set changes within the step (then also a warning, exit 1)
// Exit 0; 1 when the evaluation raised an engine warning or gave a number that is not finite;
// bad input exits 2.
#include <cstdio>
#include <string>

#include <lever/derivatives.hpp>
#include <lever/lever.hpp>
#include <lever/mjcf.hpp>

#include "cli.hpp"
#include "commands.hpp"
#include "forward_state.hpp"

namespace lever::cli {

namespace {

void row_major(Json& json, const char* key, const Eigen::MatrixXd& m) {
  json.key(key).begin_array();
  for (Eigen::Index r = 0; r < m.rows(); ++r) {
    for (Eigen::Index c = 0; c < m.cols(); ++c) json.value(m(r, c));
  }
  json.end_array();
}

void print_matrix(const char* title, const Eigen::MatrixXd& m) {
  std::printf("\n%s (%d x %d)\n", title, static_cast<int>(m.rows()), static_cast<int>(m.cols()));
  for (Eigen::Index r = 0; r < m.rows(); ++r) {
    std::printf(" ");
    for (Eigen::Index c = 0; c < m.cols(); ++c) std::printf(" %12s", num(m(r, c)).c_str());
    std::printf("\n");
  }
}

}  // namespace

void declare_derivatives(CLI::App& command) {
  command.add_option("MODEL", "the model file (MJCF)")->type_name("FILE")->required();
  add_state_options(command,
                    {"start from keyframe NAME (its qpos, qvel, ctrl; the lists below override)",
                     "joint positions, nq numbers (default: qpos0)",
                     "joint velocities, nv numbers (default: zeros)",
                     "actuator commands, nu numbers (default: zeros)"});
  add_value(command, "settle", "N",
            "first take N steps under the constant ctrl, then differentiate there\n"
            "(a grasp, a pose resting on contacts; default 0)")
      ->check(whole_number_check());
  add_switch(command, "json",
             "one JSON object: A, B (the step's Jacobians, mjd_transitionFD's layout),\n"
             "dqacc_dq, dqacc_dv, dqacc_du, dqacc_dact, dqacc_dapplied, dtau_dq, dtau_dv,\n"
             "M (row-major, flattened)");
  command.footer(
      "Exit status: 0; 1 when the engine warned or a number came out non-finite; 2 for bad input.");
}

int cmd_derivatives(const Args& command_line) {
  const auto [args, path, model] = begin("derivatives", command_line);
  Data data(model);
  Derivatives deriv(model);
  set_state_from_args(args, model, data);
  constexpr long kMaxSettle = 10'000'000;  // as lever simulate's bound on one run
  const long settle = args.has("settle") ? args.get_long("settle", 0) : 0;
  if (settle < 0 || settle > kMaxSettle) {
    throw UsageError{"--settle must be between 0 and " + std::to_string(kMaxSettle) + " steps"};
  }
  for (long k = 0; k < settle; ++k) step(model, data);
  step_derivatives(model, data, deriv);
  // RK4 leaves its last stage's forward derivatives: those of the state itself instead
  if (model.opt.integrator == Integrator::kRK4) {
    const Eigen::VectorXd qpos = data.qpos;  // forward() normalizes its quaternions
    forward_derivatives(model, data, deriv);
    data.qpos = qpos;
  }
  applied_force_derivatives(model, data, deriv);

  if (args.has("json")) {
    Json json(stdout);
    json.begin_object();
    json.key("model").value(model.name);
    json.key("nv").value(model.nv);
    json.key("nu").value(model.nu);
    json.key("integrator").value(integrator_name(model.opt.integrator));
    json.key("timestep").value(model.opt.timestep);
    json.key("qpos").values(data.qpos);
    json.key("qvel").values(data.qvel);
    json.key("ctrl").values(data.ctrl);
    json.key("nefc").value(data.nefc);
    json.key("active_set_changes").value(deriv.active_set_changes);
    row_major(json, "A", deriv.A);
    row_major(json, "B", deriv.B);
    row_major(json, "dqacc_dq", deriv.dqacc_dq);
    row_major(json, "dqacc_dv", deriv.dqacc_dv);
    row_major(json, "dqacc_du", deriv.dqacc_du);
    row_major(json, "dqacc_dact", deriv.dqacc_dact);
    row_major(json, "dqacc_dapplied", deriv.dqacc_dapplied);
    row_major(json, "dtau_dq", deriv.dtau_dq);
    row_major(json, "dtau_dv", deriv.dtau_dv);
    row_major(json, "M", data.M);
    json.end_object();
    json.newline();
  } else {
    std::printf("model %s (%s), %s integrator, timestep %g s\n", model.name.c_str(), path.c_str(),
                integrator_name(model.opt.integrator), model.opt.timestep);
    std::printf("state: qpos %s qvel %s ctrl %s\n", vec_text(data.qpos).c_str(),
                vec_text(data.qvel).c_str(), vec_text(data.ctrl).c_str());
    int limits = 0, contact_rows = 0, pushing = 0;
    for (int r = 0; r < data.nefc; ++r) {
      const bool limit = data.efc_type[r] == ConstraintType::kLimitJoint;
      limits += limit;
      contact_rows += !limit;
      pushing += !limit && data.efc_state[r] != ConstraintState::kSatisfied;
    }
    std::printf(
        "constraint rows: %d limit, %d contact (%d pushing), their active set held fixed%s\n",
        limits, contact_rows, pushing,
        deriv.active_set_changes ? "; the set changes within the step (see the warning)" : "");
    // with quaternions (ball, free joints) a position is differenced in its tangent space, nv
    // numbers (mj_differentiatePos), as mjd_transitionFD does
    const bool tangent = model.nq != model.nv;
    const std::string q = tangent ? "dq" : "qpos";
    if (tangent) {
      std::printf(
          "dq: a change of qpos in its tangent space (nv = %d numbers, as "
          "mj_differentiatePos gives it)\n",
          model.nv);
    }
    const std::string act = model.na > 0 ? "; act" : "";
    print_matrix(("A = d [" + q + "'; qvel'" + act + "'] / d [" + q + "; qvel" + act + "]").c_str(),
                 deriv.A);
    print_matrix(("B = d [" + q + "'; qvel'" + act + "'] / d ctrl").c_str(), deriv.B);
    print_matrix(("d qacc / d " + q).c_str(), deriv.dqacc_dq);
    print_matrix("d qacc / d qvel", deriv.dqacc_dv);
    print_matrix("d qacc / d ctrl (0 where a clamp binds)", deriv.dqacc_du);
    if (model.na > 0) print_matrix("d qacc / d act", deriv.dqacc_dact);
    print_matrix("d qacc / d qfrc_applied", deriv.dqacc_dapplied);
    print_matrix(("d rnea / d " + q + " at qacc").c_str(), deriv.dtau_dq);
    print_matrix("d rnea / d qvel at qacc", deriv.dtau_dv);
  }
  WarningLog warnings;
  warnings.collect(data);
  print_warnings("derivatives", warnings);
  const bool finite = deriv.A.allFinite() && deriv.B.allFinite();
  if (!finite) print_non_finite("derivatives");
  return warnings.count() > 0 || !finite ? kFindings : kOk;
}

}  // namespace lever::cli
