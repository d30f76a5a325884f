// Shared by the diff tests: which paths are compared, and how a report becomes assertions.
#pragma once

#include <algorithm>
#include <catch2/catch.hpp>
#include <cstdint>
#include <filesystem>
#include <lever/diff/report.hpp>
#include <lever/diff/runs.hpp>
#include <lever/diff/twin.hpp>
#include <string>
#include <vector>

#include <lever/forward.hpp>
#include <lever/harness/random_state.hpp>
#include <lever/harness/tolerance.hpp>
#include <random>

namespace lever::test {

/// Both paths for every model: (a) lever's own loader, what users get, and (b) MuJoCo's compiled
/// parameters copied into lever, the engine alone.
inline std::vector<diff::Path> paths_to_compare() {
  return {diff::Path::kLoader, diff::Path::kEngine};
}

/// "arm2.xml, loader path, seed 123": enough to rerun one case with `lever diff`.
inline std::string context(const std::string& file, diff::Path path, std::uint64_t seed) {
  return std::filesystem::path(file).filename().string() + ", " + diff::path_name(path) +
         " path, seed " + std::to_string(seed);
}

/// One assertion per quantity: its worst value within the bound. On failure the message names
/// the state, the quantity, the element and both values, and lists the first values beyond the
/// bound (the caller's INFO names the model, path and seed). `only` restricts the check to some
/// quantities. A quantity's bound is 1e-12, or 1e-10 for what the constraint solver decides in
/// a model with contacts (diff::kContactSolverBound, set by the report's run).
inline void check_within_bound(const diff::Report& report,
                               const std::vector<std::string>& only = {}) {
  for (const diff::Extreme& e : report.quantities()) {
    const bool wanted =
        only.empty() || std::find(only.begin(), only.end(), e.quantity) != only.end();
    if (!wanted) continue;
    INFO("state " << e.state << ": " << e.quantity << "[" << e.index << "] [" << e.element
                  << "]: lever " << e.lever << " vs mujoco " << e.mujoco << ", " << e.max_ratio
                  << " of the bound (element-wise " << e.max_elementwise_ratio << "); " << e.beyond
                  << " of " << e.compared << " values beyond the bound");
    std::string first_failures;
    int listed = 0;
    for (const std::string& f : report.failures()) {
      const bool this_quantity = f.find(": " + e.quantity + "[") != std::string::npos;
      if (this_quantity && !e.pass() && listed++ < 5) first_failures += "\n  " + f;
    }
    INFO("first values beyond the bound:" << first_failures);
    CHECK(e.max_ratio <= e.bound);
  }
}

/// A free run's quantities held to MuJoCo's own sensitivity: lever may differ from MuJoCo up to
/// `generosity` times MuJoCo's difference from itself started 1e-15 away (plus the bound), since
/// an unstable or chaotic stretch can amplify one last-bit difference more than the other; a
/// wrong term would show up as O(1) differences, far beyond it.
inline void check_near_noise_floor(const diff::FreeRun& run,
                                   const std::vector<std::string>& quantities,
                                   double generosity = 100.0) {
  for (const std::string& q : quantities) {
    const diff::Extreme* ours = run.lever_vs_mujoco.find(q);
    const diff::Extreme* noise = run.nudged_vs_mujoco.find(q);
    REQUIRE(ours);
    REQUIRE(noise);
    INFO(q << ": lever differs by " << ours->max_abs_diff << ", MuJoCo from itself by "
           << noise->max_abs_diff << " (largest |value| " << ours->max_abs_mujoco << ")");
    CHECK(ours->max_abs_diff <= generosity * (noise->max_abs_diff + allowed(ours->max_abs_mujoco)));
  }
}

/// Every integrator lever has, in MuJoCo's numbering.
inline constexpr Integrator kEveryIntegrator[] = {Integrator::kEuler, Integrator::kRK4,
                                                  Integrator::kImplicit};

/// The model run from its initial state with smooth controls for `seconds` by each integrator in
/// lockstep with MuJoCo (a fresh twin each): every quantity within the bound at every step.
inline void check_lockstep_every_integrator(const std::string& file, diff::Path path,
                                            double seconds) {
  for (const Integrator integrator : kEveryIntegrator) {
    INFO(context(file, path, 0) << ", " << integrator_name(integrator));
    diff::Twin twin(file, path);
    check_within_bound(diff::lockstep(twin, integrator, seconds, diff::Control::kSmooth));
  }
}

/// The same run free (each engine on its own states, the model's integrator) held to MuJoCo's
/// sensitivity, as check_near_noise_floor says.
inline void check_free_run(const std::string& file, diff::Path path, double seconds) {
  INFO(context(file, path, 0) << ", free run");
  diff::Twin twin(file, path);
  const diff::FreeRun run = diff::free_run(twin, seconds, diff::Control::kSmooth, 1e-15);
  check_near_noise_floor(run, diff::free_run_quantities());
}

// Inverse dynamics at the forward acceleration: M qacc + bias - passive - J^T f(qacc) returns
// qfrc_applied + qfrc_actuator, 0 on a dof nothing drives, by cancelling the constraint forces. Two
// engines' roundings of that cancellation differ by 1e-12 of the forces cancelled, not of the
// result (MuJoCo's own values on the free base of equality.xml are 1e-11 where the exact answer is
// 0, ten times the bound of the result's magnitude 2). Held here to 1e-12 of the cancelled
// constraint forces' magnitude, on the same states as random_states(twin, states, seed).
inline void inverse_at_forward_agrees(diff::Twin& twin, int states, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  const int nv = twin.model.nv;
  double worst = 0.0;
  for (int k = 0; k < states; ++k) {
    const State s = random_state(twin.model, rng);
    random_qacc(twin.model, rng);  // drawn as random_states draws it, to keep the same states
    twin.set_state(s);
    forward(twin.model, twin.data);
    twin.mujoco_forward();
    const double cancelled =
        magnitude(twin.data.qfrc_constraint.data(), nv) + magnitude(twin.d->qfrc_constraint, nv);
    for (int i = 0; i < nv; ++i) twin.data.qacc[i] = twin.d->qacc[i];
    inverse(twin.model, twin.data);
    mj_inverse(twin.m.get(), twin.d.get());
    for (int i = 0; i < nv; ++i) {
      worst = std::max(worst, std::abs(twin.data.qfrc_inverse[i] - twin.d->qfrc_inverse[i]) /
                                  allowed(cancelled));
    }
  }
  INFO("worst difference " << worst << " of 1e-12 of the cancelled constraint forces");
  CHECK(worst <= 1.0);
}

/// Every quantity of a random-states report but the inverse dynamics at the forward acceleration
/// (held by inverse_at_forward_agrees instead, in models with equality constraints).
inline std::vector<std::string> all_but_inverse_at_forward(const diff::Report& report) {
  std::vector<std::string> quantities;
  for (const diff::Extreme& e : report.quantities()) {
    if (e.quantity != "qfrc_inverse (at the forward qacc)") quantities.push_back(e.quantity);
  }
  return quantities;
}

/// Whether a model has any limited joint (so its runs must produce limit rows).
inline bool has_limits(const Model& model) {
  return std::any_of(model.jnt_limited.begin(), model.jnt_limited.end(), [](bool b) { return b; });
}

}  // namespace lever::test
