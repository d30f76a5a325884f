// Mesh files and the mass properties of a mesh, as MuJoCo 2.2.2's compiler computes them
// (user_mesh.cc: mjCMesh::LoadSTL, LoadOBJ, Process; user_objects.cc: mjCGeom::Compile,
// GetVolume, SetInertia). lever reads a mesh file only when a mesh geom must give its body mass.
//
// MuJoCo keeps vertices as 32-bit floats and does part of the arithmetic in float (face centres,
// edge vectors, the products of inertia, the re-centring); the code here keeps every such
// rounding, because the compiled numbers must agree with MuJoCo's to the last bits.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include "spec.hpp"

namespace lever::mjcf::detail {

/// A mesh file (or its contents) that cannot be used; the message names what is wrong, the
/// caller adds where.
struct MeshError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Triangles as MuJoCo 2.2.2 holds them after reading a file: float vertices and vertex indices.
struct TriangleMesh {
  std::vector<float> vert;  ///< x y z per vertex
  std::vector<int> face;    ///< three vertex indices per triangle
  bool consistent = true;   ///< false if two faces share a directed edge (OBJ only, as MuJoCo)
};

/// Binary STL, as MuJoCo 2.2.2 reads it (it reads no ASCII STL). `righthand` is false when the
/// mesh scale mirrors it: then each triangle's last two vertices swap. Repeated vertices are
/// merged as MuJoCo merges them (mjCMesh::RemoveRepeated), so that the vertex list is MuJoCo's.
TriangleMesh read_stl(const std::string& bytes, bool righthand);

/// Wavefront OBJ: `v` and `f` lines (triangles and convex quadrilaterals), numbers read as
/// tinyobjloader reads them in MuJoCo 2.2.2.
TriangleMesh read_obj(const std::string& text, bool righthand);

/// What a mesh geom takes from its mesh (MuJoCo's "volume" mesh): the frame of the mesh's centre
/// of mass and principal axes in the mesh file's frame, the half-sizes of the box with the same
/// inertia, the volume and the half-sizes of the bounding box in the principal frame.
struct MeshMass {
  Vec3 pos{};
  Quat quat{1, 0, 0, 0};
  Vec3 box{};
  double volume = 0;
  Vec3 aabb{};
  /// the shell's (MuJoCo's surface mesh, for shellinertia): the frame of its centre and principal
  /// axes, computed in the volume's principal frame as MuJoCo does, its inertia box and its area
  Vec3 shell_pos{};
  Quat shell_quat{1, 0, 0, 0};
  Vec3 shell_box{};
  double surface = 0;
  /// what collision reads (MuJoCo's mesh_vert and mesh_graph): the vertices in the principal
  /// frame, x y z per vertex, and the convex hull's graph (empty when none was asked for)
  std::vector<float> vert;
  std::vector<int> graph;
  /// its triangles, three vertex numbers each (MuJoCo's mesh_face: what a ray meets)
  std::vector<int> face;
};

/// The graph of the convex hull of the vertices (x y z per vertex) that MuJoCo 2.2.2 builds with
/// qhull (mjCMesh::MakeGraph, options "Qt", triangulated): numvert, numface, each hull vertex's
/// neighbour-list address, its vertex index, the neighbour lists (hull-local indices, each ended
/// by -1) and the triangles (vertex indices). Empty for fewer than 4 vertices. Throws MeshError
/// when qhull fails (MuJoCo: "qhull error"); the build without qhull always throws.
std::vector<int> convex_hull_graph(const std::vector<float>& vert);

/// Process a mesh as mjCMesh::Process does: refpos, refquat, scale; centre of mass and volume
/// from pyramids (|volume| per face unless `exact`, compiler/exactmeshinertia); products of
/// inertia at `density` (the geom density of the mesh's default class); principal axes. Throws
/// MeshError with MuJoCo's reasons (area, volume, eigenvalues, A + B >= C, face orientation).
/// With `hull`, also the convex hull's graph of the vertices as read (before any of the above),
/// as MuJoCo builds it for a mesh that can collide.
MeshMass process_mesh(TriangleMesh mesh, const Vec3& refpos, const Quat& refquat, const Vec3& scale,
                      double density, bool exact, bool hull);

/// The file's path as MuJoCo 2.2.2 forms it (mjuu_makefullname): an absolute file as it is, else
/// an absolute meshdir + file, else the model's folder + meshdir + file. `meshdir` gets a
/// trailing '/' if it has none.
std::string mesh_path(const std::string& model_dir, std::string meshdir, const std::string& file);

/// The bytes of a mesh file; MeshError if it cannot be read or is larger than `max_bytes`.
std::string read_mesh_file(const std::string& path, std::size_t max_bytes);

}  // namespace lever::mjcf::detail
