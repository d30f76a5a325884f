// lever/diff/runs.hpp: the differential runs: random states, lockstep trajectories, free runs.
#pragma once

#include <cstdint>
#include <lever/diff/report.hpp>
#include <lever/diff/twin.hpp>
#include <string>
#include <vector>

namespace lever::diff {

/// The seed of a model's random states: derived from the file name (test::seed_for).
std::uint64_t default_seed(const std::string& file);

/// Model constants, then `states` random states drawn with `seed` (test::random_state), each
/// compared with compare_state(). A state lever refuses (StateError: more contacts than nconmax,
/// more rows than njmax) is counted as skipped (Report::skip), and the others are compared.
Report random_states(Twin& twin, int states, std::uint64_t seed);

/// MuJoCo against itself: the same file compiled twice, the second time with every world child
/// moved by a fixed offset. The physics is the same (gravity is uniform, nothing touches the
/// world), only the rounding differs. On the same random states as random_states(twin, states,
/// seed), the dynamic quantities of the moved copy (M, qfrc_bias, qacc_smooth, qacc,
/// qfrc_constraint, efc_force) are compared with the original's: the floor under any comparison of
/// two engines. And the original's inverse dynamics at its forward acceleration against the same
/// with that acceleration moved by one ulp (named as compare_state names it): stiff contact rows
/// magnify the last bit of qacc in it. (A floating base's free joint places it whatever its
/// body's offset, so a robot that touches only itself and the floor moves by nothing in the moved
/// copy: its floor is 0 there.)
Report mujoco_self_noise(const Twin& twin, int states, std::uint64_t seed);

/// The quantities mujoco_self_noise() compares, in order.
const std::vector<std::string>& self_noise_quantities();

/// The control a run applies.
enum class Control {
  kZero,    ///< no torque
  kSmooth,  ///< test::smooth_control: sinusoids across each motor's whole span
  kKeep,    ///< ctrl as the start state has it (a keyframe's servo targets), held
};

/// How much a run exercised the limits.
struct RunStats {
  int steps = 0;
  int constrained_steps = 0;  ///< steps that started with at least one limit row (MuJoCo's)
  int max_rows = 0;           ///< most limit rows at once
};

/// From rest (qpos0), `seconds` of `integrator` in lockstep: at each step lever starts from
/// MuJoCo's own state; qacc and qfrc_constraint of the forward pass at that state are compared,
/// then both take one step and qpos, qvel after it are compared. An RK4 step is compared with
/// MuJoCo's step along lever's stage states (lever/diff/rk4.hpp), and the run goes on from
/// MuJoCo's own step (its stages converged as its forward is). The step number is the state.
Report lockstep(Twin& twin, Integrator integrator, double seconds, Control control,
                RunStats* stats = nullptr);

/// lever and MuJoCo each running on its own from rest (qpos0) with the model's integrator,
/// compared at every step (qpos, qvel, qacc, qfrc_constraint, actuator_force). With nudge != 0,
/// a second MuJoCo run starting from the same state with qpos + nudge is compared with the first in the same way:
/// the dynamics' own sensitivity to a last-bit change, the yardstick for lever's difference.
struct FreeRun {
  Report lever_vs_mujoco;
  Report nudged_vs_mujoco;  ///< empty without a nudge
  RunStats stats;
};
FreeRun free_run(Twin& twin, double seconds, Control control, double nudge = 0.0);

/// The quantities a free run compares, in order.
const std::vector<std::string>& free_run_quantities();

}  // namespace lever::diff
