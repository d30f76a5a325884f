// lever/collision.hpp: which geoms touch, and where (MuJoCo 2.2.2's collision stage).
//
// The narrow phase is one closed-form function per pair of geom types (MuJoCo's
// engine_collision_primitive.c and engine_collision_box.c, reproduced in their decisions: which
// contacts a pair yields and in what order). The driver (collision()) picks the candidate pairs
// as mj_collision does (contype/conaffinity, same and parent body filters, <pair>, <exclude>,
// bounding spheres), calls the narrow phase and mixes the two geoms' contact parameters.
#pragma once

#include <lever/data.hpp>
#include <lever/model.hpp>

namespace lever {

/// Most contacts one call of the narrow phase writes: two boxes, whose clipped polygon MuJoCo
/// 2.2.2 reports before its driver drops repeated positions (up to 16 edge crossings, 4 face
/// corners and 4 box corners; 9 can survive the driver).
inline constexpr int kMaxPairContacts = 24;

/// A geom's shape and world pose, as the narrow phase reads them.
struct GeomShape {
  GeomType type = GeomType::kSphere;
  Eigen::Vector3d size{0, 0, 0};  ///< geom_size
  Eigen::Vector3d pos{0, 0, 0};   ///< geom_xpos
  Mat3 mat = Mat3::Identity();    ///< geom_xmat
};

/// Whether lever has a narrow-phase function for this pair of geom types (either order).
bool has_collision_function(GeomType a, GeomType b);

/// The narrow phase: contacts between two geoms nearer than `margin`. Writes dist, pos and the
/// frame's first row, the normal from g1 to g2, of up to kMaxPairContacts contacts into
/// `contacts` and returns how many. As MuJoCo's pair functions, it leaves the frame's other rows
/// zero, except plane-capsule, which puts the capsule's axis in the second row for the driver to
/// use as the first tangent (collision() completes the frame as mju_makeFrame). As MuJoCo's
/// table, g1's type must not come after g2's (a sphere before a box). Throws ModelError for a
/// pair has_collision_function() rejects, or given in the wrong order.
int collide_shapes(const GeomShape& g1, const GeomShape& g2, double margin, Contact* contacts);

/// The collision stage (MuJoCo's mj_collision): data.ncon and data.contact[0, ncon), in MuJoCo's
/// order, with mixed parameters and complete frames. @pre kinematics().
///
/// A pair of geoms whose types lever has no function for (has_collision_function) that passes the
/// filters and comes within its bounding spheres is skipped and counted in
/// data.warning[Warning::kContactUnsupported] (lastinfo: its first geom). Throws StateError,
/// changing neither data.ncon nor data.contact, when the contacts would exceed model.nconmax
/// (MuJoCo keeps the first nconmax and warns); throws ModelError when the model's contact arrays
/// (geom_condim ... geom_rbound, pair_*, exclude_signature) are missing or their signatures
/// unsorted.
void collision(const Model& model, Data& data);

}  // namespace lever
