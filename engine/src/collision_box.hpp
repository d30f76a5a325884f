// The narrow phase of the pairs with a box (collision_box.cpp): sphere-box, capsule-box, box-box,
// deciding their contacts as MuJoCo 2.2.2's engine_collision_box.c does. Engine-internal.
//
// Each function writes dist, pos and the frame's first row (the normal, from geom1 into geom2;
// the other two rows are zeroed) of its contacts and returns how many it wrote. The other fields
// of Contact are the driver's.
#pragma once

#include <lever/collision.hpp>

// lever::detail, as collision_internal.hpp of branch `collide` declares the three functions
namespace lever::detail {

/// The most contacts collide_box_box() writes, and so the size of the buffer a caller passes it:
/// MuJoCo's box-box function returns the clipped polygon's points before its driver drops
/// repeated positions (remove_repeated_positions), up to 16 edge crossings + 4 face corners + 4
/// box corners. Two equal cubes face to face give 9 (the corners twice, 4 or 5 after the driver);
/// turned 45 degrees about their normal they give 9 that all stay (the octagon and the incident
/// box's lowest corner): more than kMaxPairContacts (8) survive the driver.
inline constexpr int kMaxBoxBoxContacts = 24;

/// Sphere (size[0] = radius) against a box (size = half-sizes): at most 1 contact.
int collide_sphere_box(const GeomShape& sphere, const GeomShape& box, double margin, Contact* out);

/// Capsule (size[0] = radius, size[1] = half-length along its z axis) against a box: at most 2
/// contacts (the second only where MuJoCo's heuristic finds the capsule lying along the box).
int collide_capsule_box(const GeomShape& capsule, const GeomShape& box, double margin,
                        Contact* out);

/// Box against box: at most kMaxBoxBoxContacts contacts, repeated positions included (see
/// remove_repeated_positions).
int collide_box_box(const GeomShape& box1, const GeomShape& box2, double margin, Contact* out);

/// What MuJoCo 2.2.2's driver (mj_collideGeoms, engine_collision_driver.c) does to a box-box
/// pair's contacts before it keeps them: a contact whose position equals, component by component
/// and exactly, that of a later one is dropped; the survivors keep their order. Returns how many
/// remain in contacts[0, result).
int remove_repeated_positions(Contact* contacts, int count);

}  // namespace lever::detail
