// lever/collision.hpp: which geoms touch, and where (MuJoCo 2.2.2's collision stage).
//
// The narrow phase is one function per pair of geom types, as MuJoCo 2.2.2's table: closed-form
// for the pairs MuJoCo solves in closed form (engine_collision_primitive.c, engine_collision_box.c,
// reproduced in their decisions: which contacts a pair yields and in what order), and for the
// general convex pairs (cylinders, ellipsoids, meshes) the Minkowski portal refinement MuJoCo
// runs (libccd's, written in lever's collision room with libccd's operations in its order) on
// MuJoCo's support functions (engine_collision_convex.c). The driver (collision()) picks the
// candidate pairs as mj_collision does (contype/conaffinity, same and parent body filters, <pair>,
// <exclude>, bounding spheres), calls the narrow phase and mixes the two geoms' contact
// parameters.
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
  double rbound = 0;              ///< geom_rbound (multiccd's and plane-mesh's spacing of contacts)
  /// A mesh's vertices in the geom's frame (kMesh only): mesh_vert from the mesh's address, x y z
  /// per vertex, and its convex hull's graph (mesh_graph from mesh_graphadr; null if it has none,
  /// then the support point is found by visiting every vertex).
  const double* mesh_vert = nullptr;
  int mesh_vertnum = 0;
  const int* mesh_graph = nullptr;
  /// Model::mesh_hull_neighbours from the graph's address (null: the climb reads the neighbours'
  /// points through the graph's vertex list, with the same result)
  const HullNeighbour* mesh_hull = nullptr;
};

/// The general convex pairs' settings (<option mpr_tolerance, mpr_iterations>, <flag multiccd>).
struct ConvexOptions {
  double mpr_tolerance = 1e-6;  ///< MPR's boundary tolerance
  int mpr_iterations = 50;      ///< most MPR iterations
  bool multiccd = false;        ///< MuJoCo 2.2.2's multi-point search (mjENBL_MULTICCD)
};

/// Whether lever has a narrow-phase function for this pair of geom types (either order).
bool has_collision_function(GeomType a, GeomType b);

/// Whether MuJoCo 2.2.2 collides this pair of geom types (either order) by MPR on the two support
/// functions (mjc_Convex): any pair of solids with an ellipsoid, a cylinder or a mesh, but
/// plane-ellipsoid and plane-mesh. lever runs the same search, in every build.
bool collides_by_mpr(GeomType a, GeomType b);

/// The narrow phase: contacts between two geoms nearer than `margin`. Writes dist, pos and the
/// frame's first row, the normal from g1 to g2, of up to kMaxPairContacts contacts into
/// `contacts` and returns how many. As MuJoCo's pair functions, it leaves the frame's other rows
/// zero, except plane-capsule, which puts the capsule's axis in the second row for the driver to
/// use as the first tangent (collision() completes the frame as mju_makeFrame). As MuJoCo's
/// table, g1's type must not come after g2's (a sphere before a box). Throws ModelError for a
/// pair has_collision_function() rejects, or given in the wrong order. `convex` applies to the
/// pairs MuJoCo solves with MPR (mjc_Convex).
int collide_shapes(const GeomShape& g1, const GeomShape& g2, double margin, Contact* contacts,
                   const ConvexOptions& convex = {});

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
