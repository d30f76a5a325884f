// The narrow phase of the pairs with a box (sphere-box, capsule-box, box-box), on doubles:
// box_pairs.hpp's functions, written once on a scalar (the transition room differentiates them on
// dual numbers), with collide_shapes()'s contract, and the driver's removal of box-box's repeated
// positions.
#include "collision/box_pairs.hpp"
#include "collision/narrow_phase.hpp"

#include <array>

namespace lever::detail {

namespace {

using box_pairs::Box;
using box_pairs::Vec3;
using Found = primitive::Touch<double>;

Vec3<double> to_vec(const Eigen::Vector3d& v) { return {v[0], v[1], v[2]}; }

Box<double> box_of(const GeomShape& shape) {
  const Mat3& m = shape.mat;
  return {to_vec(shape.pos),
          {m(0, 0), m(0, 1), m(0, 2), m(1, 0), m(1, 1), m(1, 2), m(2, 0), m(2, 1), m(2, 2)},
          to_vec(shape.size)};
}

/// The contacts found, as the narrow phase writes them: dist, pos and the normal as the frame's
/// first row.
int write_contacts(const std::array<Found, kMaxPairContacts>& found, int count, Contact* out) {
  for (int k = 0; k < count; ++k) {
    const Found& f = found[static_cast<std::size_t>(k)];
    Contact& contact = out[k];
    contact.dist = f.dist;
    contact.pos = Eigen::Vector3d(f.pos[0], f.pos[1], f.pos[2]);
    contact.frame.setZero();
    contact.frame.row(0) << f.normal[0], f.normal[1], f.normal[2];
  }
  return count;
}

}  // namespace

int collide_sphere_box(const GeomShape& sphere, const GeomShape& box, double margin, Contact* out) {
  std::array<Found, kMaxPairContacts> found;
  const int n = box_pairs::sphere_box(to_vec(sphere.pos), sphere.size[0], box_of(box), margin,
                                      found.data());
  return write_contacts(found, n, out);
}

int collide_capsule_box(const GeomShape& capsule, const GeomShape& box, double margin,
                        Contact* out) {
  std::array<Found, kMaxPairContacts> found;
  const Vec3<double> capsule_z = {capsule.mat(0, 2), capsule.mat(1, 2), capsule.mat(2, 2)};
  const int n = box_pairs::capsule_box(to_vec(capsule.pos), capsule_z, capsule.size[0],
                                       capsule.size[1], box_of(box), margin, found.data());
  return write_contacts(found, n, out);
}

int collide_box_box(const GeomShape& box1, const GeomShape& box2, double margin, Contact* out) {
  std::array<Found, kMaxPairContacts> found;
  const int n = box_pairs::box_box(box_of(box1), box_of(box2), margin, found.data());
  return write_contacts(found, n, out);
}

int remove_repeated_positions(Contact* contacts, int count) {
  int kept = 0;
  for (int i = 0; i < count; ++i) {
    bool repeated = false;
    for (int j = i + 1; j < count && !repeated; ++j) {
      repeated = contacts[i].pos == contacts[j].pos;  // exact, component by component
    }
    if (repeated) continue;
    if (kept < i) contacts[kept] = contacts[i];
    ++kept;
  }
  return kept;
}

}  // namespace lever::detail
