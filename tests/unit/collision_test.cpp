// The narrow phase against hand calculations (MuJoCo-free; tests/diff compares it with MuJoCo).
#include <catch2/catch.hpp>

#include <cmath>

#include <lever/collision.hpp>
#include <lever/error.hpp>

namespace {

using lever::Contact;
using lever::GeomShape;
using lever::GeomType;
using lever::Mat3;
using Vec3 = Eigen::Vector3d;

constexpr double kTight = 1e-15;

GeomShape shape(GeomType type, const Vec3& size, const Vec3& pos, const Mat3& mat) {
  GeomShape s;
  s.type = type;
  s.size = size;
  s.pos = pos;
  s.mat = mat;
  return s;
}

/// A rotation about x by `angle`.
Mat3 about_x(double angle) {
  Mat3 R;
  R << 1, 0, 0, 0, std::cos(angle), -std::sin(angle), 0, std::sin(angle), std::cos(angle);
  return R;
}

}  // namespace

TEST_CASE("narrow phase: a sphere above a tilted plane", "[unit][collision]") {
  const Mat3 R = about_x(0.3);
  const Vec3 normal = R.col(2);
  const GeomShape plane = shape(GeomType::kPlane, Vec3(1, 1, 0.1), Vec3(0.1, 0.2, 0.3), R);
  const double radius = 0.1, height = 0.08;  // penetrating by 2 cm
  const GeomShape sphere =
      shape(GeomType::kSphere, Vec3(radius, 0, 0),
            plane.pos + Vec3(0.3, -0.2, 0).cross(normal) + normal * height, Mat3::Identity());
  Contact c[lever::kMaxPairContacts];
  REQUIRE(lever::collide_shapes(plane, sphere, 0.0, c) == 1);
  CHECK(std::abs(c[0].dist - (height - radius)) < kTight);
  // midway between the plane and the sphere's lowest point
  const Vec3 expected = sphere.pos - normal * (radius + c[0].dist / 2);
  CHECK((c[0].pos - expected).norm() < kTight);
  CHECK((c[0].frame.row(0).transpose() - normal).norm() == 0.0);

  // beyond the margin: none; within it: one, with a positive distance
  GeomShape above = sphere;
  above.pos = plane.pos + normal * (radius + 0.05);
  CHECK(lever::collide_shapes(plane, above, 0.04, c) == 0);
  REQUIRE(lever::collide_shapes(plane, above, 0.06, c) == 1);
  CHECK(std::abs(c[0].dist - 0.05) < kTight);
}

TEST_CASE("narrow phase: a box resting flat touches at its four lower corners",
          "[unit][collision]") {
  const GeomShape plane = shape(GeomType::kPlane, Vec3(1, 1, 0.1), Vec3::Zero(), Mat3::Identity());
  const GeomShape box =
      shape(GeomType::kBox, Vec3(0.1, 0.2, 0.3), Vec3(0.5, 0, 0.3), Mat3::Identity());
  Contact c[lever::kMaxPairContacts];
  REQUIRE(lever::collide_shapes(plane, box, 0.0, c) == 4);
  for (int k = 0; k < 4; ++k) {
    // corners 0-3 in order: x flips fastest, then y; all at z = 0
    const Vec3 corner(box.pos[0] + ((k & 1) ? 0.1 : -0.1), (k & 2) ? 0.2 : -0.2, 0.0);
    CHECK(c[k].dist == 0.0);
    CHECK((c[k].pos - corner).norm() < kTight);
  }
}

TEST_CASE("narrow phase: a capsule lying on a plane, and two parallel capsules",
          "[unit][collision]") {
  const GeomShape plane = shape(GeomType::kPlane, Vec3(1, 1, 0.1), Vec3::Zero(), Mat3::Identity());
  const Mat3 lying = about_x(M_PI / 2);  // axis along -y
  const GeomShape capsule = shape(GeomType::kCapsule, Vec3(0.05, 0.2, 0), Vec3(0, 0, 0.04), lying);
  Contact c[lever::kMaxPairContacts];
  REQUIRE(lever::collide_shapes(plane, capsule, 0.0, c) == 2);
  for (int k = 0; k < 2; ++k) {
    CHECK(std::abs(c[k].dist + 0.01) < kTight);
    // the capsule's axis is handed on as the first tangent
    CHECK((c[k].frame.row(1).transpose() - lying.col(2)).norm() == 0.0);
  }
  CHECK(std::abs(std::abs(c[0].pos[1] - c[1].pos[1]) - 0.4) < kTight);

  // side by side, 9 cm apart with radii 5 cm: two contacts 1 cm deep, normal along x
  const GeomShape other = shape(GeomType::kCapsule, Vec3(0.05, 0.2, 0), Vec3(0.09, 0, 0.04), lying);
  REQUIRE(lever::collide_shapes(capsule, other, 0.0, c) == 2);
  for (int k = 0; k < 2; ++k) {
    CHECK(std::abs(c[k].dist + 0.01) < kTight);
    CHECK((c[k].frame.row(0).transpose() - Vec3(1, 0, 0)).norm() < kTight);
  }
}

TEST_CASE("narrow phase: pairs are refused out of order or without a function",
          "[unit][collision]") {
  const GeomShape plane = shape(GeomType::kPlane, Vec3(1, 1, 0.1), Vec3::Zero(), Mat3::Identity());
  const GeomShape sphere =
      shape(GeomType::kSphere, Vec3(0.1, 0, 0), Vec3::Zero(), Mat3::Identity());
  const GeomShape field = shape(GeomType::kHfield, Vec3(1, 1, 0.1), Vec3::Zero(), Mat3::Identity());
  Contact c[lever::kMaxPairContacts];
  CHECK_THROWS_AS(lever::collide_shapes(sphere, plane, 0.0, c), lever::ModelError);
  CHECK_THROWS_WITH(lever::collide_shapes(field, sphere, 0.0, c),
                    Catch::Contains("no collision function for a hfield against a sphere"));
  CHECK(lever::has_collision_function(GeomType::kCylinder, GeomType::kPlane));
  CHECK(lever::has_collision_function(GeomType::kPlane, GeomType::kEllipsoid));
  // every pair of solids: closed form or MPR, as MuJoCo 2.2.2's table
  for (int a = 2; a <= 7; ++a) {
    for (int b = 2; b <= 7; ++b) {
      CHECK(lever::has_collision_function(static_cast<GeomType>(a), static_cast<GeomType>(b)));
    }
  }
  CHECK(lever::has_collision_function(GeomType::kMesh, GeomType::kPlane));
  CHECK_FALSE(lever::has_collision_function(GeomType::kPlane, GeomType::kPlane));
  CHECK_FALSE(lever::has_collision_function(GeomType::kHfield, GeomType::kSphere));
  CHECK(lever::has_collision_function(GeomType::kBox, GeomType::kSphere));
  // the pairs MuJoCo 2.2.2 gives MPR (not in the WebAssembly build), either order
  using T = GeomType;
  CHECK(lever::collides_by_mpr(T::kCylinder, T::kBox));
  CHECK(lever::collides_by_mpr(T::kBox, T::kCylinder));
  CHECK(lever::collides_by_mpr(T::kSphere, T::kEllipsoid));
  CHECK(lever::collides_by_mpr(T::kMesh, T::kMesh));
  CHECK_FALSE(lever::collides_by_mpr(T::kPlane, T::kEllipsoid));
  CHECK_FALSE(lever::collides_by_mpr(T::kMesh, T::kPlane));
  CHECK_FALSE(lever::collides_by_mpr(T::kPlane, T::kCylinder));
  CHECK_FALSE(lever::collides_by_mpr(T::kSphere, T::kBox));
  CHECK_FALSE(lever::collides_by_mpr(T::kHfield, T::kMesh));
}
