// The forces inside the tree once the constraint forces are known (MuJoCo 2.2.2's
// mj_rnePostConstraint), and the subtrees' momenta (its mj_subtreeVel): what the force, torque,
// accelerometer, frame acceleration and subtree velocity sensors read. Spatial vectors are in
// the c-frame (world axes, origin at the subtree root's centre of mass), [angular; linear].
#include <algorithm>

#include "basics/basics.hpp"
#include "sensors/sensors.hpp"

namespace lever {

namespace {

using Eigen::Vector3d;

// A force (torque about `from`; force) as the same force about `to`: the torque gains
// (from - to) x force.
Force force_about(const Force& f, const Vector3d& from, const Vector3d& to) {
  Force out = f;
  out.head<3>() -= cross(to - from, f.tail<3>());
  return out;
}

// Contact i's force and torque in world axes, [torque; force], from its rows' forces: the
// normal force, then friction along the tangents (a pyramid's edges decoded, as
// lever::contact_force does), then torsion and rolling torques, turned out of the contact frame.
Force contact_wrench(const Data& data, const Contact& contact) {
  double local[6] = {0, 0, 0, 0, 0, 0};
  const double* f = data.efc_force.data() + contact.efc_address;
  if (data.efc_type[contact.efc_address] == ConstraintType::kContactPyramidal) {
    const int tangents = contact.dim - 1;
    for (int k = 0; k < 2 * tangents; ++k) local[0] += f[k];
    for (int k = 0; k < tangents; ++k)
      local[1 + k] = (f[2 * k] - f[2 * k + 1]) * contact.friction[k];
  } else {
    for (int k = 0; k < contact.dim; ++k) local[k] = f[k];
  }
  // the frame's rows are its axes: a vector's world form is frame^T times its coordinates
  Force wrench;
  wrench.head<3>() = rotate_back(contact.frame, Vector3d(local[3], local[4], local[5]));
  wrench.tail<3>() = rotate_back(contact.frame, Vector3d(local[0], local[1], local[2]));
  return wrench;
}

// A point given in body b's frame, in world coordinates (MuJoCo's mj_local2Global, summed in its
// order).
Vector3d point_on_body(const Data& data, int b, const double* local) {
  const Mat3& R = data.xmat[b];
  Vector3d p;
  for (int r = 0; r < 3; ++r) {
    p[r] = (R(r, 0) * local[0] + R(r, 1) * local[1] + R(r, 2) * local[2]) + data.xpos[b][r];
  }
  return p;
}

// The equality rows' forces on their bodies, added to cfrc_ext as MuJoCo 2.2.2 adds them: a
// connect's three rows are a force in world axes, a weld's six a force and a torque, acting at
// the constraint's point on each body, body 1 with the rows' sign and body 2 against it (the
// opposite of a contact's convention). A joint coupling moves no body directly.
void add_equality_forces(const Model& model, Data& data) {
  int row = 0;
  while (row < data.ne) {
    const int id = data.efc_id[row];
    const EqualityType type = model.eq_type[id];
    if (type == EqualityType::kJoint) {
      ++row;
      continue;
    }
    const bool weld = type == EqualityType::kWeld;
    const double* f = data.efc_force.data() + row;
    Force wrench;  // [torque; force]
    wrench.tail<3>() = Vector3d(f[0], f[1], f[2]);
    wrench.head<3>() = weld ? Vector3d(f[3], f[4], f[5]) : Vector3d::Zero();
    const double* anchors = model.eq_data[id].data();
    // connect: body 1's anchor first; weld: body 2's (see kEqualityData)
    const double* on_body1 = anchors + (weld ? 3 : 0);
    const double* on_body2 = anchors + (weld ? 0 : 3);
    if (const int b1 = model.eq_obj1id[id]; b1 != 0) {
      data.cfrc_ext[b1] += force_about(wrench, point_on_body(data, b1, on_body1),
                                       data.subtree_com[model.body_rootid[b1]]);
    }
    if (const int b2 = model.eq_obj2id[id]; b2 != 0) {
      data.cfrc_ext[b2] -= force_about(wrench, point_on_body(data, b2, on_body2),
                                       data.subtree_com[model.body_rootid[b2]]);
    }
    row += weld ? 6 : 3;
  }
}

}  // namespace

void rne_post_constraint(const Model& model, Data& data) {
  const int nbody = model.nbody;

  // external forces: each contact pushes geom2's body along its normal and geom1's body back
  for (Force& f : data.cfrc_ext) f.setZero();
  for (int i = 0; i < data.ncon; ++i) {
    const Contact& contact = data.contact[i];
    if (contact.efc_address < 0) continue;
    const Force wrench = contact_wrench(data, contact);
    const int body1 = model.geom_bodyid[contact.geom1], body2 = model.geom_bodyid[contact.geom2];
    if (body1 != 0) {
      data.cfrc_ext[body1] -=
          force_about(wrench, contact.pos, data.subtree_com[model.body_rootid[body1]]);
    }
    if (body2 != 0) {
      data.cfrc_ext[body2] +=
          force_about(wrench, contact.pos, data.subtree_com[model.body_rootid[body2]]);
    }
  }
  add_equality_forces(model, data);

  // down the tree: each body's acceleration (the world's is -g, so that gravity is felt as an
  // upward acceleration), the net force that takes, and the parent's share of it
  data.cacc[0].setZero();
  if (!model.opt.disabled(kDisableGravity)) data.cacc[0].tail<3>() = -model.opt.gravity;
  data.cfrc_int[0].setZero();
  for (int b = 1; b < nbody; ++b) {
    const int first = model.body_dofadr[b], n = model.body_dofnum[b];
    Motion velocity_term = Motion::Zero(), joint_term = Motion::Zero();
    for (int k = first; k < first + n; ++k) {
      velocity_term += data.cdof_dot[k] * data.qvel[k];
      joint_term += data.cdof[k] * data.qacc[k];
    }
    data.cacc[b] = data.cacc[model.body_parentid[b]] + velocity_term;
    data.cacc[b] += joint_term;
    const RigidInertia& I = data.cinert[b];
    const Force net = I * data.cacc[b] + cross_force(data.cvel[b], I * data.cvel[b]);
    data.cfrc_int[b] = net - data.cfrc_ext[b];
  }

  // up the tree: a body's parent also carries everything below it
  for (int b = nbody - 1; b > 0; --b) data.cfrc_int[model.body_parentid[b]] += data.cfrc_int[b];
}

void subtree_velocities(const Model& model, Data& data) {
  const int nbody = model.nbody;
  auto& body_vel = data.work.body_vel;

  // each body alone: its centre of mass's velocity, its momentum, its spin about its centre
  for (int b = 0; b < nbody; ++b) {
    const Motion& v = data.cvel[b];
    const Vector3d offset = data.xipos[b] - data.subtree_com[model.body_rootid[b]];
    body_vel[b].head<3>() = v.head<3>();
    body_vel[b].tail<3>() = v.tail<3>() - cross(offset, v.head<3>());
    data.subtree_linvel[b] = model.body_mass[b] * body_vel[b].tail<3>();
    // I w with I = R diag(inertia) R^T, R the principal axes
    Vector3d w = rotate_back(data.ximat[b], body_vel[b].head<3>());
    w = w.cwiseProduct(model.body_inertia[b]);
    data.subtree_angmom[b] = rotate(data.ximat[b], w);
  }

  // momenta summed up the tree, then divided by each subtree's mass
  for (int b = nbody - 1; b >= 0; --b) {
    if (b > 0) data.subtree_linvel[model.body_parentid[b]] += data.subtree_linvel[b];
    data.subtree_linvel[b] /= std::max(detail::kMinVal, model.body_subtreemass[b]);
  }

  // angular momenta about each subtree's centre of mass: the body's own spin, its centre of
  // mass's motion about the subtree's, and each child subtree's, moved to the parent's centre
  for (int b = nbody - 1; b > 0; --b) {
    const int parent = model.body_parentid[b];
    const Vector3d own = model.body_mass[b] * (body_vel[b].tail<3>() - data.subtree_linvel[b]);
    data.subtree_angmom[b] += cross(data.xipos[b] - data.subtree_com[b], own);
    data.subtree_angmom[parent] += data.subtree_angmom[b];
    const Vector3d relative =
        model.body_subtreemass[b] * (data.subtree_linvel[b] - data.subtree_linvel[parent]);
    data.subtree_angmom[parent] += cross(data.subtree_com[b] - data.subtree_com[parent], relative);
  }
}

}  // namespace lever
