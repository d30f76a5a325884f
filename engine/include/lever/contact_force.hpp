// lever/contact_force.hpp: a contact's force in its own frame (MuJoCo 2.2.2's mj_contactForce).
//
// The solver's unknowns for a contact are its rows' forces (efc_force from contact.efc_address):
// for a pyramidal cone, 2 (dim - 1) edge forces, each pushing along the normal and along plus or
// minus one friction direction; for an elliptic cone or a frictionless contact, the components
// themselves. contact_force() turns them into what a user reads: the normal force, then the
// friction forces (and torsional and rolling torques for condim 4 and 6) along the contact frame's
// axes. Shared by the command line, the Python package and the browser build.
#pragma once

#include <Eigen/Core>

#include <lever/data.hpp>
#include <lever/model.hpp>

namespace lever {

/// Contact `id`'s force in its frame (data.contact[id].frame: normal, tangent 1, tangent 2):
/// [normal, tangent 1, tangent 2, torsion, roll 1, roll 2], the entries past contact.dim zero, as
/// mj_contactForce. A positive normal force pushes the two geoms apart (the frame's normal points
/// from geom1 into geom2). A contact without rows (contact.exclude: beyond its margin,
/// within the gap) has zero force. @pre forward() (or the acceleration stage) has run.
///
/// Throws StateError if `id` is not in [0, data.ncon) or the data does not fit the model (MuJoCo
/// returns zeros for a bad id; lever says so instead).
Eigen::Matrix<double, 6, 1> contact_force(const Model& model, const Data& data, int id);

}  // namespace lever
