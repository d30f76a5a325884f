// lever/forward.hpp: the whole pipeline, the integrators, and inverse dynamics.
#pragma once

#include <lever/data.hpp>
#include <lever/model.hpp>

namespace lever {

/// Everything at the current state (MuJoCo's mj_forward): kinematics, M and its factor, limit
/// rows, transmission; passive forces, bias, reference accelerations; actuation, qacc_smooth,
/// the constraint solve and qacc. Allocates nothing.
void forward(const Model& model, Data& data);

/// One step of the model's integrator (MuJoCo's mj_step): check the state (a NaN or |x| > 1e10 in
/// qpos/qvel resets it and records a warning), forward(), then semi-implicit Euler with implicit
/// joint damping or RK4, and time += timestep. As in MuJoCo, the outputs left in data describe
/// the state at the start of the step (for RK4: its last stage).
void step(const Model& model, Data& data);

/// Inverse dynamics (MuJoCo's mj_inverse): the joint force that produces data.qacc at the current
/// qpos/qvel, given passive and limit forces: qfrc_inverse = rnea(qacc) - qfrc_passive -
/// qfrc_constraint, where the limit forces are those implied by qacc.
void inverse(const Model& model, Data& data);

}  // namespace lever
