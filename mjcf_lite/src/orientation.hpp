// Rotations as MuJoCo 2.2.2's compiler computes them, operation for operation, so that compiled
// quaternions and principal axes agree to the last bit: the compiler's normalization (which
// leaves near-zero vectors alone), the orientation alternatives (axisangle, xyaxes, zaxis, euler,
// fullinertia) and the Jacobi principal-axis solver (mju_eig3).
// Sources: MuJoCo 2.2.2 user_util.cc, user_objects.cc (mjCAlternative::Set),
// engine_util_solve.c (mju_eig3), engine_util_spatial.c.
#pragma once

#include <array>
#include <string>

#include "spec.hpp"

namespace lever::mjcf::detail {

using Mat3 = std::array<double, 9>;  // row-major
using Sym6 = std::array<double, 6>;  // symmetric 3x3 as (xx, yy, zz, xy, xz, yz)

constexpr double kPi = 3.14159265358979323846;
constexpr double kCompilerEps = 1e-14;  // mjEPS of the compiler

/// Normalize v[0..n) to unit length and return its former length, unless its squared length is
/// below 1e-14: then leave it alone and return 0 (mjuu_normvec).
double normalize(double* v, int n);

/// Degrees to radians the way euler and axisangle are converted: x / 180 * pi.
inline double frame_radians(double degrees) { return degrees / 180.0 * kPi; }
/// Degrees to radians the way joint range, ref and springref are converted: x * (pi / 180).
inline double joint_radians(double degrees) { return degrees * (kPi / 180.0); }

/// The compiler's rotation matrix of a quaternion (mjuu_quat2mat).
Mat3 rotation(const Quat& q);

/// The compiler's quaternion product, normalized (mjuu_mulquat).
Quat compiler_product(const Quat& a, const Quat& b);

/// The engine's quaternion normalization (mju_normalize4): tiny -> identity.
void engine_normalize(Quat& q);

/// The engine's rotation matrix (mju_quat2Mat): exactly the identity for (1, 0, 0, 0).
Mat3 engine_rotation(const Quat& q);

/// The minimal rotation taking +z onto the unit vector v (mjuu_z2quat).
Quat z_to_quat(const Vec3& v);

/// Principal moments (decreasing) and the quaternion of the principal axes of a symmetric
/// inertia matrix, by MuJoCo's Jacobi iteration (mju_eig3).
struct Principal {
  Vec3 moments{};
  Quat quat{1, 0, 0, 0};
};
Principal principal_axes(const Sym6& inertia);

/// Apply the alternatives of `o` over `quat` (and `inertia` for fullinertia), in MuJoCo's order
/// axisangle, xyaxes, zaxis, fullinertia, euler (the last one given wins). Returns MuJoCo's
/// reason when one is degenerate ("zaxis too small", ...), else nullptr.
const char* apply_alternatives(const Orientation& o, bool degree, const std::string& eulerseq,
                               Quat& quat, Vec3* inertia);

}  // namespace lever::mjcf::detail
