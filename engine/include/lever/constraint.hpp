// lever/constraint.hpp: MuJoCo 2.2.2's soft joint limits and contacts.
//
// A limited joint within `margin` of a stop gets one constraint row; a contact one (frictionless),
// 2 (condim - 1) (pyramidal cone) or condim (elliptic cone) rows. A limit's impedance comes from
// solimplimit, its reference acceleration from solreflimit, its regularizer from dof_invweight0
// (frozen at qpos0 by set_const()); a contact's from its solref, solimp and body_invweight0. The
// rows are solved to the unique minimizer MuJoCo's Newton solver converges to (docs/contact.md).
#pragma once

#include <lever/data.hpp>
#include <lever/model.hpp>

namespace lever {

/// Instantiate the limit and contact rows at data.qpos with their impedance, R, D, K, B (MuJoCo's
/// mj_makeConstraint). @pre kinematics().
void make_constraint(const Model& model, Data& data);

/// efc_vel and efc_aref at data.qvel (MuJoCo's mj_referenceConstraint).
void reference_constraint(const Model& model, Data& data);

/// Solve the rows: efc_force, efc_state, qfrc_constraint and qacc (MuJoCo's mj_fwdConstraint);
/// qacc_warmstart = qacc afterwards, where the next PGS solve starts.
/// @pre qfrc_smooth, qacc_smooth, efc_aref, M and its factor are current.
void solve_constraint(const Model& model, Data& data);

}  // namespace lever
