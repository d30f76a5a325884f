// Geom mass properties and their combination; see inertia.hpp. The formulas are the solid-body
// ones (capsule = cylinder + two hemispheres moved to its ends); the operand order is MuJoCo's.
#include "inertia.hpp"

namespace lever::mjcf::detail {

double geom_volume(GeomType type, const Vec3& size) {
  const double r = size[0];
  const double h = 2 * size[1];  // full height of a capsule's or cylinder's cylindrical part
  switch (type) {
    case GeomType::kSphere: return 4 * kPi * r * r * r / 3;
    case GeomType::kCapsule: return kPi * (r * r * h + 4 * r * r * r / 3);
    case GeomType::kCylinder: return kPi * r * r * h;
    case GeomType::kEllipsoid: return 4 * kPi * size[0] * size[1] * size[2] / 3;
    case GeomType::kBox: return size[0] * size[1] * size[2] * 8;
    case GeomType::kPlane:  // no volume: a plane gives its body no mass (mujoco)
    case GeomType::kHfield:
    case GeomType::kMesh: break;  // mesh: compiler.cpp's apply_mesh
  }
  return 0;
}

double geom_mass(GeomType type, const Vec3& size, double density, std::optional<double> mass) {
  if (!mass) return density * geom_volume(type, size);
  if (*mass == 0) return 0;
  // mujoco assigns a given mass only to a geom with a volume
  return geom_volume(type, size) > 1e-15 ? *mass : 0;
}

Vec3 geom_inertia(GeomType type, const Vec3& size, double m) {
  const double a = size[0], b = size[1], c = size[2];
  switch (type) {
    case GeomType::kSphere: {
      const double i = 2 * m * a * a / 5;
      return {i, i, i};
    }
    case GeomType::kCapsule: {
      const double r = a, h = 2 * b;
      // the two hemispheres together weigh m * Vsphere / Vtotal
      const double caps = m * 4 * r / (4 * r + 3 * h);
      const double cylinder = m - caps;
      const double across = cylinder * (3 * r * r + h * h) / 12;
      const double along = cylinder * r * r / 2;
      const double sphere = 2 * caps * r * r / 5;
      // each hemisphere's centre is 3r/8 beyond its face, h/2 from the capsule's centre
      const double shift = caps * h * (3 * r + 2 * h) / 8;
      // mujoco adds (sphere + shift) as one term: keep that grouping for the last bit
      return {across + (sphere + shift), across + (sphere + shift), along + sphere};
    }
    case GeomType::kCylinder: {
      const double h = 2 * b;
      const double across = m * (3 * a * a + h * h) / 12;
      return {across, across, m * a * a / 2};
    }
    case GeomType::kEllipsoid:
      return {m * (b * b + c * c) / 5, m * (a * a + c * c) / 5, m * (a * a + b * b) / 5};
    case GeomType::kBox:
      return {m * (b * b + c * c) / 3, m * (a * a + c * c) / 3, m * (a * a + b * b) / 3};
    case GeomType::kPlane:
    case GeomType::kHfield:
    case GeomType::kMesh: break;
  }
  return {0, 0, 0};
}

namespace {

// R diag(I) R^T of a geom, as (xx, yy, zz, xy, xz, yz)
Sym6 rotated_inertia(const Vec3& moments, const Quat& q) {
  const Mat3 r = rotation(q);
  const int rows[6][2] = {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {0, 2}, {1, 2}};
  Sym6 out{};
  for (int k = 0; k < 6; ++k) {
    const int i = rows[k][0], j = rows[k][1];
    out[static_cast<size_t>(k)] = r[3 * i] * (r[3 * j] * moments[0]) +
                                  r[3 * i + 1] * (r[3 * j + 1] * moments[1]) +
                                  r[3 * i + 2] * (r[3 * j + 2] * moments[2]);
  }
  return out;
}

// inertia of a point mass m at offset d (the parallel-axis term)
Sym6 point_inertia(double m, const Vec3& d) {
  return {m * (d[1] * d[1] + d[2] * d[2]),
          m * (d[0] * d[0] + d[2] * d[2]),
          m * (d[0] * d[0] + d[1] * d[1]),
          -m * d[0] * d[1],
          -m * d[0] * d[2],
          -m * d[1] * d[2]};
}

}  // namespace

std::optional<std::string> combine(const std::vector<MassElement>& parts, BodyInertia& out) {
  // total mass and centre of mass, three running sums
  double mass = 0;
  Vec3 moment{};
  for (const MassElement& p : parts) {
    mass += p.mass;
    for (int k = 0; k < 3; ++k)
      moment[static_cast<size_t>(k)] += p.mass * p.pos[static_cast<size_t>(k)];
  }
  if (mass < 1e-15) return "body mass is too small, cannot compute center of mass";
  const Vec3 com{moment[0] / mass, moment[1] / mass, moment[2] / mass};

  // inertia about the centre of mass, in the body frame
  Sym6 total{};
  for (const MassElement& p : parts) {
    const Sym6 own = rotated_inertia(p.inertia, p.quat);
    const Sym6 shift =
        point_inertia(p.mass, {p.pos[0] - com[0], p.pos[1] - com[1], p.pos[2] - com[2]});
    for (size_t j = 0; j < 6; ++j) total[j] = total[j] + own[j] + shift[j];
  }

  const Principal principal = principal_axes(total);
  out = BodyInertia{com, principal.quat, mass, principal.moments};
  if (principal.moments[2] < kCompilerEps) return "inertia must have positive eigenvalues";
  return std::nullopt;
}

}  // namespace lever::mjcf::detail
