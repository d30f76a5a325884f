// lever/diff/compare.hpp: every quantity lever shares with MuJoCo, compared at one state.
//
// Forward outputs (every array of Data's field table, lever/fields.hpp, that MuJoCo has and
// forward() writes, found in mjData by name; M through mj_fullM; the limit rows when they are the
// same rows), site Jacobians, energy, inverse dynamics, and one step of each integrator. Each
// function leaves both engines evaluated at the state it was given.
#pragma once

#include <Eigen/Core>
#include <lever/diff/report.hpp>
#include <lever/diff/twin.hpp>

namespace lever::diff {

/// Labels element i of a qpos-sized array: "qpos 7 (joint 'ball' #1, coordinate 0)".
Labeler per_coordinate(const Model& model);

/// set_const's model constants: dof_invweight0, dof_M0, body_invweight0, body_subtreemass.
void compare_model_constants(const Twin& twin, Report& report);

/// Run forward on both at s and compare every forward output, the energy and the site
/// Jacobians, under state number k.
void compare_forward(Twin& twin, const test::State& s, int k, Report& report);

/// Inverse dynamics on both at s with the same qacc; `label` says which qacc it is.
void compare_inverse(Twin& twin, const test::State& s, const Eigen::VectorXd& qacc,
                     const std::string& label, int k, Report& report);

/// One step of `integrator` on both from s: qpos, qvel and time after it; for RK4 also each
/// later stage's qvel and qacc, MuJoCo's stages evaluated at lever's stage states
/// (lever/diff/rk4.hpp).
void compare_step(Twin& twin, const test::State& s, Integrator integrator, int k, Report& report);

/// All of the above at one state: forward, inverse at the forward solution and at
/// `random_qacc`, and one Euler and one RK4 step.
void compare_state(Twin& twin, const test::State& s, const Eigen::VectorXd& random_qacc, int k,
                   Report& report);

}  // namespace lever::diff
