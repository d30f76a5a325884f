// The general convex pairs, as MuJoCo 2.2.2 collides them (engine_collision_convex.c): every pair
// with a cylinder, an ellipsoid or a mesh that has no closed form in its table.
//
//   support      each geom's farthest point along a direction (MuJoCo's mjccd_support): in the
//                geom's frame, then rotated and moved to the world; a mesh's vertex found by
//                climbing its convex hull's graph (or by visiting every vertex if it has none);
//                both geoms grown by half the margin, so that shapes within the margin overlap
//   convex_pair  the Minkowski portal refinement MuJoCo runs (libccd's ccdMPRPenetration, written
//                in collision/mpr.hpp) on the two support functions, with the model's
//                mpr_tolerance and mpr_iterations: depth, direction and point of the grown shapes'
//                overlap; dist = margin - depth, and the normal corrected where a geom's surface
//                gives it exactly (fix_normal); with multiccd, four more searches with both
//                geoms turned by +-1e-3 rad about the contact's tangents, keeping the contacts
//                that are distinct
//   plane_convex the support point against -normal (an ellipsoid's exact lowest point); for a mesh
//                up to two more vertices below the margin, among the lowest one's hull neighbours
//
// Every sum runs in MuJoCo's order, so that the search receives the same support points bit for
// bit as libccd does in MuJoCo and returns the same answer.
#include <algorithm>
#include <cmath>
#include <cstddef>

#include <lever/collision.hpp>

#include "collision/mpr.hpp"
#include "collision/narrow_phase.hpp"
#include "collision/surface_normal.hpp"


namespace lever::detail {

namespace {

using Vec3 = Eigen::Vector3d;

/// MuJoCo's mju_sign: -1, 0 or 1.
double sign_of(double x) { return x < 0 ? -1.0 : (x > 0 ? 1.0 : 0.0); }

double distance3(const Vec3& a, const Vec3& b) {
  const Vec3 d(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
  return std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
}

// ---- the support function (MuJoCo's mjccd_support) ---------------------------------------------

/// A geom as its support function reads it, set up once per search (MPR calls it some twenty
/// times): the pose as 9 + 3 numbers, the growth, and a mesh's vertices and hull graph.
///
/// The hull graph (MuJoCo's mesh_graph): numvert, numface, then per hull vertex its first edge's
/// address and its vertex index in the mesh, then each hull vertex's neighbours (hull-local
/// indices) ending with -1.
struct Support {
  GeomType type;
  const double* mat;   // geom_xmat, row by row
  const double* pos;   // geom_xpos
  const double* size;  // geom_size
  double margin;       // both geoms grow by margin / 2
  const double* vert;  // a mesh's vertices, x y z each
  int vertnum;
  const int* edge_address = nullptr;  // null: no hull graph, every vertex is visited
  const int* vertex_index = nullptr;
  const int* neighbours = nullptr;
  // Model::mesh_hull_neighbours at the neighbour lists' place: each neighbour's number and point
  // together (null: read through vertex_index)
  const HullNeighbour* neighbour_points = nullptr;
  const HullNeighbour* list_lengths = nullptr;  // hull vertex h's list length: [h].vertex
  int found = -1;  // the mesh vertex last found, as MuJoCo records it (meshindex)

  Support(const GeomShape& g, double grow)
      : type(g.type),
        mat(g.mat.data()),
        pos(g.pos.data()),
        size(g.size.data()),
        margin(grow),
        vert(g.mesh_vert),
        vertnum(g.mesh_vertnum) {
    if (g.mesh_graph) {
      const int numvert = g.mesh_graph[0];
      edge_address = g.mesh_graph + 2;
      vertex_index = edge_address + numvert;
      neighbours = vertex_index + numvert;
      if (g.mesh_hull) {
        neighbour_points = g.mesh_hull + (neighbours - g.mesh_graph);
        list_lengths = g.mesh_hull + 2;
      }
    }
  }

  /// Mesh vertex v (an index into vert, 3 numbers each).
  const double* vertex(std::ptrdiff_t v) const { return vert + 3 * v; }
  /// Hull vertex h's mesh vertex.
  const double* hull_vertex(std::ptrdiff_t h) const {
    return vertex(static_cast<std::ptrdiff_t>(vertex_index[h]));
  }
};

/// A mesh vertex's projection on a direction, as MuJoCo sums it.
double along(const double* vertex, const double* dir) {
  return dir[0] * vertex[0] + dir[1] * vertex[1] + dir[2] * vertex[2];
}

/// The end of the climb over the hull's graph from its first vertex, each round through the
/// neighbours of the vertex it started from, moving to every better one (MuJoCo's order, so that
/// among equal projections the same vertex is found), and its point (`point`). kTable: each
/// neighbour's point read beside its number (Model::mesh_hull_neighbours, the point there
/// copied from mesh_vert), else through the hull's vertex list: the same numbers in the same
/// order.
template <bool kTable>
std::ptrdiff_t climb(const Support& s, const double* dir, const double*& point) {
  std::ptrdiff_t current = 0;
  point = s.hull_vertex(0);
  double best = along(point, dir);
  [[maybe_unused]] int length = kTable ? s.list_lengths[0].vertex : 0;  // current's list's
  for (bool moved = true; moved;) {
    moved = false;
    if constexpr (kTable) {
      // counted to the list's end; a neighbour's number and list length read if better
      const HullNeighbour* neighbour = s.neighbour_points + s.edge_address[current];
      const HullNeighbour* const end = neighbour + length;
      for (; neighbour != end; ++neighbour) {
        const double projection = along(neighbour->point, dir);
        if (projection > best) {
          best = projection;
          current = neighbour->vertex;
          length = neighbour->length;
          point = neighbour->point;
          moved = true;
        }
      }
    } else {
      for (const int* e = s.neighbours + s.edge_address[current]; *e >= 0; ++e) {
        const double projection = along(s.hull_vertex(*e), dir);
        if (projection > best) {
          best = projection;
          current = *e;
          point = s.hull_vertex(*e);
          moved = true;
        }
      }
    }
  }
  return current;
}

/// The mesh vertex farthest along dir (in the mesh's frame): the first of the best when every
/// vertex is visited; the end of the climb from the hull's first vertex otherwise. Records in
/// s.found its index as MuJoCo does (a mesh vertex without a graph, a hull vertex with one) and
/// returns its point, null if none.
const double* mesh_support_point(Support& s, const double* dir) {
  if (!s.edge_address) {
    double best = -1e10;
    int best_vertex = -1;
    for (int i = 0; i < s.vertnum; ++i) {
      const double projection = along(s.vertex(i), dir);
      if (projection > best) {
        best = projection;
        best_vertex = i;
      }
    }
    s.found = best_vertex;
    return best_vertex < 0 ? nullptr : s.vertex(best_vertex);
  }
  const double* point = nullptr;
  const std::ptrdiff_t current =
      s.neighbour_points ? climb<true>(s, dir, point) : climb<false>(s, dir, point);
  s.found = static_cast<int>(current);
  return point;
}

/// The geom's support point `out` in the world along world direction `world_dir`, grown by
/// margin / 2: the direction into the geom's frame, the farthest point there, back to the world.
/// One function per type (MPR's support callbacks are chosen once per search).
template <GeomType kType>
void support_point(Support& s, const double* world_dir, double* out) {
  const double* R = s.mat;
  const double* size = s.size;
  const double* d = world_dir;
  // R^T d, each column's products summed top to bottom (mju_rotVecMatT)
  const double dir[3] = {R[0] * d[0] + R[3] * d[1] + R[6] * d[2],
                         R[1] * d[0] + R[4] * d[1] + R[7] * d[2],
                         R[2] * d[0] + R[5] * d[1] + R[8] * d[2]};
  double res[3];
  if constexpr (kType == GeomType::kSphere) {
    for (int i = 0; i < 3; ++i) res[i] = dir[i] * size[0];
  } else if constexpr (kType == GeomType::kCapsule) {
    for (int i = 0; i < 3; ++i) res[i] = dir[i] * size[0];
    res[2] += sign_of(dir[2]) * size[1];
  } else if constexpr (kType == GeomType::kEllipsoid) {
    // the unit sphere's support point of the direction scaled by the semi-axes, scaled back
    Vec3 unit(dir[0] * size[0], dir[1] * size[1], dir[2] * size[2]);
    normalize_or_x(unit);
    for (int i = 0; i < 3; ++i) res[i] = unit[i] * size[i];
  } else if constexpr (kType == GeomType::kCylinder) {
    // the rim point along the direction's horizontal part (the axis if it has none), the disc
    // its vertical part points to
    const double horizontal = std::sqrt(dir[0] * dir[0] + dir[1] * dir[1]);
    if (horizontal > kMinVal) {
      res[0] = dir[0] / horizontal * size[0];
      res[1] = dir[1] / horizontal * size[0];
    } else {
      res[0] = res[1] = 0;
    }
    res[2] = sign_of(dir[2]) * size[1];
  } else if constexpr (kType == GeomType::kBox) {
    for (int i = 0; i < 3; ++i) res[i] = sign_of(dir[i]) * size[i];
  } else if constexpr (kType == GeomType::kMesh) {
    const double* point = mesh_support_point(s, dir);
    for (int i = 0; i < 3; ++i) res[i] = point ? point[i] : 0.0;
  } else {
    res[0] = res[1] = res[2] = 0;  // planes and height fields have no support function
  }
  for (int i = 0; i < 3; ++i) res[i] += dir[i] * s.margin / 2;
  // R res + pos, each row's products summed left to right (mju_rotVecMat, mju_addTo3)
  double world[3];
  for (int i = 0; i < 3; ++i) {
    world[i] = R[3 * i] * res[0] + R[3 * i + 1] * res[1] + R[3 * i + 2] * res[2];
    world[i] += s.pos[i];
  }
  for (int i = 0; i < 3; ++i) out[i] = world[i];
}

using SupportFunction = void (*)(Support&, const double*, double*);

/// support_point of a geom type.
SupportFunction support_function(GeomType type) {
  switch (type) {
    case GeomType::kSphere: return support_point<GeomType::kSphere>;
    case GeomType::kCapsule: return support_point<GeomType::kCapsule>;
    case GeomType::kEllipsoid: return support_point<GeomType::kEllipsoid>;
    case GeomType::kCylinder: return support_point<GeomType::kCylinder>;
    case GeomType::kBox: return support_point<GeomType::kBox>;
    case GeomType::kMesh: return support_point<GeomType::kMesh>;
    default: return support_point<GeomType::kPlane>;
  }
}

/// support_point of the geom's own type.
void support_point(Support& s, const double* world_dir, double* out) {
  support_function(s.type)(s, world_dir, out);
}

// ---- the normal where a geom's surface gives it (MuJoCo's mjc_fixNormal) -----------------------

/// Replace MPR's normal by the geoms' surface normals where they give one (surface_normal.hpp,
/// on doubles); the frame's first tangent is then MuJoCo's default again.
void fix_normal(const GeomShape& g1, const GeomShape& g2, Contact& c) {
  primitive::Vec<double> normal = primitive_vec(c.frame.row(0).transpose());
  const primitive::Vec<double> pos = primitive_vec(c.pos);
  if (!primitive::fix_normal(primitive_shape(g1), primitive_shape(g2), pos, normal)) return;
  c.frame.row(0) << normal[0], normal[1], normal[2];
  c.frame.row(1).setZero();
}

/// A geom's centre, MPR's interior point (MuJoCo's mjccd_center).
mpr::Vec<double> centre(const GeomShape& g) { return {{g.pos[0], g.pos[1], g.pos[2]}}; }

/// A geom's support function as the search calls it: its type's, chosen once per search.
struct SupportOf {
  Support& s;
  SupportFunction function = support_function(s.type);
  void operator()(const double* dir, double* point) const { function(s, dir, point); }
};

/// One MPR search: a contact if the grown shapes overlap with a defined direction (MuJoCo's
/// mjc_MPRIteration).
bool mpr_contact(const GeomShape& g1, const GeomShape& g2, double margin,
                 const ConvexOptions& options, Contact& c) {
  Support o1(g1, margin), o2(g2, margin);
  SupportOf a{o1}, b{o2};
  mpr::Supports<SupportOf, SupportOf> both{a, b};
  mpr::Search<double, decltype(both)> search(both, options.mpr_tolerance,
                                             static_cast<unsigned long>(options.mpr_iterations));
  mpr::Answer<double> found;
  if (!mpr::overlapping(search.penetration(centre(g1), centre(g2), found))) return false;
  if (mpr::near_origin(found.dir)) return false;  // overlap, but no direction
  c.dist = margin - found.depth;
  c.pos = Vec3(found.pos[0], found.pos[1], found.pos[2]);
  c.frame.setZero();
  c.frame.row(0) << found.dir[0], found.dir[1], found.dir[2];
  fix_normal(g1, g2, c);
  return true;
}

// ---- multiccd: the geoms turned about the first contact (MuJoCo's mjc_Convex) ------------------

/// mju_quat2Mat of mju_axisAngle2Quat(axis, angle).
Mat3 axis_angle_rotation(const Vec3& axis, double angle) {
  if (angle == 0) return Mat3::Identity();
  const double s = std::sin(angle * 0.5);
  const double q0 = std::cos(angle * 0.5), q1 = axis[0] * s, q2 = axis[1] * s, q3 = axis[2] * s;
  const double q00 = q0 * q0, q01 = q0 * q1, q02 = q0 * q2, q03 = q0 * q3;
  const double q11 = q1 * q1, q12 = q1 * q2, q13 = q1 * q3;
  const double q22 = q2 * q2, q23 = q2 * q3, q33 = q3 * q3;
  Mat3 R;
  R << q00 + q11 - q22 - q33, 2 * (q12 - q03), 2 * (q13 + q02),  //
      2 * (q12 + q03), q00 - q11 + q22 - q33, 2 * (q23 - q01),   //
      2 * (q13 - q02), 2 * (q23 + q01), q00 - q11 - q22 + q33;
  return R;
}

/// A geom turned by rot about `origin`: mat = rot mat, pos moved so that origin stays put
/// (mju_rotateFrame; rot's rows times mat's rows accumulated as mju_mulMatMat, zeros skipped).
GeomShape turned(const GeomShape& g, const Mat3& rot, const Vec3& origin) {
  GeomShape t = g;
  for (int i = 0; i < 3; ++i) {
    Vec3 row(0, 0, 0);
    for (int k = 0; k < 3; ++k) {
      const double r = rot(i, k);
      if (r != 0) {
        for (int j = 0; j < 3; ++j) row[j] += g.mat(k, j) * r;
      }
    }
    t.mat.row(i) = row.transpose();
  }
  const Vec3 rel = origin - g.pos;
  Vec3 moved = rotate_rows(rot, rel);
  moved -= rel;
  t.pos = g.pos - moved;
  return t;
}

}  // namespace

void convex_support(const GeomShape& g, double margin, const double* dir, double* point) {
  Support s(g, margin);
  support_point(s, dir, point);
}

int convex_pair(const GeomShape& g1, const GeomShape& g2, double margin,
                const ConvexOptions& options, Contact* contacts) {
  if (!mpr_contact(g1, g2, margin, options, contacts[0])) return 0;
  int count = 1;
  const auto roundish = [](GeomType t) {
    return t == GeomType::kSphere || t == GeomType::kEllipsoid;
  };
  if (!options.multiccd || roundish(g1.type) || roundish(g2.type)) return count;

  // turn g1 by +-1e-3 rad about each tangent of the first contact and g2 back, search again, and
  // keep a new contact farther than 1e-3 of the smaller bounding radius from every earlier one,
  // at the first contact's depth
  Mat3 frame = contacts[0].frame;
  complete_frame(frame);
  const double tolerance = 1e-3 * std::min(g1.rbound, g2.rbound);
  const Vec3 origin = contacts[0].pos;
  for (int axis = 1; axis <= 2; ++axis) {
    for (const double angle : {-1e-3, 1e-3}) {
      const Mat3 rot = axis_angle_rotation(frame.row(axis).transpose(), angle);
      const GeomShape t1 = turned(g1, rot, origin);
      const GeomShape t2 = turned(g2, rot.transpose(), origin);
      Contact& candidate = contacts[count];
      if (!mpr_contact(t1, t2, margin, options, candidate)) continue;
      bool distinct = true;
      for (int i = 0; i < count; ++i) {
        if (distance3(contacts[i].pos, candidate.pos) <= tolerance) distinct = false;
      }
      if (distinct) {
        candidate.dist = contacts[0].dist;
        ++count;
      }
    }
  }
  return count;
}

int plane_convex(const GeomShape& plane, const GeomShape& convex, double margin,
                 Contact* contacts) {
  const Vec3 normal = plane.mat.col(2);
  const Vec3 down = normal * -1.0;
  Support lowest_support(convex, 0);
  Vec3 lowest;
  support_point(lowest_support, down.data(), lowest.data());
  const int lowest_found = lowest_support.found;
  const double dist = dot3(normal, lowest - plane.pos);
  if (dist > margin) return 0;
  Contact& first = contacts[0];
  first.dist = dist;
  first.pos = lowest + normal * (-0.5 * dist);
  first.frame.setZero();
  first.frame.row(0) = normal.transpose();
  if (convex.type != GeomType::kMesh) return 1;

  // a mesh: more vertices below the margin (at most three contacts), each at least 0.3 of the
  // bounding radius from the first
  constexpr int kMostContacts = 3;
  const Vec3 down_local = rotate_columns(convex.mat, down);
  const double threshold = dot3(normal, convex.pos - plane.pos) - margin;
  int count = 1;
  const auto add_vertex = [&](const double* vertex) {
    Vec3 point = rotate_rows(convex.mat, Vec3(vertex[0], vertex[1], vertex[2]));
    point += convex.pos;
    if (distance3(point, first.pos) < 0.3 * convex.rbound) return;
    Contact& c = contacts[count++];
    c.dist = dot3(normal, point - plane.pos);
    c.pos = point + normal * (-0.5 * c.dist);
    c.frame.setZero();
    c.frame.row(0) = normal.transpose();
  };
  const Support& mesh = lowest_support;
  if (!mesh.edge_address) {
    for (int i = 0; i < mesh.vertnum && count < kMostContacts; ++i) {
      const double* vertex = mesh.vertex(i);
      if (along(vertex, down_local.data()) > threshold && i != lowest_found) add_vertex(vertex);
    }
  } else if (lowest_found >= 0) {
    for (const int* e = mesh.neighbours + mesh.edge_address[lowest_found];
         *e >= 0 && count < kMostContacts; ++e) {
      const double* vertex = mesh.hull_vertex(*e);
      if (along(vertex, down_local.data()) > threshold) add_vertex(vertex);
    }
  }
  return count;
}

// ---- MPR's support points, written down (for the derivative of its answer) --------------------

namespace {

/// A geom's support function as mpr_search calls it: its points also written down in order.
struct RecordingSupport {
  Support& s;
  Vec3* points;
  int capacity;
  int count = 0;
  SupportFunction function = support_function(s.type);
  void operator()(const double* dir, double* point) {
    function(s, dir, point);
    if (count < capacity) points[count] = Vec3(point[0], point[1], point[2]);
    ++count;
  }
};

}  // namespace

int mpr_search(const GeomShape& g1, const GeomShape& g2, double margin,
               const ConvexOptions& options, Contact& answer, Eigen::Vector3d* points1,
               Eigen::Vector3d* points2, int capacity) {
  Support o1(g1, margin), o2(g2, margin);
  RecordingSupport a{o1, points1, capacity}, b{o2, points2, capacity};
  mpr::Supports<RecordingSupport, RecordingSupport> both{a, b};
  mpr::Search<double, decltype(both)> search(both, options.mpr_tolerance,
                                             static_cast<unsigned long>(options.mpr_iterations));
  mpr::Answer<double> found;
  if (!mpr::overlapping(search.penetration(centre(g1), centre(g2), found))) return -1;
  answer.dist = margin - found.depth;
  answer.pos = Vec3(found.pos[0], found.pos[1], found.pos[2]);
  answer.frame.setZero();
  answer.frame.row(0) << found.dir[0], found.dir[1], found.dir[2];
  return std::min(a.count, b.count);
}

}  // namespace lever::detail
