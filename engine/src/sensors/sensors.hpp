// The sensors room: MuJoCo 2.2.2's sensor stages (engine_sensor.c) and what they need that the
// pipeline does not compute otherwise. sensors.cpp evaluates each stage's sensors after that
// stage (position, velocity, acceleration), then adds their noise and clips them at their
// cutoff; post_constraint.cpp holds the forces inside the tree after the constraint solve
// (MuJoCo's mj_rnePostConstraint: cacc, cfrc_int, cfrc_ext) and the subtrees' momenta (its
// mj_subtreeVel); ray.cpp casts rays against geoms (its engine_ray.c), for the rangefinder and
// the touch sensor's zone. A model without sensors costs one comparison per stage.
#pragma once

#include <Eigen/Core>

#include <lever/data.hpp>
#include <lever/model.hpp>

namespace lever {

// ---- the stages (sensors.cpp) -------------------------------------------------------------------
/// The sensors whose stage is the position stage (MuJoCo's mj_sensorPos); after the position
/// stage (kinematics, contacts, constraint rows, transmission).
void sensor_position(const Model& model, Data& data);
/// The velocity stage's sensors (mj_sensorVel); after the velocity stage.
void sensor_velocity(const Model& model, Data& data);
/// The acceleration stage's sensors (mj_sensorAcc); after the constraint solve. Computes cacc,
/// cfrc_int and cfrc_ext first when one of them needs it.
void sensor_acceleration(const Model& model, Data& data);

// ---- the forces inside the tree (post_constraint.cpp) ------------------------------------------
/// cacc (each body's acceleration, gravity as the world's -g), cfrc_ext (the contacts' forces on
/// each body, about the subtree's centre of mass) and cfrc_int (what each body's parent exerts
/// on its subtree), from qacc, the velocities and efc_force (MuJoCo's mj_rnePostConstraint).
void rne_post_constraint(const Model& model, Data& data);

/// subtree_linvel (each subtree's centre-of-mass velocity) and subtree_angmom (its angular
/// momentum about its centre of mass) (MuJoCo's mj_subtreeVel).
void subtree_velocities(const Model& model, Data& data);

// ---- rays (ray.cpp) ------------------------------------------------------------------------------
/// Distance along vec (a unit vector, or any: distances are in its lengths) from pnt to the
/// surface of a shape of `type` at pos with rotation R and MuJoCo's size, -1 if the ray misses it
/// (MuJoCo's mju_rayGeom). type: plane, sphere, capsule, ellipsoid, cylinder or box.
double ray_shape(const Eigen::Vector3d& pos, const Mat3& R, const Eigen::Vector3d& size,
                 const Eigen::Vector3d& pnt, const Eigen::Vector3d& vec, GeomType type);

/// Distance along vec from pnt to mesh geom g's triangles, -1 if the ray meets none (MuJoCo's
/// mj_rayMesh: its bounding box first, then every triangle).
double ray_mesh(const Model& model, const Data& data, int g, const Eigen::Vector3d& pnt,
                const Eigen::Vector3d& vec);

/// The nearest geom a ray from pnt along vec meets, the geoms of body `exclude_body` and
/// invisible ones (rgba alpha 0) left out (MuJoCo's mj_ray with every group and static geoms):
/// its distance in lengths of vec, -1 if none; *geom its id (-1).
double ray(const Model& model, const Data& data, const Eigen::Vector3d& pnt,
           const Eigen::Vector3d& vec, int exclude_body, int* geom);

}  // namespace lever
