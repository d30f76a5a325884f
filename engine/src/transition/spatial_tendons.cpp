// A spatial tendon's Jacobian differentiated: the tendon's path of sites moves with the pose, so
// its Jacobian ten_J (the length's gradient) does too, and every force carried along it (its
// spring and damper, its actuators, its limit and friction-loss rows) changes through it.
//
// A straight segment from point a (on body A) to point b (on body B), |b - a| = l, u its unit
// vector, adds u . (j_i(b) - j_i(a)) = u . dj_i to J_i (smooth/tendon.cpp), j_i(x) dof i's velocity
// at x (zero when i does not move x's body). Along dof c:
//   d J_i / d q_c = ((dj_c - u (u . dj_c)) / l) . dj_i  +  u . (d j_i(b) / d q_c - d j_i(a) / d q_c)
//   d j_i(x) / d q_c = [c carries i] (w_c x j_i(x) - w_i x j_c(x)) + w_i x j_c(x)   (c, i move x)
// (the rule of a connect's anchor, equality_rows.cpp). Each branch after a pulley is divided by its
// divisor. A segment within one body keeps its length. Wrapping (a sphere's or cylinder's tangent
// points slide over the geom as the sites move, a second-order term of the path) is refused by
// name.
#include <lever/error.hpp>

#include <string>

#include "basics/basics.hpp"
#include "transition/transition.hpp"

namespace lever::detail {

namespace {

using Vec3 = Eigen::Vector3d;

std::string tendon_label(const Model& model, int t) {
  return model.tendon_name[t].empty() ? std::to_string(t) : "'" + model.tendon_name[t] + "'";
}

// T += scale d (u . dj) / d q for the segment from site a to site b on different bodies.
void add_segment_change(const Model& model, const Data& data, int site_a, int site_b,
                        double scale, Derivatives::Workspace& w, Eigen::MatrixXd& T) {
  const int nv = model.nv;
  const Vec3 a = data.site_xpos[site_a], b = data.site_xpos[site_b];
  const double length = (b - a).norm();
  if (length < kMinVal) return;  // MuJoCo's fixed direction for coincident points: no turn
  const Vec3 u = (b - a) / length;
  std::vector<char>& on_a = w.moves1;
  std::vector<char>& on_b = w.moves2;
  dofs_moving(model, model.site_bodyid[site_a], on_a);
  dofs_moving(model, model.site_bodyid[site_b], on_b);
  Vec3* const j_a = w.equality_point_velocity.data();
  Vec3* const j_b = j_a + nv;
  for (int i = 0; i < nv; ++i) {
    j_a[i] = on_a[i] ? point_velocity(model, data, i, a) : Vec3::Zero();
    j_b[i] = on_b[i] ? point_velocity(model, data, i, b) : Vec3::Zero();
  }
  // u . d j_i(x) / d q_c for a point x that dofs i and c both move
  const auto point_change = [&](const Vec3* j, int i, int c, const Vec3& wi, const Vec3& wc,
                                bool carried) {
    Vec3 dj = wi.cross(j[c]);
    if (carried) dj += wc.cross(j[i]) - wi.cross(j[c]);
    return u.dot(dj);
  };
  for (int c = 0; c < nv; ++c) {
    if (!on_a[c] && !on_b[c]) continue;
    const Vec3 wc = data.cdof[c].head<3>();
    const Vec3 dj_c = j_b[c] - j_a[c];
    const Vec3 turn = (dj_c - u * u.dot(dj_c)) / length;  // d u / d q_c
    for (int i = 0; i < nv; ++i) {
      if (!on_a[i] && !on_b[i]) continue;
      const Vec3 wi = data.cdof[i].head<3>();
      const bool carried = w.carries[static_cast<std::size_t>(c * nv + i)] != 0;
      double change = turn.dot(j_b[i] - j_a[i]);
      if (on_b[i] && on_b[c]) change += point_change(j_b, i, c, wi, wc, carried);
      if (on_a[i] && on_a[c]) change -= point_change(j_a, i, c, wi, wc, carried);
      T(i, c) += scale * change;
    }
  }
}

}  // namespace

bool is_spatial_tendon(const Model& model, int t) {
  return model.tendon_num[t] > 0 && model.wrap_type[model.tendon_adr[t]] != WrapType::kJoint;
}

void refuse_wrapping_tendons(const Model& model) {
  for (int t = 0; t < model.ntendon; ++t) {
    const int first = model.tendon_adr[t], end = first + model.tendon_num[t];
    for (int k = first; k < end; ++k) {
      if (model.wrap_type[k] != WrapType::kSphere && model.wrap_type[k] != WrapType::kCylinder) {
        continue;
      }
      throw ModelError("derivatives: tendon " + tendon_label(model, t) + " wraps around geom '" +
                       model.geom_name[model.wrap_objid[k]] +
                       "'; lever's analytic derivatives cover spatial tendons of straight "
                       "segments (sites and pulleys) so far, not wrapping.");
    }
  }
  // a tendon coupling's Jacobian carries the tendons' Jacobians (contact_rows.cpp's coordinate
  // rows take them as constant)
  for (int e = 0; e < model.neq; ++e) {
    if (model.eq_type[e] != EqualityType::kTendon) continue;
    for (const int t : {model.eq_obj1id[e], model.eq_obj2id[e]}) {
      if (t < 0 || !is_spatial_tendon(model, t)) continue;
      throw ModelError("derivatives: equality constraint " +
                       (model.eq_name[e].empty() ? std::to_string(e) : "'" + model.eq_name[e] + "'") +
                       " couples spatial tendon " + tendon_label(model, t) +
                       "; lever's analytic derivatives cover couplings of fixed tendons so far.");
    }
  }
}

void spatial_tendon_change(const Model& model, const Data& data, int t,
                           Derivatives::Workspace& w) {
  Eigen::MatrixXd& T = w.tendon_change;
  T.setZero();
  const int adr = model.tendon_adr[t], num = model.tendon_num[t];
  double divisor = 1.0;  // the current branch's
  for (int k = 0; k + 1 < num; ++k) {
    const WrapType type0 = model.wrap_type[adr + k], type1 = model.wrap_type[adr + k + 1];
    if (type0 == WrapType::kPulley) {
      divisor = model.wrap_prm[adr + k];
      continue;
    }
    if (type1 == WrapType::kPulley) continue;
    const int site0 = model.wrap_objid[adr + k], site1 = model.wrap_objid[adr + k + 1];
    if (model.site_bodyid[site0] == model.site_bodyid[site1]) continue;
    add_segment_change(model, data, site0, site1, 1 / divisor, w, T);
  }
}

void add_pair_product(const Model& model, const double* x, const double* y, const double* a,
                      double scale, Eigen::Ref<Eigen::VectorXd> out) {
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
