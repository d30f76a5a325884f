// Compiler rotations; see orientation.hpp. Every expression keeps MuJoCo's operand order, because
// the compiled numbers must agree to the last bit.
#include "orientation.hpp"

#include <cmath>

namespace lever::mjcf::detail {

namespace {

// hamilton product, as the engine computes it (mju_mulQuat): no normalization
Quat product(const Quat& a, const Quat& b) {
  return {a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
          a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
          a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
          a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0]};
}

}  // namespace

// the compiler's product is followed by its normalization (mjuu_mulquat)
Quat compiler_product(const Quat& a, const Quat& b) {
  Quat q = product(a, b);
  normalize(q.data(), 4);
  return q;
}

// the engine's quaternion normalization: multiply by the inverse norm; tiny -> identity
void engine_normalize(Quat& q) {
  const double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  if (norm < 1e-15) {
    q = {1, 0, 0, 0};
    return;
  }
  const double inverse = 1 / norm;
  for (double& x : q) x *= inverse;
}

// the engine's rotation matrix: exactly the identity for the unit quaternion
Mat3 engine_rotation(const Quat& q) {
  if (q[0] == 1 && q[1] == 0 && q[2] == 0 && q[3] == 0) return {1, 0, 0, 0, 1, 0, 0, 0, 1};
  return rotation(q);
}

namespace {

Vec3 cross(const Vec3& b, const Vec3& c) {
  return {b[1] * c[2] - b[2] * c[1], b[2] * c[0] - b[0] * c[2], b[0] * c[1] - b[1] * c[0]};
}

// quaternion of the frame whose columns are x, y, z (mjuu_frame2quat), normalized
Quat frame_to_quat(const Vec3& x, const Vec3& y, const Vec3& z) {
  Quat q{};
  if (x[0] + y[1] + z[2] > 0) {
    q[0] = 0.5 * std::sqrt(1 + x[0] + y[1] + z[2]);
    q[1] = 0.25 * (y[2] - z[1]) / q[0];
    q[2] = 0.25 * (z[0] - x[2]) / q[0];
    q[3] = 0.25 * (x[1] - y[0]) / q[0];
  } else if (x[0] > y[1] && x[0] > z[2]) {
    q[1] = 0.5 * std::sqrt(1 + x[0] - y[1] - z[2]);
    q[0] = 0.25 * (y[2] - z[1]) / q[1];
    q[2] = 0.25 * (y[0] + x[1]) / q[1];
    q[3] = 0.25 * (z[0] + x[2]) / q[1];
  } else if (y[1] > z[2]) {
    q[2] = 0.5 * std::sqrt(1 - x[0] + y[1] - z[2]);
    q[0] = 0.25 * (z[0] - x[2]) / q[2];
    q[1] = 0.25 * (y[0] + x[1]) / q[2];
    q[3] = 0.25 * (z[1] + y[2]) / q[2];
  } else {
    q[3] = 0.5 * std::sqrt(1 - x[0] - y[1] + z[2]);
    q[0] = 0.25 * (x[1] - y[0]) / q[3];
    q[1] = 0.25 * (z[0] + x[2]) / q[3];
    q[2] = 0.25 * (z[1] + y[2]) / q[3];
  }
  normalize(q.data(), 4);
  return q;
}

const char* from_axisangle(std::array<double, 4> a, bool degree, Quat& q) {
  if (degree) a[3] = frame_radians(a[3]);
  if (normalize(a.data(), 3) < kCompilerEps) return "axisangle too small";
  const double half = a[3] / 2;
  q = {std::cos(half), std::sin(half) * a[0], std::sin(half) * a[1], std::sin(half) * a[2]};
  return nullptr;
}

const char* from_xyaxes(const Vec6& axes, Quat& q) {
  Vec3 x{axes[0], axes[1], axes[2]}, y{axes[3], axes[4], axes[5]};
  if (normalize(x.data(), 3) < kCompilerEps) return "xaxis too small";
  // make y orthogonal to x
  const double d = x[0] * y[0] + x[1] * y[1] + x[2] * y[2];
  for (int i = 0; i < 3; ++i) y[i] -= x[i] * d;
  if (normalize(y.data(), 3) < kCompilerEps) return "yaxis too small";
  Vec3 z = cross(x, y);
  if (normalize(z.data(), 3) < kCompilerEps) return "cross(xaxis, yaxis) too small";
  q = frame_to_quat(x, y, z);
  return nullptr;
}

const char* from_zaxis(Vec3 z, Quat& q) {
  if (normalize(z.data(), 3) < kCompilerEps) return "zaxis too small";
  q = z_to_quat(z);
  return nullptr;
}

const char* from_fullinertia(const Vec6& f, Quat& q, Vec3* inertia) {
  const Principal p = principal_axes({f[0], f[1], f[2], f[3], f[4], f[5]});
  q = p.quat;
  if (inertia) *inertia = p.moments;
  if (p.moments[2] < kCompilerEps) return "inertia must have positive eigenvalues";
  return nullptr;
}

const char* from_euler(Vec3 angles, bool degree, const std::string& sequence, Quat& q) {
  if (degree) {
    for (double& a : angles) a = frame_radians(a);
  }
  q = {1, 0, 0, 0};
  for (int i = 0; i < 3; ++i) {
    // one elementary rotation about the axis the letter names
    Quat r{std::cos(angles[i] / 2), 0, 0, 0};
    const double s = std::sin(angles[i] / 2);
    const char axis = sequence[static_cast<size_t>(i)];
    if (axis == 'x' || axis == 'X') r[1] = s;
    if (axis == 'y' || axis == 'Y') r[2] = s;
    if (axis == 'z' || axis == 'Z') r[3] = s;
    // lower case: rotating axes (post-multiply); upper case: fixed axes (pre-multiply)
    const bool rotating = axis == 'x' || axis == 'y' || axis == 'z';
    q = rotating ? compiler_product(q, r) : compiler_product(r, q);
  }
  normalize(q.data(), 4);
  return nullptr;
}

}  // namespace

double normalize(double* v, int n) {
  double sum = 0;
  for (int i = 0; i < n; ++i) sum += v[i] * v[i];
  if (sum < kCompilerEps) return 0;
  const double norm = std::sqrt(sum);
  for (int i = 0; i < n; ++i) v[i] /= norm;
  return norm;
}

Mat3 rotation(const Quat& q) {
  const double q00 = q[0] * q[0], q11 = q[1] * q[1], q22 = q[2] * q[2], q33 = q[3] * q[3];
  Mat3 r;
  r[0] = q00 + q11 - q22 - q33;
  r[4] = q00 - q11 + q22 - q33;
  r[8] = q00 - q11 - q22 + q33;
  r[1] = 2 * (q[1] * q[2] - q[0] * q[3]);
  r[2] = 2 * (q[1] * q[3] + q[0] * q[2]);
  r[3] = 2 * (q[1] * q[2] + q[0] * q[3]);
  r[5] = 2 * (q[2] * q[3] - q[0] * q[1]);
  r[6] = 2 * (q[1] * q[3] - q[0] * q[2]);
  r[7] = 2 * (q[2] * q[3] + q[0] * q[1]);
  return r;
}

Quat z_to_quat(const Vec3& v) {
  // axis = (0,0,1) x v, with the signed zeros this product gives
  const Vec3 z{0, 0, 1};
  Vec3 axis = cross(z, v);
  const double s = normalize(axis.data(), 3);
  if (s < 1e-10) axis = {1, 0, 0};
  const double angle = std::atan2(s, v[2]);
  return {std::cos(angle / 2), axis[0] * std::sin(angle / 2), axis[1] * std::sin(angle / 2),
          axis[2] * std::sin(angle / 2)};
}

namespace {

// D = E^T A E, accumulated row by row and skipping zero multipliers, as mju_mulMatTMat and
// mju_mulMatMat do (the skipped terms change signed zeros only, but keep the order anyway)
Mat3 rotate_into(const Mat3& e, const Mat3& a) {
  Mat3 t{};
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      const double s = e[i * 3 + j];
      if (s == 0) continue;
      for (int c = 0; c < 3; ++c) t[j * 3 + c] += a[i * 3 + c] * s;
    }
  }
  Mat3 d{};
  for (int i = 0; i < 3; ++i) {
    for (int k = 0; k < 3; ++k) {
      const double s = t[i * 3 + k];
      if (s == 0) continue;
      for (int c = 0; c < 3; ++c) d[i * 3 + c] += e[k * 3 + c] * s;
    }
  }
  return d;
}

// one Jacobi rotation zeroing D[r][c], as a quaternion about axis k; false when D is diagonal
bool jacobi_step(const Mat3& d, Quat& q) {
  int r = 1, c = 2, k = 0;
  if (std::fabs(d[1]) > std::fabs(d[2]) && std::fabs(d[1]) > std::fabs(d[5])) {
    r = 0, c = 1, k = 2;
  } else if (std::fabs(d[2]) > std::fabs(d[5])) {
    r = 0, c = 2, k = 1;
  }
  constexpr double kEps = 1e-12;
  if (std::fabs(d[3 * r + c]) < kEps) return false;
  const double tau = (d[4 * c] - d[4 * r]) / (2 * d[3 * r + c]);
  const double t =
      tau >= 0 ? 1.0 / (tau + std::sqrt(1 + tau * tau)) : -1.0 / (-tau + std::sqrt(1 + tau * tau));
  const double cosine = 1.0 / std::sqrt(1 + t * t);
  if (cosine > 1.0 - kEps) return false;
  Quat u{0, 0, 0, 0};
  double& v = u[static_cast<size_t>(k) + 1];
  v = tau >= 0 ? -std::sqrt(0.5 - 0.5 * cosine) : std::sqrt(0.5 - 0.5 * cosine);
  if (k == 1) v = -v;
  u[0] = std::sqrt(1.0 - v * v);
  engine_normalize(u);
  q = product(q, u);
  engine_normalize(q);
  return true;
}

}  // namespace

Principal principal_axes(const Sym6& in) {
  const Mat3 a{in[0], in[3], in[4], in[3], in[1], in[5], in[4], in[5], in[2]};
  Principal p;
  for (int iteration = 0; iteration < 500; ++iteration) {
    const Mat3 d = rotate_into(engine_rotation(p.quat), a);
    p.moments = {d[0], d[4], d[8]};
    if (!jacobi_step(d, p.quat)) break;
  }
  // bubble sort to decreasing order (lead index 0, 1, 0), turning the frame 90 degrees about
  // z (swap of 0 and 1) or x (swap of 1 and 2) with each swap
  for (int pass = 0; pass < 3; ++pass) {
    const int j = pass % 2;
    if (p.moments[static_cast<size_t>(j)] < p.moments[static_cast<size_t>(j) + 1]) {
      std::swap(p.moments[static_cast<size_t>(j)], p.moments[static_cast<size_t>(j) + 1]);
      Quat turn{0.707106781186548, 0, 0, 0};  // mujoco's truncated literal, not sqrt(0.5)
      turn[static_cast<size_t>((j + 2) % 3) + 1] = turn[0];
      p.quat = product(p.quat, turn);
      engine_normalize(p.quat);
    }
  }
  return p;
}

const char* apply_alternatives(const Orientation& o, bool degree, const std::string& eulerseq,
                               Quat& quat, Vec3* inertia) {
  const char* error = nullptr;
  if (o.axisangle) error = from_axisangle(*o.axisangle, degree, quat);
  if (!error && o.xyaxes) error = from_xyaxes(*o.xyaxes, quat);
  if (!error && o.zaxis) error = from_zaxis(*o.zaxis, quat);
  if (!error && o.fullinertia) error = from_fullinertia(*o.fullinertia, quat, inertia);
  if (!error && o.euler) error = from_euler(*o.euler, degree, eulerseq, quat);
  return error;
}

}  // namespace lever::mjcf::detail
