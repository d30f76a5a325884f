// The narrow phase's closed-form pairs without a box: MuJoCo 2.2.2's
// engine_collision_primitive.c (plane against sphere, capsule, box and cylinder; sphere and
// capsule against each other), and collide_shapes(), the table that dispatches to them and to
// the box pairs (box.cpp) and the general convex pairs (convex.cpp). They are written once, on a
// scalar, in primitive_pairs.hpp (the transition room differentiates them on dual numbers); here
// they run on doubles.
//
// The branch tests (margins, clamps, kMinVal) decide which contacts exist, so they are MuJoCo's,
// evaluated on the same sums in the same order: dot products left to right, rotations row by
// row. Each function writes dist, pos and the frame's normal row; the second row
// stays zero (the capsule's axis for plane-capsule, which MuJoCo uses as the first tangent) and the
// driver completes the frame, as mj_collideGeoms does with mju_makeFrame.
#include <array>
#include <cmath>
#include <string>
#include <utility>

#include <lever/collision.hpp>
#include <lever/error.hpp>

#include "collision/collision_room.hpp"
#include "collision/narrow_phase.hpp"
#include "collision/primitive_pairs.hpp"

namespace lever {

namespace {

// ---- the pairs written once on a scalar (primitive_pairs.hpp), on doubles ----------------------

using Vec3 = Eigen::Vector3d;
namespace primitive = detail::primitive;
using primitive::Shape;
using primitive::Touch;

using detail::primitive_shape;

/// A closed-form pair of primitive_pairs.hpp with collide_shapes()'s contract: each contact's
/// dist, pos, normal row and the tangent the pair seeds (zero if none).
template <int (*pair)(const Shape<double>&, const Shape<double>&, double, Touch<double>*)>
int closed_form(const GeomShape& g1, const GeomShape& g2, double margin, Contact* contacts) {
  std::array<Touch<double>, 4> found{};  // plane-box's four corners at the most
  const int count = pair(primitive_shape(g1), primitive_shape(g2), margin, found.data());
  for (int k = 0; k < count; ++k) {
    const Touch<double>& t = found[static_cast<std::size_t>(k)];
    Contact& c = contacts[k];
    c.dist = t.dist;
    c.pos = Vec3(t.pos[0], t.pos[1], t.pos[2]);
    c.frame.row(0) << t.normal[0], t.normal[1], t.normal[2];
    c.frame.row(1) << t.tangent[0], t.tangent[1], t.tangent[2];
    c.frame.row(2).setZero();
  }
  return count;
}

int sphere_sphere_pair(const Shape<double>& s1, const Shape<double>& s2, double margin,
                       Touch<double>* out) {
  return primitive::sphere_sphere(s1.pos, s1, s1.size[0], s2.pos, s2, s2.size[0], margin, out);
}

int plane_sphere_pair(const Shape<double>& plane, const Shape<double>& sphere, double margin,
                      Touch<double>* out) {
  return primitive::plane_sphere(plane, sphere.pos, sphere.size[0], margin, out);
}

using PairFunction = int (*)(const GeomShape&, const GeomShape&, double, Contact*);

/// lever's closed-form part of MuJoCo's mjCOLLISIONFUNC, indexed by (type1, type2) with
/// type1 <= type2; null where MuJoCo runs MPR (is_convex_pair) or has no function.
PairFunction pair_function(GeomType a, GeomType b) {
  using T = GeomType;
  switch (a) {
    case T::kPlane:
      switch (b) {
        case T::kSphere: return closed_form<plane_sphere_pair>;
        case T::kCapsule: return closed_form<primitive::plane_capsule<double>>;
        case T::kEllipsoid:
        case T::kMesh: return detail::plane_convex;
        case T::kCylinder: return closed_form<primitive::plane_cylinder<double>>;
        case T::kBox: return closed_form<primitive::plane_box<double>>;
        default: return nullptr;
      }
    case T::kSphere:
      switch (b) {
        case T::kSphere: return closed_form<sphere_sphere_pair>;
        case T::kCapsule: return closed_form<primitive::sphere_capsule<double>>;
        case T::kBox: return detail::collide_sphere_box;
        default: return nullptr;
      }
    case T::kCapsule:
      switch (b) {
        case T::kCapsule: return closed_form<primitive::capsule_capsule<double>>;
        case T::kBox: return detail::collide_capsule_box;
        default: return nullptr;
      }
    case T::kBox: return b == T::kBox ? detail::collide_box_box : nullptr;
    default: return nullptr;
  }
}

/// The pairs MuJoCo 2.2.2 gives mjc_Convex (type1 <= type2): every pair of two solids (neither a
/// plane nor a height field) without a closed form, i.e. any with an ellipsoid, a cylinder or a
/// mesh, except plane-ellipsoid and plane-mesh (mjc_PlaneConvex, in the table above).
bool is_convex_pair(GeomType a, GeomType b) {
  const auto solid = [](GeomType t) { return t != GeomType::kPlane && t != GeomType::kHfield; };
  return solid(a) && solid(b) && pair_function(a, b) == nullptr;
}

}  // namespace

bool has_collision_function(GeomType a, GeomType b) {
  if (static_cast<int>(a) > static_cast<int>(b)) std::swap(a, b);
  return pair_function(a, b) != nullptr || is_convex_pair(a, b);
}

bool collides_by_mpr(GeomType a, GeomType b) {
  if (static_cast<int>(a) > static_cast<int>(b)) std::swap(a, b);
  return is_convex_pair(a, b);
}

int collide_shapes(const GeomShape& g1, const GeomShape& g2, double margin, Contact* contacts,
                   const ConvexOptions& convex) {
  if (static_cast<int>(g1.type) > static_cast<int>(g2.type)) {
    throw ModelError(std::string("collide_shapes: a ") + detail::geom_type_name(g1.type) +
                     " must come after a " + detail::geom_type_name(g2.type) +
                     " (pass the geoms in MuJoCo's type order)");
  }
  if (is_convex_pair(g1.type, g2.type)) {
    return detail::convex_pair(g1, g2, margin, convex, contacts);
  }
  const PairFunction f = pair_function(g1.type, g2.type);
  if (!f) {
    throw ModelError(std::string("lever has no collision function for a ") +
                     detail::geom_type_name(g1.type) + " against a " +
                     detail::geom_type_name(g2.type));
  }
  return f(g1, g2, margin, contacts);
}

}  // namespace lever
