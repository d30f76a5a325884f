// The collision stage, MuJoCo 2.2.2's mj_collision (engine_collision_driver.c): which geom pairs
// are tested, in which order, and how the two geoms' contact parameters mix.
//
//   broad phase   body pairs in signature order ((b1 + 1) << 16) + (b2 + 1): every pair with the
//                 world (if it has geoms) or with a body welded to the world that holds a plane,
//                 plus the pairs whose bounding boxes overlap along the eigenvectors of the geoms'
//                 position covariance (MuJoCo's sweep and prune, here tested pair by pair: the set
//                 is the same, and listing it in signature order is what the sort did). A body
//                 pair listed twice is tested twice, as in MuJoCo. The eigenframe is computed
//                 only for a pair whose verdict it decides (sweep_lists).
//   <pair>        explicit pairs merged in by signature; a geom pair they name is not tested again
//   <exclude>     body pairs skipped (dynamic pairs only)
//   geom pair     contype/conaffinity, same weld body, parent filter (dynamic pairs only, unless
//                 <flag filterparent="disable">); the bounding-sphere and plane tests; for a
//                 pair MuJoCo searches by MPR, the geoms' boxes (geom_aabb) apart by more than
//                 2e-4 along an axis of either (no search; MPR would find nothing); then the
//                 narrow phase
//   parameters    margin and gap max, condim and friction by priority else max, solref/solimp
//                 mixed by solmix (with <flag override="enable"> margin, solref and solimp are
//                 opt.o_margin, o_solref, o_solimp); includemargin = margin - gap, contacts beyond
//                 it kept with exclude = 1
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>

#include <lever/collision.hpp>
#include <lever/error.hpp>

#include "collision/narrow_phase.hpp"
#include "model/model_room.hpp"
#include "collision/collision_room.hpp"

namespace lever {

namespace {

using detail::dot3;
using detail::kMinVal;
using detail::normalize_or_x;
using Vec3 = Eigen::Vector3d;

/// MuJoCo's mjMINMU: the smallest friction coefficient a contact gets.
constexpr double kMinFriction = 1e-5;

// a geom as a message names it: 'name' (id), or its id alone when it has no name
std::string geom_label(const Model& model, int g) {
  const std::string& name = model.geom_name[static_cast<std::size_t>(g)];
  return name.empty() ? std::to_string(g) : "'" + name + "' (" + std::to_string(g) + ")";
}

// ---- the eigenframe of the broad phase (MuJoCo's mju_eig3) --------------------------------------

using Quat4 = std::array<double, 4>;

double normalize4(Quat4& q) {
  const double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  if (norm < kMinVal) {
    q = {1, 0, 0, 0};
  } else {
    const double inverse = 1 / norm;
    for (double& x : q) x *= inverse;
  }
  return norm;
}

Quat4 quat_product(const Quat4& a, const Quat4& b) {
  return {a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
          a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
          a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
          a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0]};
}

/// The rotation of a unit quaternion, with MuJoCo's sums (mju_quat2Mat).
Mat3 quat_rotation(const Quat4& q) {
  Mat3 R = Mat3::Identity();
  if (q[0] == 1 && q[1] == 0 && q[2] == 0 && q[3] == 0) return R;
  const double q00 = q[0] * q[0], q01 = q[0] * q[1], q02 = q[0] * q[2], q03 = q[0] * q[3];
  const double q11 = q[1] * q[1], q12 = q[1] * q[2], q13 = q[1] * q[3];
  const double q22 = q[2] * q[2], q23 = q[2] * q[3], q33 = q[3] * q[3];
  R << q00 + q11 - q22 - q33, 2 * (q12 - q03), 2 * (q13 + q02),  //
      2 * (q12 + q03), q00 - q11 + q22 - q33, 2 * (q23 - q01),   //
      2 * (q13 - q02), 2 * (q23 + q01), q00 - q11 - q22 + q33;
  return R;
}

/// V^T A V of 3x3 matrices as MuJoCo forms it (V^T A first), each element summed over k in
/// order; only the upper triangle and the diagonal, which are all the rotation reads.
Mat3 rotated_upper(const Mat3& A, const Mat3& V) {
  Mat3 VtA;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      double sum = 0;
      for (int k = 0; k < 3; ++k) sum += V(k, i) * A(k, j);
      VtA(i, j) = sum;
    }
  }
  Mat3 D;
  for (int i = 0; i < 3; ++i) {
    for (int j = i; j < 3; ++j) {
      double sum = 0;
      for (int k = 0; k < 3; ++k) sum += VtA(i, k) * V(k, j);
      D(i, j) = sum;
    }
  }
  D(1, 0) = D(2, 0) = D(2, 1) = 0;  // not read
  return D;
}

/// The eigenvectors of a symmetric 3x3 matrix by Jacobi rotations, accumulated as a quaternion
/// and sorted by decreasing eigenvalue (mju_eig3). The broad phase bounds the bodies along the
/// rows of the returned matrix, as MuJoCo does.
Mat3 eigenframe(const Mat3& covariance) {
  constexpr double kEps = 1e-12;
  Quat4 quat{1, 0, 0, 0};
  Vec3 eigval;
  for (int iter = 0; iter < 500; ++iter) {
    const Mat3 V = quat_rotation(quat);
    const Mat3 D = rotated_upper(covariance, V);
    eigval = Vec3(D(0, 0), D(1, 1), D(2, 2));

    // the largest off-diagonal element (row, column) and the axis of the rotation that zeroes it
    int row = 1, col = 2, axis = 0;
    if (std::abs(D(0, 1)) > std::abs(D(0, 2)) && std::abs(D(0, 1)) > std::abs(D(1, 2))) {
      row = 0, col = 1, axis = 2;
    } else if (std::abs(D(0, 2)) > std::abs(D(1, 2))) {
      row = 0, col = 2, axis = 1;
    }
    if (std::abs(D(row, col)) < kEps) break;

    // 2x2 symmetric Schur decomposition
    const double tau = (D(col, col) - D(row, row)) / (2 * D(row, col));
    const double t = tau >= 0 ? 1.0 / (tau + std::sqrt(1 + tau * tau))
                              : -1.0 / (-tau + std::sqrt(1 + tau * tau));
    const double c = 1.0 / std::sqrt(1 + t * t);
    if (c > 1.0 - kEps) break;

    Quat4 rotation{0, 0, 0, 0};
    const double half_sine = std::sqrt(0.5 - 0.5 * c);
    rotation[axis + 1] = tau >= 0 ? -half_sine : half_sine;
    if (axis == 1) rotation[axis + 1] = -rotation[axis + 1];
    rotation[0] = std::sqrt(1.0 - rotation[axis + 1] * rotation[axis + 1]);
    normalize4(rotation);
    quat = quat_product(quat, rotation);
    normalize4(quat);
  }

  // decreasing eigenvalues: compare (0, 1), (1, 2), (0, 1); each swap turns the frame by 90 deg
  for (int j = 0; j < 3; ++j) {
    const int lead = j % 2;
    if (eigval[lead] < eigval[lead + 1]) {
      std::swap(eigval[lead], eigval[lead + 1]);
      Quat4 quarter_turn{0.707106781186548, 0, 0, 0};
      quarter_turn[(lead + 2) % 3 + 1] = quarter_turn[0];
      quat = quat_product(quat, quarter_turn);
      normalize4(quat);
    }
  }
  return quat_rotation(quat);
}

// ---- the stage ---------------------------------------------------------------------------------

class Collider {
 public:
  Collider(const Model& model, Data& data) : m_(model), d_(data) {}

  void run() {
    const bool sweep = has_moving_geoms();
    const int nbody = m_.nbody;
    const std::uint8_t* role = m_.body_collision.data();
    int pair_address = 0, exclude_address = 0;
    for (int b1 = 0; b1 < nbody; ++b1) {
      const int b1_with_every_body = role[b1] & Model::kBodyPairsWithAll ? 1 : 0;
      for (int b2 = b1 + 1; b2 < nbody; ++b2) {
        const int listed = b1_with_every_body + (role[b2] & Model::kBodyPairsWithAll ? 1 : 0) +
                           (sweep && sweep_lists(b1, b2) ? 1 : 0);
        for (int k = 0; k < listed; ++k) {
          body_pair(b1, b2, pair_address, exclude_address);
        }
      }
    }
    // the explicit pairs after the last body pair
    while (pair_address < m_.npair) collide_geoms(-1, -1, pair_address++);
  }

  int count() const { return count_; }
  int unsupported() const { return unsupported_; }
  int last_unsupported_geom() const { return last_unsupported_geom_; }

 private:
  const Model& m_;
  Data& d_;
  int count_ = 0;
  int unsupported_ = 0;
  int last_unsupported_geom_ = -1;
  bool boxes_ready_ = false;  // the bodies' bounds along the eigenframe (work.body_aabb)
  int checks_left_ = kChecksWithoutFrame;

  /// Geom pairs the broad phase looks at before it computes the eigenframe: a few dozen (the
  /// frame's Jacobi sweeps cost about as much as that many checks).
  static constexpr int kChecksWithoutFrame = 32;

  // ---- bodies ----------------------------------------------------------------------------------

  int weld(int body) const { return m_.body_weldid[body]; }

  /// Whether a geom is outside the world body (else the sweep lists no pair).
  bool has_moving_geoms() const {
    for (int g = 0; g < m_.ngeom; ++g) {
      if (m_.geom_bodyid[g] != 0) return true;
    }
    return false;
  }

  /// The sweep's verdict for bodies b1 < b2 (boxes_overlap). The eigenframe is computed only
  /// when a pair needs it: a pair whose verdict changes nothing (excluded, or every geom pair
  /// filtered or beyond its bounding spheres: collide_geoms would return before any effect), or
  /// that overlaps along every axis whatever the frame (two geoms' bounding spheres overlapping
  /// by more than rounding), is decided without it.
  bool sweep_lists(int b1, int b2) {
    if (!boxes_ready_) {
      switch (verdict_without_frame(b1, b2)) {
        case Verdict::kOverlap: return true;
        case Verdict::kNoEffect: return false;
        case Verdict::kUndecided: break;
      }
      compute_bounding_boxes();
      boxes_ready_ = true;
    }
    return boxes_overlap(b1, b2);
  }

  enum class Verdict { kOverlap, kNoEffect, kUndecided };

  Verdict verdict_without_frame(int b1, int b2) {
    if (!boxes_may_overlap(b1, b2)) return Verdict::kNoEffect;  // the same false either way
    if (std::binary_search(m_.exclude_signature.begin(), m_.exclude_signature.end(),
                           ((b1 + 1) << 16) + (b2 + 1))) {
      return Verdict::kNoEffect;
    }
    bool effect = false;
    for (int g1 = m_.body_geomadr[b1]; g1 < m_.body_geomadr[b1] + m_.body_geomnum[b1]; ++g1) {
      for (int g2 = m_.body_geomadr[b2]; g2 < m_.body_geomadr[b2] + m_.body_geomnum[b2]; ++g2) {
        if (--checks_left_ < 0) return Verdict::kUndecided;
        const double dist = center_distance(g1, g2);
        // each body's box along an axis holds [c - reach, c + reach] of each of its geoms (c its
        // centre's coordinate, reach >= 0): two such intervals overlap along every unit axis
        // when the centres are closer than the reaches' sum, by more than the bounds' rounding
        const double reach1 = m_.geom_rbound[g1] + m_.geom_margin[g1];
        const double reach2 = m_.geom_rbound[g2] + m_.geom_margin[g2];
        const double reach = reach1 + reach2;
        const double rounding = 1e-9 * (1 + reach + d_.geom_xpos[g1].cwiseAbs().sum() +
                                        d_.geom_xpos[g2].cwiseAbs().sum());
        if (reach1 >= 0 && reach2 >= 0 && dist <= reach - rounding) return Verdict::kOverlap;
        if (effect) continue;
        // bounds_apart's first test, as collide_geoms makes it (r1 + r2 and the distance do not
        // depend on the geoms' order), then the pair's other tests
        const double r1 = m_.geom_rbound[g1], r2 = m_.geom_rbound[g2];
        if (r1 > 0 && r2 > 0 && dist > r1 + r2 + dynamic_margin(g1, g2)) continue;
        effect = !nothing_to_collide(g1, g2);
      }
    }
    return effect ? Verdict::kUndecided : Verdict::kNoEffect;
  }

  /// Bounds of each body's geoms (spheres of geom_rbound + geom_margin) along the eigenframe of
  /// the non-world geoms' positions (at least one: has_moving_geoms).
  void compute_bounding_boxes() {
    Vec3 center = Vec3::Zero();
    int n = 0;
    for (int g = 0; g < m_.ngeom; ++g) {
      if (m_.geom_bodyid[g] == 0) continue;
      for (int i = 0; i < 3; ++i) center[i] += d_.geom_xpos[g][i];
      ++n;
    }
    for (int i = 0; i < 3; ++i) center[i] /= n;

    Mat3 covariance = Mat3::Zero();
    for (int g = 0; g < m_.ngeom; ++g) {
      if (m_.geom_bodyid[g] == 0) continue;
      const Vec3 dif = d_.geom_xpos[g] - center;
      for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) covariance(i, j) += dif[i] * dif[j];
      }
    }
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) covariance(i, j) /= n;
    }
    const Mat3 frame = eigenframe(covariance);

    double* box = d_.work.body_aabb.data();
    std::fill(box, box + 6 * m_.nbody, 0.0);
    for (int b = 1; b < m_.nbody; ++b) {
      double* body_box = box + 6 * b;
      for (int k = 0; k < m_.body_geomnum[b]; ++k) {
        const int g = m_.body_geomadr[b] + k;
        for (int j = 0; j < 3; ++j) {
          const double c = dot3(d_.geom_xpos[g], frame.row(j).transpose());
          const double lo = c - m_.geom_rbound[g] - m_.geom_margin[g];
          const double hi = c + m_.geom_rbound[g] + m_.geom_margin[g];
          body_box[2 * j] = k == 0 ? lo : std::min(body_box[2 * j], lo);
          body_box[2 * j + 1] = k == 0 ? hi : std::max(body_box[2 * j + 1], hi);
        }
      }
    }
  }

  /// The sweep's verdict for two non-world bodies: overlap along the first axis in single
  /// precision (MuJoCo sorts float copies of the bounds; bounds equal as floats count as
  /// overlapping, where MuJoCo's order of equal keys decides), along the other two in double;
  /// two bodies of one geom each must also pass contype/conaffinity.
  bool boxes_overlap(int b1, int b2) const {
    if (!boxes_may_overlap(b1, b2)) return false;
    const double* a = d_.work.body_aabb.data() + 6 * b1;
    const double* b = d_.work.body_aabb.data() + 6 * b2;
    if (static_cast<float>(b[0]) > static_cast<float>(a[1]) ||
        static_cast<float>(a[0]) > static_cast<float>(b[1])) {
      return false;
    }
    return !(a[2] > b[3] || a[3] < b[2] || a[4] > b[5] || a[5] < b[4]);
  }

  /// boxes_overlap's tests that need no box: non-world bodies that collide, and two bodies of
  /// one geom each pass contype/conaffinity.
  bool boxes_may_overlap(int b1, int b2) const {
    const std::uint8_t* role = m_.body_collision.data();
    if (b1 == 0 || !(role[b1] & Model::kBodyCollides) || !(role[b2] & Model::kBodyCollides)) {
      return false;
    }
    if (m_.body_geomnum[b1] == 1 && m_.body_geomnum[b2] == 1) {
      const int g1 = m_.body_geomadr[b1], g2 = m_.body_geomadr[b2];
      if (!(m_.geom_contype[g1] & m_.geom_conaffinity[g2]) &&
          !(m_.geom_contype[g2] & m_.geom_conaffinity[g1])) {
        return false;
      }
    }
    return true;
  }

  /// One listed body pair: the explicit pairs up to its signature, then (unless excluded) its
  /// geom pairs, skipping those an explicit pair of the same signature already tested.
  void body_pair(int b1, int b2, int& pair_address, int& exclude_address) {
    const int signature = ((b1 + 1) << 16) + (b2 + 1);
    bool merged = false;
    const int first_pair = pair_address;
    while (pair_address < m_.npair && m_.pair_signature[pair_address] <= signature) {
      if (m_.pair_signature[pair_address] == signature) merged = true;
      collide_geoms(-1, -1, pair_address++);
    }
    while (exclude_address < m_.nexclude && m_.exclude_signature[exclude_address] < signature) {
      ++exclude_address;
    }
    if (exclude_address < m_.nexclude && m_.exclude_signature[exclude_address] == signature) {
      return;
    }
    for (int g1 = m_.body_geomadr[b1]; g1 < m_.body_geomadr[b1] + m_.body_geomnum[b1]; ++g1) {
      for (int g2 = m_.body_geomadr[b2]; g2 < m_.body_geomadr[b2] + m_.body_geomnum[b2]; ++g2) {
        if (merged && named_by_pair(g1, g2, first_pair, pair_address)) continue;
        collide_geoms(g1, g2, -1);
      }
    }
  }

  bool named_by_pair(int g1, int g2, int first, int end) const {
    for (int p = first; p < end; ++p) {
      if ((m_.pair_geom1[p] == g1 && m_.pair_geom2[p] == g2) ||
          (m_.pair_geom1[p] == g2 && m_.pair_geom2[p] == g1)) {
        return true;
      }
    }
    return false;
  }

  // ---- geom pairs ------------------------------------------------------------------------------

  /// contype/conaffinity, same weld body, and the parent filter (MuJoCo's mj_contactFilter).
  bool filtered_out(int g1, int g2) const {
    if (!(m_.geom_contype[g1] & m_.geom_conaffinity[g2]) &&
        !(m_.geom_contype[g2] & m_.geom_conaffinity[g1])) {
      return true;
    }
    const int weld1 = weld(m_.geom_bodyid[g1]), weld2 = weld(m_.geom_bodyid[g2]);
    if (weld1 == weld2) return true;
    const int weld_parent1 = weld(m_.body_parentid[weld1]);
    const int weld_parent2 = weld(m_.body_parentid[weld2]);
    const bool filter_parent =
        !m_.opt.disabled(kDisableFilterparent) && weld1 != 0 && weld2 != 0;
    return filter_parent && (weld1 == weld_parent2 || weld2 == weld_parent1);
  }

  /// Height of geom g's centre above plane p.
  double above_plane(int p, int g) const {
    return dot3(d_.geom_xpos[g] - d_.geom_xpos[p], d_.geom_xmat[p].col(2));
  }

  GeomShape shape(int g) const { return detail::geom_shape(m_, d_, g); }

  /// The mid-phase before MPR: whether the two geoms' boxes (geom_aabb, in their frames), each
  /// grown by margin / 2 as the support functions grow the geoms, are apart by more than
  /// kBoxesApart along one of the six box axes. MPR on such a pair finds no contact (the
  /// search, libccd's in MuJoCo and mpr.hpp's here, reports one only where the origin is within rounding of the grown shapes' Minkowski
  /// difference, or within |v0 x v1| < 1.5e-8 of its first segment, i.e. within 1.5e-8 / |v0|
  /// with |v0| >= the gap: 1.2e-4 at most), so it is not run. MuJoCo 2.2.2 runs it and finds
  /// nothing; a margin below zero, which shrinks the geoms unevenly, is never skipped.
  bool boxes_apart(int g1, int g2, double margin) const {
    constexpr double kBoxesApart = 2e-4;
    if (!(margin >= 0)) return false;
    const double* R1 = d_.geom_xmat[g1].data();  // row by row: column i is the geom's axis i
    const double* R2 = d_.geom_xmat[g2].data();
    const double* box1 = m_.geom_aabb[g1].data();
    const double* box2 = m_.geom_aabb[g2].data();
    const double* p1 = d_.geom_xpos[g1].data();
    const double* p2 = d_.geom_xpos[g2].data();
    double between[3];  // from box 1's centre to box 2's, in the world
    for (int r = 0; r < 3; ++r) {
      const double* row1 = R1 + 3 * r;
      const double* row2 = R2 + 3 * r;
      const double c1 = p1[r] + row1[0] * box1[0] + row1[1] * box1[1] + row1[2] * box1[2];
      const double c2 = p2[r] + row2[0] * box2[0] + row2[1] * box2[1] + row2[2] * box2[2];
      between[r] = c2 - c1;
    }
    const double reach = margin + kBoxesApart;  // besides the boxes' own half widths
    double C[3][3];  // |axis i of geom 1 . axis j of geom 2|, row i made before box 1's axis i
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        C[i][j] = std::abs(R1[i] * R2[j] + R1[3 + i] * R2[3 + j] + R1[6 + i] * R2[6 + j]);
      }
      const double along = R1[i] * between[0] + R1[3 + i] * between[1] + R1[6 + i] * between[2];
      const double half = box1[3 + i] + box2[3] * C[i][0] + box2[4] * C[i][1] + box2[5] * C[i][2];
      if (std::abs(along) > half + reach) return true;
    }
    for (int j = 0; j < 3; ++j) {
      const double along = R2[j] * between[0] + R2[3 + j] * between[1] + R2[6 + j] * between[2];
      const double half = box2[3 + j] + box1[3] * C[0][j] + box1[4] * C[1][j] + box1[5] * C[2][j];
      if (std::abs(along) > half + reach) return true;
    }
    return false;
  }

  /// A mesh geom whose mesh lever did not read (no vertices) has no shape to collide.
  bool unread_mesh(int g) const {
    return m_.geom_type[g] == GeomType::kMesh &&
           (m_.geom_dataid[g] < 0 || m_.mesh_vertnum[m_.geom_dataid[g]] == 0);
  }

  /// The geoms in the order of MuJoCo's table of pair functions (the lower type first).
  void in_type_order(int& g1, int& g2) const {
    if (static_cast<int>(m_.geom_type[g1]) > static_cast<int>(m_.geom_type[g2])) {
      std::swap(g1, g2);
    }
  }

  /// Planes and height fields among themselves: MuJoCo has no function for either.
  bool both_flat(int g1, int g2) const {
    const auto flat = [](GeomType t) { return t == GeomType::kPlane || t == GeomType::kHfield; };
    return flat(m_.geom_type[g1]) && flat(m_.geom_type[g2]);
  }

  /// The distance between two geoms' centres (the same number whichever comes first).
  double center_distance(int g1, int g2) const {
    const Vec3 dif = d_.geom_xpos[g1] - d_.geom_xpos[g2];
    return std::sqrt(dot3(dif, dif));
  }

  /// The bounding spheres apart, or a plane (g1 or g2, in type order) below the other geom's
  /// bounding sphere, by more than margin.
  bool bounds_apart(int g1, int g2, double margin) const {
    const double r1 = m_.geom_rbound[g1], r2 = m_.geom_rbound[g2];
    if (r1 > 0 && r2 > 0 && center_distance(g1, g2) > r1 + r2 + margin) return true;
    if (m_.geom_type[g1] == GeomType::kPlane && r2 > 0 && above_plane(g1, g2) > margin + r2) {
      return true;
    }
    return m_.geom_type[g2] == GeomType::kPlane && r1 > 0 && above_plane(g2, g1) > margin + r1;
  }

  /// A dynamic pair's margin (the geoms' larger, or opt.o_margin with override).
  double dynamic_margin(int g1, int g2) const {
    return m_.opt.enabled(kEnableOverride) ? m_.opt.o_margin
                                           : std::max(m_.geom_margin[g1], m_.geom_margin[g2]);
  }

  /// Whether collide_geoms(g1, g2, -1) returns before it has any effect, for the pair's
  /// types, filters or bounds.
  bool nothing_to_collide(int g1, int g2) const {
    in_type_order(g1, g2);
    return both_flat(g1, g2) || filtered_out(g1, g2) ||
           bounds_apart(g1, g2, dynamic_margin(g1, g2));
  }

  /// One geom pair: (g1, g2) of a dynamic pair, or explicit pair `ipair` (g1, g2 unused).
  void collide_geoms(int g1, int g2, int ipair) {
    if (ipair >= 0) {
      g1 = m_.pair_geom1[ipair];
      g2 = m_.pair_geom2[ipair];
    }
    in_type_order(g1, g2);
    const GeomType type1 = m_.geom_type[g1], type2 = m_.geom_type[g2];
    if (both_flat(g1, g2)) return;
    if (ipair < 0 && filtered_out(g1, g2)) return;

    // margin, gap, condim
    double margin, gap;
    int condim;
    if (ipair < 0) {
      margin = dynamic_margin(g1, g2);
      gap = std::max(m_.geom_gap[g1], m_.geom_gap[g2]);
      condim = m_.geom_priority[g1] != m_.geom_priority[g2]
                   ? m_.geom_condim[higher_priority(g1, g2)]
                   : std::max(m_.geom_condim[g1], m_.geom_condim[g2]);
    } else {
      margin = m_.pair_margin[ipair];
      gap = m_.pair_gap[ipair];
      condim = m_.pair_dim[ipair];
    }
    const bool override_contacts = m_.opt.enabled(kEnableOverride);
    if (override_contacts) margin = m_.opt.o_margin;

    // bounding spheres, and a plane against the other geom's bounding sphere
    if (bounds_apart(g1, g2, margin)) return;

    if (!has_collision_function(type1, type2) || unread_mesh(g1) || unread_mesh(g2)) {
      ++unsupported_;  // recorded in data.warning once the whole stage has succeeded
      last_unsupported_geom_ = g1;
      return;
    }

    if (collides_by_mpr(type1, type2) && boxes_apart(g1, g2, margin)) return;

    // The narrow phase writes each contact's dist, pos and whole frame: the normal, and zero
    // rows but where the pair sets a tangent (the capsule's axis). The buffer is Data's: nothing
    // is allocated or constructed per pair. Where the stage's own list has room for a pair's
    // most, the contacts are found in place there (not copied); else in the pair's buffer.
    const bool in_place = count_ + kMaxPairContacts <= m_.nconmax;
    Contact* found = in_place ? &d_.work.contact[count_] : d_.work.pair_contact.data();
    const ConvexOptions convex{m_.opt.mpr_tolerance, m_.opt.mpr_iterations,
                               m_.opt.enabled(kEnableMulticcd)};
    int n = collide_shapes(shape(g1), shape(g2), margin, found, convex);
    if (n == 0) return;
    if (type1 == GeomType::kBox && type2 == GeomType::kBox)
      n = detail::remove_repeated_positions(found, n);

    // friction, solref, solimp
    std::array<double, 5> friction;
    std::array<double, 2> solref;
    std::array<double, 5> solimp;
    if (ipair < 0) {
      mix_parameters(g1, g2, friction, solref, solimp);
    } else {
      friction = m_.pair_friction[ipair];
      solref = m_.pair_solref[ipair];
      solimp = m_.pair_solimp[ipair];
    }
    for (double& mu : friction) mu = std::max(kMinFriction, mu);
    if (override_contacts) {
      solref = m_.opt.o_solref;
      solimp = m_.opt.o_solimp;
    }

    // A contact's frame is made from the narrow phase's first two rows alone: a contact whose two
    // rows are the one before's, bit for bit (a plane's contacts share its normal), gets its
    // frame as made.
    std::array<double, 6> frame_rows;
    for (int i = 0; i < n; ++i) {
      Contact& c = found[i];  // completed where it was found
      c.dim = condim;
      c.geom1 = g1;
      c.geom2 = g2;
      c.includemargin = margin - gap;
      c.friction = friction;
      c.solref = solref;
      c.solimp = solimp;
      c.exclude = c.dist < c.includemargin ? 0 : 1;
      if (i > 0 && std::memcmp(c.frame.data(), frame_rows.data(), sizeof frame_rows) == 0) {
        c.frame = found[i - 1].frame;
      } else {
        std::memcpy(frame_rows.data(), c.frame.data(), sizeof frame_rows);
        if (!detail::complete_frame(c.frame)) {
          throw StateError("lever::collision: a contact normal is undefined (not a unit vector)");
        }
      }
      c.efc_address = -1;
      c.mu = 0;  // make_constraint sets it for a contact with friction rows
      if (count_ >= m_.nconmax) {
        throw StateError("lever::collision: more than nconmax = " + std::to_string(m_.nconmax) +
                         " contacts (contact number " + std::to_string(m_.nconmax + 1) +
                         " is between geoms " + geom_label(m_, g1) + " and " + geom_label(m_, g2) +
                         "); MuJoCo would drop the rest with a warning, lever refuses: raise "
                         "<size nconmax> (data.contact is left as it was)");
      }
      if (!in_place) d_.work.contact[count_] = c;
      ++count_;
    }
  }

  int higher_priority(int g1, int g2) const {
    return m_.geom_priority[g1] > m_.geom_priority[g2] ? g1 : g2;
  }

  /// Parameters of a dynamic pair: the higher priority's, else friction's max per component and
  /// solref/solimp weighted by solmix (solref's min per component when either is direct, < 0).
  void mix_parameters(int g1, int g2, std::array<double, 5>& friction,
                      std::array<double, 2>& solref, std::array<double, 5>& solimp) const {
    std::array<double, 3> mu;
    if (m_.geom_priority[g1] != m_.geom_priority[g2]) {
      const int g = higher_priority(g1, g2);
      for (int i = 0; i < 3; ++i) mu[i] = m_.geom_friction[g][i];
      solref = m_.geom_solref[g];
      solimp = m_.geom_solimp[g];
    } else {
      for (int i = 0; i < 3; ++i)
        mu[i] = std::max(m_.geom_friction[g1][i], m_.geom_friction[g2][i]);
      const double s1 = m_.geom_solmix[g1], s2 = m_.geom_solmix[g2];
      double mix;
      if (s1 >= kMinVal && s2 >= kMinVal) {
        mix = s1 / (s1 + s2);
      } else if (s1 < kMinVal && s2 < kMinVal) {
        mix = 0.5;
      } else {
        mix = s1 < kMinVal ? 0.0 : 1.0;
      }
      const auto& ref1 = m_.geom_solref[g1];
      const auto& ref2 = m_.geom_solref[g2];
      for (int i = 0; i < 2; ++i) {
        solref[i] = ref1[0] > 0 && ref2[0] > 0 ? mix * ref1[i] + (1 - mix) * ref2[i]
                                               : std::min(ref1[i], ref2[i]);
      }
      for (int i = 0; i < 5; ++i) {
        solimp[i] = m_.geom_solimp[g1][i] * mix;
        solimp[i] += m_.geom_solimp[g2][i] * (1 - mix);
      }
    }
    // sliding twice, torsional, rolling twice
    friction = {mu[0], mu[0], mu[1], mu[2], mu[2]};
  }
};

bool body_can_collide(const Model& model, int body) {
  for (int g = model.body_geomadr[body]; g < model.body_geomadr[body] + model.body_geomnum[body];
       ++g) {
    if (model.geom_contype[g] || model.geom_conaffinity[g]) return true;
  }
  return false;
}

bool body_has_plane_or_hfield(const Model& model, int body) {
  for (int g = model.body_geomadr[body]; g < model.body_geomadr[body] + model.body_geomnum[body];
       ++g) {
    if (model.geom_type[g] == GeomType::kPlane || model.geom_type[g] == GeomType::kHfield) {
      return true;
    }
  }
  return false;
}

/// The model's contact arrays have their sizes and the pair and exclusion lists are sorted by
/// signature (the merge relies on it); a ModelError names the first that is not.
void check_contact_model(const Model& model) {
  const auto fail = [](const std::string& what) {
    throw ModelError("lever::collision: " + what + " (compile the model with contact parameters)");
  };
  const auto ngeom = static_cast<size_t>(model.ngeom);
  const auto sized = [&](size_t n, const char* name) {
    if (n != ngeom) fail(std::string(name) + " has " + std::to_string(n) + " entries, not ngeom");
  };
  sized(model.geom_condim.size(), "geom_condim");
  sized(model.geom_priority.size(), "geom_priority");
  sized(model.geom_solmix.size(), "geom_solmix");
  sized(model.geom_friction.size(), "geom_friction");
  sized(model.geom_solref.size(), "geom_solref");
  sized(model.geom_solimp.size(), "geom_solimp");
  sized(model.geom_margin.size(), "geom_margin");
  sized(model.geom_gap.size(), "geom_gap");
  sized(model.geom_rbound.size(), "geom_rbound");
  sized(model.geom_dataid.size(), "geom_dataid");
  const auto npair = static_cast<size_t>(model.npair);
  for (size_t n : {model.pair_dim.size(), model.pair_geom1.size(), model.pair_geom2.size(),
                   model.pair_signature.size(), model.pair_solref.size(), model.pair_solimp.size(),
                   model.pair_margin.size(), model.pair_gap.size(), model.pair_friction.size()}) {
    if (n != npair) fail("a pair_ array does not have npair entries");
  }
  if (model.exclude_signature.size() != static_cast<size_t>(model.nexclude)) {
    fail("exclude_signature does not have nexclude entries");
  }
  if (!std::is_sorted(model.pair_signature.begin(), model.pair_signature.end()) ||
      !std::is_sorted(model.exclude_signature.begin(), model.exclude_signature.end())) {
    fail("pair_signature and exclude_signature must be sorted");
  }
  for (int p = 0; p < model.npair; ++p) {
    if (model.pair_geom1[p] < 0 || model.pair_geom1[p] >= model.ngeom || model.pair_geom2[p] < 0 ||
        model.pair_geom2[p] >= model.ngeom) {
      fail("pair " + std::to_string(p) + " names a geom that does not exist");
    }
  }
}

}  // namespace

namespace detail {

GeomShape geom_shape(const Model& model, const Data& data, int g) {
  const double* vert = nullptr;
  int vertnum = 0;
  const int* graph = nullptr;
  const HullNeighbour* hull = nullptr;
  const int mesh = model.geom_dataid[g];
  if (mesh >= 0 && model.mesh_vertnum[mesh] > 0) {
    vert = model.mesh_vert[static_cast<size_t>(model.mesh_vertadr[mesh])].data();
    vertnum = model.mesh_vertnum[mesh];
    const int address = model.mesh_graphadr[mesh];
    if (address >= 0) {
      graph = model.mesh_graph.data() + address;
      hull = model.mesh_hull_neighbours.data() + address;
    }
  }
  // every member given: nothing is set twice
  return GeomShape{model.geom_type[g], model.geom_size[g], data.geom_xpos[g], data.geom_xmat[g],
                   model.geom_rbound[g], vert, vertnum, graph, hull};
}

void build_collision_constants(Model& model) {
  // a body without joints moves with its parent (bodies come after their parents)
  std::fill(model.body_weldid.begin(), model.body_weldid.end(), 0);
  for (int b = 1; b < model.nbody; ++b) {
    model.body_weldid[b] = model.body_jntnum[b] > 0 ? b : model.body_weldid[model.body_parentid[b]];
  }
  // the world (with geoms), and static bodies holding a plane, are paired with every body
  std::fill(model.body_collision.begin(), model.body_collision.end(), 0);
  for (int b = 0; b < model.nbody; ++b) {
    if (!body_can_collide(model, b)) continue;
    const bool with_all = (b == 0 && model.body_geomnum[0] > 0) ||
                          (model.body_weldid[b] == 0 && body_has_plane_or_hfield(model, b));
    model.body_collision[b] =
        static_cast<std::uint8_t>(Model::kBodyCollides | (with_all ? Model::kBodyPairsWithAll : 0));
  }
  // each geom's box in its frame: what every support point of the geom lies in (the support
  // functions' points: a mesh's vertices, a box's corners, the primitives' surfaces)
  for (int g = 0; g < model.ngeom; ++g) {
    std::array<double, 6>& box = model.geom_aabb[g];
    box.fill(0.0);
    const Eigen::Vector3d& size = model.geom_size[g];
    switch (model.geom_type[g]) {
      case GeomType::kSphere: box[3] = box[4] = box[5] = size[0]; break;
      case GeomType::kCapsule:
        box[3] = box[4] = size[0];
        box[5] = size[0] + size[1];
        break;
      case GeomType::kCylinder:
        box[3] = box[4] = size[0];
        box[5] = size[1];
        break;
      case GeomType::kEllipsoid:
      case GeomType::kBox:
        for (int i = 0; i < 3; ++i) box[3 + i] = size[i];
        break;
      case GeomType::kMesh: {
        const int mesh = model.geom_dataid[g];
        if (mesh < 0 || model.mesh_vertnum[mesh] == 0) break;
        const Eigen::Vector3d* vert = model.mesh_vert.data() + model.mesh_vertadr[mesh];
        Eigen::Vector3d lo = vert[0], hi = vert[0];
        for (int v = 1; v < model.mesh_vertnum[mesh]; ++v) {
          lo = lo.cwiseMin(vert[v]);
          hi = hi.cwiseMax(vert[v]);
        }
        for (int i = 0; i < 3; ++i) {
          box[i] = 0.5 * (lo[i] + hi[i]);
          // the half size reaching both bounds from the rounded centre
          box[3 + i] = std::max(hi[i] - box[i], box[i] - lo[i]);
        }
        break;
      }
      default: break;  // planes and height fields: no support function
    }
  }
  // each hull neighbour's point beside its number, at its place in mesh_graph (the graphs are
  // well formed: set_const's validate checked them)
  for (int mesh = 0; mesh < model.nmesh; ++mesh) {
    const int address = model.mesh_graphadr[mesh];
    if (address < 0 || model.mesh_vertnum[mesh] == 0) continue;
    const int* graph = model.mesh_graph.data() + address;
    const int numvert = graph[0];
    const int* edge_address = graph + 2;
    const int* vertex_index = edge_address + numvert;
    const int* neighbours = vertex_index + numvert;
    const Eigen::Vector3d* vert = model.mesh_vert.data() + model.mesh_vertadr[mesh];
    HullNeighbour* table =
        model.mesh_hull_neighbours.data() + (neighbours - model.mesh_graph.data());
    HullNeighbour* lengths = model.mesh_hull_neighbours.data() + address + 2;
    for (int h = 0; h < numvert; ++h) {
      for (int e = edge_address[h];; ++e) {
        const int next = neighbours[e];
        HullNeighbour& entry = table[e];
        entry.vertex = next;
        entry.length = 0;
        for (int i = 0; i < 3; ++i) entry.point[i] = next >= 0 ? vert[vertex_index[next]][i] : 0.0;
        if (next < 0) {
          lengths[h] = HullNeighbour{{0.0, 0.0, 0.0}, e - edge_address[h], 0};
          break;
        }
      }
    }
    // each neighbour's own list length, beside its number
    for (int h = 0; h < numvert; ++h) {
      for (int e = edge_address[h]; neighbours[e] >= 0; ++e) {
        table[e].length = lengths[neighbours[e]].vertex;
      }
    }
  }
}

}  // namespace detail

void collision(const Model& model, Data& data) {
  check_entry(model, data, "lever::collision");
  check_contact_model(model);
  const auto nconmax = static_cast<size_t>(std::max(0, model.nconmax));
  if (data.contact.size() != nconmax || data.work.contact.size() != nconmax) {
    throw StateError("lever::collision: data.contact holds " + std::to_string(data.contact.size()) +
                     " contacts but the model's nconmax is " + std::to_string(model.nconmax) +
                     " (make the Data from this model)");
  }
  if (model.nconmax == 0 || model.nbody < 2) {
    data.ncon = 0;
    return;
  }
  Collider collider(model, data);
  collider.run();  // throws before data.contact or data.ncon change

  std::copy(data.work.contact.begin(), data.work.contact.begin() + collider.count(),
            data.contact.begin());
  data.ncon = collider.count();
  if (collider.unsupported() > 0) {
    WarningStat& stat = data.warning[static_cast<int>(Warning::kContactUnsupported)];
    stat.number += collider.unsupported();
    stat.lastinfo = collider.last_unsupported_geom();
  }
}

}  // namespace lever
