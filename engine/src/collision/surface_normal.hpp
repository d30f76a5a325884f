// MuJoCo 2.2.2's normal correction after a convex search (mjc_fixNormal, engine_collision_convex.c):
// where a round geom's surface gives the normal at the contact exactly (a sphere, a capsule, an
// ellipsoid, a cylinder's wall), it replaces the direction MPR found. Written once on a scalar type
// S, like primitive_pairs.hpp: double in the narrow phase (convex.cpp), dual numbers where the
// transition room differentiates a contact's geometry (transition/contact_geometry.cpp). Every
// branch and every iteration's stop is decided on value(x), so on dual numbers the derivative is
// that of the path the narrow phase took.
#pragma once

#include <Eigen/Core>

#include <cmath>

#include <lever/model.hpp>

#include "basics/basics.hpp"
#include "collision/primitive_pairs.hpp"

namespace lever::detail::primitive {

/// Normal of an ellipsoid at the ray from an inner point along nrm to its surface, refined by
/// re-aiming the ray at the surface normal found (mjc_ellipsoidInside). False if it gave none.
template <class S>
bool ellipsoid_normal_inside(Vec<S>& nrm, const Vec<S>& pos, const Eigen::Vector3d& size) {
  using std::sqrt;
  const Eigen::Vector3d inverse_square(1 / (size[0] * size[0]), 1 / (size[1] * size[1]),
                                       1 / (size[2] * size[2]));
  const S C = pos[0] * pos[0] * inverse_square[0] + pos[1] * pos[1] * inverse_square[1] +
              pos[2] * pos[2] * inverse_square[2] - 1.0;
  if (value(C) > 0) return false;
  normalize(nrm);
  for (int iter = 0; iter < 30; ++iter) {
    // the ray pos + x nrm (x >= 0) meets the surface where A x^2 + 2 B x + C = 0
    const S A = nrm[0] * nrm[0] * inverse_square[0] + nrm[1] * nrm[1] * inverse_square[1] +
                nrm[2] * nrm[2] * inverse_square[2];
    const S B = pos[0] * nrm[0] * inverse_square[0] + pos[1] * nrm[1] * inverse_square[1] +
                pos[2] * nrm[2] * inverse_square[2];
    const S det = B * B - A * C;
    if (value(det) < kMinVal || value(A) < kMinVal) return iter > 0;
    const S x = (B * -1.0 + sqrt(det)) / A;
    if (value(x) < 0) return iter > 0;
    const Vec<S> surface = pos + nrm * x;
    Vec<S> normal{{surface[0] * inverse_square[0], surface[1] * inverse_square[1],
                   surface[2] * inverse_square[2]}};
    normalize(normal);
    const Vec<S> change = nrm - normal;
    const double moved = std::sqrt(value(dot(change, change)));
    nrm = normal;
    if (moved < 1e-6) break;
  }
  return true;
}

/// Normal of an ellipsoid at the surface point nearest an outer point: Newton on the Lagrange
/// multiplier of the nearest-point problem (mjc_ellipsoidOutside).
template <class S>
void ellipsoid_normal_outside(Vec<S>& nrm, const Vec<S>& pos, const Eigen::Vector3d& size) {
  const Eigen::Vector3d S2(size[0] * size[0], size[1] * size[1], size[2] * size[2]);
  const Vec<S> PS2{{pos[0] * pos[0] * S2[0], pos[1] * pos[1] * S2[1], pos[2] * pos[2] * S2[2]}};
  S la(0.0);
  for (int iter = 0; iter < 30; ++iter) {
    const Vec<S> R{{S(1.0) / (la + S2[0]), S(1.0) / (la + S2[1]), S(1.0) / (la + S2[2])}};
    const S val = PS2[0] * R[0] * R[0] + PS2[1] * R[1] * R[1] + PS2[2] * R[2] * R[2] - 1.0;
    if (value(val) < 1e-6) break;
    const S deriv = (PS2[0] * R[0] * R[0] * R[0] + PS2[1] * R[1] * R[1] * R[1] +
                     PS2[2] * R[2] * R[2] * R[2]) * -2.0;
    if (value(deriv) > -kMinVal) break;
    const S delta = val * -1.0 / deriv;
    if (value(delta) < 1e-6) break;
    la = la + delta;
  }
  nrm = {{pos[0] / (la + S2[0]), pos[1] / (la + S2[1]), pos[2] / (la + S2[2])}};
  normalize(nrm);
}

/// The outward normal of a geom at the contact point pos, in the geom's frame, if its type gives
/// one there (a sphere's, capsule's or ellipsoid's surface; a cylinder's round wall, well away
/// from its discs); nrm starts as the contact's normal in the geom's frame.
template <class S>
bool surface_normal(GeomType type, const Eigen::Vector3d& size, const Vec<S>& pos, Vec<S>& nrm) {
  switch (type) {
    case GeomType::kSphere:
      nrm = pos;
      return true;
    case GeomType::kCapsule:
      if (value(pos[2]) < -size[1]) {
        nrm[2] = pos[2] + size[1];
      } else if (value(pos[2]) > size[1]) {
        nrm[2] = pos[2] - size[1];
      } else {
        nrm[2] = S(0.0);
      }
      nrm[0] = pos[0];
      nrm[1] = pos[1];
      return true;
    case GeomType::kEllipsoid: {
      if (size[0] < kMinVal || size[1] < kMinVal || size[2] < kMinVal) return false;
      const double elliptic = value(pos[0]) * value(pos[0]) / (size[0] * size[0]) +
                              value(pos[1]) * value(pos[1]) / (size[1] * size[1]) +
                              value(pos[2]) * value(pos[2]) / (size[2] * size[2]);
      if (elliptic <= 1) return ellipsoid_normal_inside(nrm, pos, size);
      ellipsoid_normal_outside(nrm, pos, size);
      return true;
    }
    case GeomType::kCylinder: {
      const double z = value(pos[2]);
      if (std::abs(z) > 0.95 * size[1]) return false;  // near a disc
      const double to_disc = std::abs(size[1] - std::abs(z));
      const double to_wall = std::abs(
          size[0] - std::sqrt(value(pos[0]) * value(pos[0]) + value(pos[1]) * value(pos[1])));
      if (to_disc < 0.25 * to_wall) return false;  // not four times nearer the wall
      nrm = {{pos[0], pos[1], S(0.0)}};
      return true;
    }
    default:
      return false;
  }
}

/// Replace MPR's normal (from g1 towards g2) at the contact point pos by the geoms' surface
/// normals where they give one: their difference (made unit) when both do, else the one that does
/// (mjc_fixNormal). Returns whether either did (the normal then changed).
template <class S>
bool fix_normal(const Shape<S>& g1, const Shape<S>& g2, const Vec<S>& pos, Vec<S>& normal_out) {
  const Shape<S>* geoms[2] = {&g1, &g2};
  Vec<S> normal[2] = {normal_out, normal_out * -1.0};
  bool processed[2] = {false, false};
  for (int i = 0; i < 2; ++i) {
    const Shape<S>& g = *geoms[i];
    if (g.type != GeomType::kSphere && g.type != GeomType::kCapsule &&
        g.type != GeomType::kEllipsoid && g.type != GeomType::kCylinder) {
      continue;
    }
    const Vec<S> local = unrotate(g, pos - g.pos);
    Vec<S> nrm = unrotate(g, normal[i]);
    processed[i] = surface_normal(g.type, g.size, local, nrm);
    if (processed[i]) {
      normalize(nrm);
      normal[i] = rotate(g, nrm);
    }
  }
  if (processed[0] && processed[1]) {
    Vec<S> n = normal[0] - normal[1];
    normalize(n);
    normal_out = n;
  } else if (processed[0]) {
    normal_out = normal[0];
  } else if (processed[1]) {
    normal_out = normal[1] * -1.0;
  }
  return processed[0] || processed[1];
}

}  // namespace lever::detail::primitive
