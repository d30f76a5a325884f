// The collision room: the stage MuJoCo 2.2.2's mj_collision runs (driver.cpp: broad phase, pair
// filters, the mid-phase box test, parameter mixing), the narrow phase's closed-form pairs
// (primitive.cpp, box.cpp, and primitive_pairs.hpp / box_pairs.hpp written once on a scalar type,
// narrow_phase.hpp), the general convex pairs by MPR (libccd's search, the one MuJoCo links,
// written on a scalar type in mpr.hpp) with MuJoCo's support functions and multiccd (convex.cpp; its mpr_search writes down the support points for the derivatives),
// MuJoCo's normal correction for round geoms (surface_normal.hpp, on a scalar type too) and the
// constants set_const computes for the stage.
#pragma once

#include <lever/collision.hpp>
#include <lever/data.hpp>
#include <lever/model.hpp>

namespace lever::detail {

/// The collision stage's constants (driver.cpp; set_const computes them once): the broad
/// phase's Model::body_weldid and body_collision, the mid-phase's geom_aabb and the support
/// function's mesh_hull_neighbours.
void build_collision_constants(Model& model);

/// Geom g as the narrow phase takes it: its type, size and bounding radius, its pose in data, a
/// mesh's vertices, hull graph and Model::mesh_hull_neighbours (driver.cpp; the collision stage
/// and the derivatives of its contacts read the same shape).
GeomShape geom_shape(const Model& model, const Data& data, int g);

/// A geom type's name in MJCF (<geom type="...">), for messages.
inline const char* geom_type_name(GeomType t) {
  switch (t) {
    case GeomType::kPlane: return "plane";
    case GeomType::kHfield: return "hfield";
    case GeomType::kSphere: return "sphere";
    case GeomType::kCapsule: return "capsule";
    case GeomType::kEllipsoid: return "ellipsoid";
    case GeomType::kCylinder: return "cylinder";
    case GeomType::kBox: return "box";
    case GeomType::kMesh: return "mesh";
  }
  return "unknown";
}

}  // namespace lever::detail
