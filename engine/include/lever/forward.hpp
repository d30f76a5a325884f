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
/// the state at the start of the step (for RK4: its last stage), except those nothing in a step
/// reads, which step() does not compute: geom_xpos and geom_xmat when nothing in the model can
/// collide keep the values of the last forward() (or kinematics()). Call forward() to
/// read them at the new state.
void step(const Model& model, Data& data);

/// step() with every output forward() computes, as MuJoCo's mj_step leaves them (xquat and the
/// geom frames included, at the state the step starts from; for RK4 its last stage): for a caller
/// that draws or reads the frames after each step without calling forward() (lever.mujoco's
/// mj_step is this). Its new state is step()'s, bit for bit.
void step_all(const Model& model, Data& data);

/// The first half of a step split around the control (MuJoCo's mj_step1): check qpos and qvel (a
/// bad value resets the state and records a warning, as step() does), then the position and
/// velocity stages of forward(): poses, M, limit rows, passive and bias forces. Between step1 and
/// step2, set data.ctrl or data.qfrc_applied from what step1 computed (qfrc_bias, site_xpos, ...).
void step1(const Model& model, Data& data);

/// The second half (MuJoCo's mj_step2): motors, accelerations, the limit solve, the qacc check,
/// then an Euler step. As in MuJoCo 2.2.2, RK4 models are advanced with Euler here (RK4 needs
/// the controls at the middle of the step); step1 + step2 of an Euler model equals step().
void step2(const Model& model, Data& data);

/// Inverse dynamics (MuJoCo's mj_inverse): the joint force that produces data.qacc at the current
/// qpos/qvel, given passive and limit forces: qfrc_inverse = rnea(qacc) - qfrc_passive -
/// qfrc_constraint, where the limit forces are those implied by qacc.
void inverse(const Model& model, Data& data);

}  // namespace lever
