// A spatial tendon's Jacobian differentiated: the tendon's path moves with the pose, so its
// Jacobian ten_J (the length's gradient) does too, and every force carried along it (its spring
// and damper, its actuators, its limit, friction-loss and coupling rows) changes through it.
//
// A straight segment from point a (carried by body A) to point b (body B), |b - a| = l, u its unit
// vector, adds u . (j_i(b) - j_i(a)) = u . dj_i to J_i (smooth/tendon.cpp), j_i(x) dof i's
// velocity at x as a point of its body (zero when i does not move the body). Along dof c, the
// points moving by da_c and db_c:
//   d J_i / d q_c = ((dx_c - u (u . dx_c)) / l) . dj_i + u . (d j_i(b) / d q_c - d j_i(a) / d q_c)
//   d j_i(x) / d q_c = [c carries i] (w_c x j_i(x) - w_i x j_c(x)) + w_i x (x's motion)
// with dx_c = db_c - da_c. A site's motion is j_c(site) (the connect anchor's rule follows). A
// wrap around a sphere or cylinder adds two segments, site -> tangent point and tangent point ->
// site, the tangent points carried by the geom's body (MuJoCo's Jacobian, the arc adding nothing)
// and sliding over it as the sites and the geom move: their motion is the wrap itself
// (smooth/wrap_path.hpp) on dual numbers, the two sites, the side site and the geom moving along
// dof c, every branch held (which pair of tangents, which way round, Newton's iterations through
// the geom). Each branch after a pulley is divided by its divisor; a segment within one body keeps
// its length.
#include <cmath>

#include "basics/basics.hpp"
#include "basics/dual.hpp"
#include "smooth/smooth.hpp"
#include "smooth/wrap_path.hpp"
#include "transition/transition.hpp"

namespace lever::detail {

namespace {

using Vec3 = Eigen::Vector3d;

// A point of a tendon's path: where it is, the body it is carried by (its rates j_i are that
// body's), and its motion per dof in motion[c] (a site's: j_c where c moves its body; a tangent
// point's: its slide over the geom too).
struct PathPoint {
  Vec3 x;
  int body;
  const Vec3* motion;
};

// T += scale d (u . dj) / d q for the segment from a to b (different bodies), dj = j(b) - j(a):
//   d J_i / d q_c = ((dx_c - u (u . dx_c)) / l) . dj_i + u . (d j_i(b) / d q_c - d j_i(a) / d q_c)
// with dx_c = b's motion - a's and d j_i(x) / d q_c = [c carries i] (w_c x j_i(x) - w_i x j_c(x))
// + w_i x (x's motion), for i moving x's body.
void add_segment_change(const Model& model, const Data& data, const PathPoint& a,
                        const PathPoint& b, double scale, Derivatives::Workspace& w,
                        Eigen::MatrixXd& T) {
  const int nv = model.nv;
  const double length = (b.x - a.x).norm();
  if (length < kMinVal) return;  // MuJoCo's fixed direction for coincident points: no turn
  const Vec3 u = (b.x - a.x) / length;
  std::vector<char>& on_a = w.moves1;
  std::vector<char>& on_b = w.moves2;
  dofs_moving(model, a.body, on_a);
  dofs_moving(model, b.body, on_b);
  Vec3* const j_a = w.equality_point_velocity.data();
  Vec3* const j_b = j_a + nv;
  for (int i = 0; i < nv; ++i) {
    j_a[i] = on_a[i] ? point_velocity(model, data, i, a.x) : Vec3::Zero();
    j_b[i] = on_b[i] ? point_velocity(model, data, i, b.x) : Vec3::Zero();
  }
  // u . d j_i(x) / d q_c for a point x of a body that dof i moves
  const auto rate_change = [&](const Vec3* j, const Vec3& motion, int i, int c, const Vec3& wi,
                               const Vec3& wc, bool carried) {
    Vec3 dj = wi.cross(motion);
    if (carried) dj += wc.cross(j[i]) - wi.cross(j[c]);
    return u.dot(dj);
  };
  for (int c = 0; c < nv; ++c) {
    const Vec3 dx_c = b.motion[c] - a.motion[c];
    if (!on_a[c] && !on_b[c] && a.motion[c].isZero(0) && b.motion[c].isZero(0)) continue;
    const Vec3 wc = data.cdof[c].head<3>();
    const Vec3 turn = (dx_c - u * u.dot(dx_c)) / length;  // d u / d q_c
    for (int i = 0; i < nv; ++i) {
      if (!on_a[i] && !on_b[i]) continue;
      const Vec3 wi = data.cdof[i].head<3>();
      const bool carried = w.carries[static_cast<std::size_t>(c * nv + i)] != 0;
      double change = turn.dot(j_b[i] - j_a[i]);
      if (on_b[i]) change += rate_change(j_b, b.motion[c], i, c, wi, wc, carried);
      if (on_a[i]) change -= rate_change(j_a, a.motion[c], i, c, wi, wc, carried);
      T(i, c) += scale * change;
    }
  }
}

// motion[c] = j_c(x) for the dofs that move body (a site's motion), 0 for the others.
void rigid_motion(const Model& model, const Data& data, int body, const Vec3& x,
                  std::vector<char>& moves, Vec3* motion) {
  dofs_moving(model, body, moves);
  for (int c = 0; c < model.nv; ++c) {
    motion[c] = moves[c] ? point_velocity(model, data, c, x) : Vec3::Zero();
  }
}

// The wrap of the path site0 -> site1 around geom g (side site `side`, -1 none) on dual numbers,
// the sites, the side site and the geom moving along each dof c in turn: the tangent points'
// motions into w.tangent_motion[c] (t0) and [nv + c] (t1). Returns whether the path wraps (else
// it runs straight and nothing is written); t0, t1 the tangent points.
bool wrap_motion(const Model& model, const Data& data, int site0, int site1, int g, int side,
                 Derivatives::Workspace& w, Vec3& t0, Vec3& t1) {
  const int nv = model.nv;
  const bool cylinder = model.geom_type[g] == GeomType::kCylinder;
  const Eigen::Vector3d* side_x = side >= 0 ? &data.site_xpos[side] : nullptr;
  if (wrap_around_geom(data.site_xpos[site0], data.site_xpos[site1], data.geom_xpos[g],
                       data.geom_xmat[g], model.geom_size[g][0], cylinder, side_x, t0, t1) < 0) {
    return false;
  }
  std::vector<char>& on = w.moves1;
  Vec3* const motion0 = w.tangent_motion.data();        // site0's, then the tangents'
  Vec3* const motion1 = motion0 + nv;
  Vec3* const motion_side = w.equality_point_velocity.data();
  Vec3* const motion_centre = motion_side + nv;
  rigid_motion(model, data, model.site_bodyid[site0], data.site_xpos[site0], on, motion0);
  rigid_motion(model, data, model.site_bodyid[site1], data.site_xpos[site1], on, motion1);
  if (side >= 0) rigid_motion(model, data, model.site_bodyid[side], data.site_xpos[side], on,
                              motion_side);
  rigid_motion(model, data, model.geom_bodyid[g], data.geom_xpos[g], on, motion_centre);
  const Mat3& R = data.geom_xmat[g];
  for (int c = 0; c < nv; ++c) {
    const Vec3 wc = on[c] ? Vec3(data.cdof[c].head<3>()) : Vec3::Zero();  // the geom's turn
    Dual x0[3], x1[3], centre[3], s[3], frame[3][3], d0[3], d1[3];
    for (int k = 0; k < 3; ++k) {
      x0[k] = {data.site_xpos[site0][k], motion0[c][k]};
      x1[k] = {data.site_xpos[site1][k], motion1[c][k]};
      centre[k] = {data.geom_xpos[g][k], motion_centre[c][k]};
      if (side >= 0) s[k] = {data.site_xpos[side][k], motion_side[c][k]};
    }
    for (int col = 0; col < 3; ++col) {
      const Vec3 axis = R.col(col), turn = wc.cross(axis);
      for (int k = 0; k < 3; ++k) frame[k][col] = {axis[k], turn[k]};
    }
    wrap_path::wrap(x0, x1, centre, frame, model.geom_size[g][0], cylinder,
                    side >= 0 ? s : nullptr, d0, d1);
    motion0[c] = Vec3(d0[0].d, d0[1].d, d0[2].d);
    motion1[c] = Vec3(d1[0].d, d1[1].d, d1[2].d);
  }
  return true;
}

}  // namespace

bool is_spatial_tendon(const Model& model, int t) {
  return model.tendon_num[t] > 0 && model.wrap_type[model.tendon_adr[t]] != WrapType::kJoint;
}

void spatial_tendon_change(const Model& model, const Data& data, int t,
                           Derivatives::Workspace& w) {
  const int nv = model.nv;
  Eigen::MatrixXd& T = w.tendon_change;
  T.setZero();
  const int adr = model.tendon_adr[t], num = model.tendon_num[t];
  Vec3* const site_motion = w.segment_motion.data();  // two sites' motions, nv each
  double divisor = 1.0;  // the current branch's
  int k = 0;
  while (k + 1 < num) {
    const WrapType type0 = model.wrap_type[adr + k], type1 = model.wrap_type[adr + k + 1];
    if (type0 == WrapType::kPulley || type1 == WrapType::kPulley) {
      if (type0 == WrapType::kPulley) divisor = model.wrap_prm[adr + k];
      ++k;
      continue;
    }
    const bool wraps = type1 == WrapType::kSphere || type1 == WrapType::kCylinder;
    const int site0 = model.wrap_objid[adr + k];
    const int site1 = model.wrap_objid[adr + k + (wraps ? 2 : 1)];
    const int body0 = model.site_bodyid[site0], body1 = model.site_bodyid[site1];
    const PathPoint a{data.site_xpos[site0], body0, site_motion};
    const PathPoint b{data.site_xpos[site1], body1, site_motion + nv};
    Vec3 t0, t1;
    const int g = wraps ? model.wrap_objid[adr + k + 1] : -1;
    const int side = wraps ? static_cast<int>(std::lround(model.wrap_prm[adr + k + 1])) : -1;
    if (wraps && wrap_motion(model, data, site0, site1, g, side, w, t0, t1)) {
      // site0 -> t0 and t1 -> site1, the tangent points carried by the geom's body and sliding
      // over it; the arc between them lies within one body
      const int body_g = model.geom_bodyid[g];
      const Vec3* tangents = w.tangent_motion.data();
      if (body0 != body_g) {
        rigid_motion(model, data, body0, data.site_xpos[site0], w.moves1, site_motion);
        add_segment_change(model, data, a, PathPoint{t0, body_g, tangents}, 1 / divisor, w, T);
      }
      if (body_g != body1) {
        rigid_motion(model, data, body1, data.site_xpos[site1], w.moves1, site_motion + nv);
        add_segment_change(model, data, PathPoint{t1, body_g, tangents + nv}, b, 1 / divisor, w,
                           T);
      }
    } else if (body0 != body1) {
      rigid_motion(model, data, body0, data.site_xpos[site0], w.moves1, site_motion);
      rigid_motion(model, data, body1, data.site_xpos[site1], w.moves1, site_motion + nv);
      add_segment_change(model, data, a, b, 1 / divisor, w, T);
    }
    k += wraps ? 2 : 1;
  }
}

void add_pair_product(const Model& model, const double* x, const double* y, const double* a,
                      double scale, Eigen::Ref<Eigen::VectorXd, 0, Eigen::InnerStride<>> out) {
  for (int i = 0; i < model.nv; ++i) {
    for (int j = i; j >= 0; j = model.dof_parentid[j]) {
      const double s_ij = x[i] * y[j] + y[i] * x[j];  // (x y^T + y x^T)(i, j), symmetric
      if (s_ij == 0.0) continue;
      out[i] += scale * s_ij * a[j];
      if (j != i) out[j] += scale * s_ij * a[i];
    }
  }
}

}  // namespace lever::detail
