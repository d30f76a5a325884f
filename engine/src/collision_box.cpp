// Placeholder until the box pairs land (branch `box` replaces this file wholesale): the three
// functions exist so that lever links, and refuse clearly when called.
#include <lever/error.hpp>

#include "collision_internal.hpp"

namespace lever::detail {

int collide_sphere_box(const GeomShape&, const GeomShape&, double, Contact*) {
  throw ModelError("sphere-box collision is not implemented yet");
}

int collide_capsule_box(const GeomShape&, const GeomShape&, double, Contact*) {
  throw ModelError("capsule-box collision is not implemented yet");
}

int collide_box_box(const GeomShape&, const GeomShape&, double, Contact*) {
  throw ModelError("box-box collision is not implemented yet");
}

}  // namespace lever::detail
