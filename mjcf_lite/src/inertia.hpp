// Mass and inertia from geoms, as MuJoCo 2.2.2's compiler infers them when a body has no
// <inertial>: each geom's volume, mass and principal inertia from its shape, then the body's
// centre of mass and principal axes from all geoms whose group is in compiler/inertiagrouprange.
// Source: MuJoCo 2.2.2 user_objects.cc (mjCGeom::GetVolume, SetInertia, mjCBody::GeomFrame).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "orientation.hpp"
#include "spec.hpp"

namespace lever::mjcf::detail {

/// The volume of a geom from its compiled size (half-lengths).
double geom_volume(GeomType type, const Vec3& size);

/// A geom's own mass: its `mass` attribute if given (0 if its volume is below 1e-15), otherwise
/// density x volume.
double geom_mass(GeomType type, const Vec3& size, double density, std::optional<double> mass);

/// Principal moments of a solid geom of mass `mass` about its centre, in the geom frame.
Vec3 geom_inertia(GeomType type, const Vec3& size, double mass);

/// One geom as it enters the body's inertia: compiled frame, mass and principal moments.
struct MassElement {
  Vec3 pos{};
  Quat quat{1, 0, 0, 0};
  double mass = 0;
  Vec3 inertia{};
};

/// The body's inertial frame, mass and principal moments.
struct BodyInertia {
  Vec3 ipos{};
  Quat iquat{1, 0, 0, 0};
  double mass = 0;
  Vec3 inertia{};
};

/// Combine two or more geoms into one rigid body (centre of mass, parallel-axis terms, principal
/// axes). Returns the reason on failure ("body mass is too small, ...").
std::optional<std::string> combine(const std::vector<MassElement>& parts, BodyInertia& out);

}  // namespace lever::mjcf::detail
