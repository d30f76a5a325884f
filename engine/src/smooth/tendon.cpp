// Tendons (MuJoCo 2.2.2's mj_tendon, the tendon part of mj_fwdVelocity and of mj_passive).
//
// A fixed tendon's length is a weighted sum of its joints' coordinates, L = sum_k c_k q_k (qpos
// itself, not its offset from qpos0), so its Jacobian is the constant row with c_k at each
// joint's dof: a joint named twice keeps its last coefficient, as MuJoCo writes it.
//
// A spatial tendon is a path of sites, each pair joined by a straight segment or, when a sphere or
// cylinder lies between them in the path, wrapped around it (wrap.cpp): two tangent segments and
// an arc. Its length is the sum of its segments, each branch after a pulley divided by the
// pulley's divisor. A segment's length changes as its ends move apart: d|b - a| = u . (db - da),
// with u the unit vector from a to b, so a segment between points of two different bodies adds
// u^T (J_b - J_a) to the tendon's Jacobian (J the points' translational Jacobians); the arc,
// whose two tangent points lie on the geom's body, adds nothing of its own (its change as the
// tangent points slide is second order).
//
// The Jacobian is dense, as MuJoCo's ten_J for models it keeps dense (nv < 60); its velocity is
// J qvel, summed as MuJoCo sums it for the model's layout (sparse_jacobian). Along each tendon acts a spring-damper, f = -stiffness (L - lengthspring) - damping v,
// carried to the dofs as J^T f.
#include <lever/dynamics.hpp>
#include <lever/kinematics.hpp>

#include "model/model_room.hpp"
#include "smooth/smooth.hpp"
#include "basics/basics.hpp"

#include <array>
#include <cmath>

namespace lever {

namespace {

// Tendon t's length and Jacobian row J along its joints.
double fixed_tendon(const Model& model, const Data& data, int t, double* J) {
  double length = 0.0;
  const int first = model.tendon_adr[t], end = first + model.tendon_num[t];
  for (int w = first; w < end; ++w) {
    const int joint = model.wrap_objid[w];
    const double coef = model.wrap_prm[w];
    length += coef * data.qpos[model.jnt_qposadr[joint]];
    J[model.jnt_dofadr[joint]] = coef;
  }
  return length;
}

// The path's next point, recorded in wrap_xpos and wrap_obj (two points per row).
void record_point(Data& data, int& point, const Eigen::Vector3d& x, int object) {
  std::array<double, 6>& row = data.wrap_xpos[point / 2];
  for (int c = 0; c < 3; ++c) row[3 * (point % 2) + c] = x[c];
  data.wrap_obj[point / 2][point % 2] = object;
  ++point;
}

// J += scale u^T (J_b - J_a), u the unit vector from a to b: the segment a-b's share of the
// tendon's Jacobian, a on body_a and b on body_b.
void add_segment_jacobian(const Model& model, Data& data, int body_a, const Eigen::Vector3d& a,
                          int body_b, const Eigen::Vector3d& b, double scale, double* J) {
  ArenaMatrix& jac = data.work.tendon_jac;  // rows 0-2: a's, 6-8: b's (3-5, 9-11 rotations)
  detail::point_jacobians(model, data, body_a, a, jac.middleRows(0, 3), jac.middleRows(3, 3));
  detail::point_jacobians(model, data, body_b, b, jac.middleRows(6, 3), jac.middleRows(9, 3));
  double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  const double norm = std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
  if (norm < detail::kMinVal) {
    u[0] = 1.0;  // MuJoCo's direction for coincident points
    u[1] = u[2] = 0.0;
  } else {
    const double inverse = 1.0 / norm;
    for (double& c : u) c *= inverse;
  }
  for (int j = 0; j < model.nv; ++j) {
    double rate = 0.0;
    for (int r = 0; r < 3; ++r) rate += (jac(6 + r, j) - jac(r, j)) * u[r];
    J[j] += rate * scale;
  }
}

double distance(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const double d[3] = {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
  return std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
}

bool is_wrapping_geom(WrapType type) { return type == WrapType::kSphere || type == WrapType::kCylinder; }

// Tendon t's length and Jacobian row J along its sites, wrapping geoms and pulleys; its points
// recorded from `point` on (advanced past them).
double spatial_tendon(const Model& model, Data& data, int t, double* J, int& point) {
  const int adr = model.tendon_adr[t], num = model.tendon_num[t];
  double length = 0.0;
  double divisor = 1.0;  // the current branch's: 1 until a pulley divides it
  int j = 0;
  while (j < num - 1) {
    const WrapType type0 = model.wrap_type[adr + j], type1 = model.wrap_type[adr + j + 1];
    if (type0 == WrapType::kPulley || type1 == WrapType::kPulley) {
      if (type0 == WrapType::kPulley) {
        // a new branch: its marker point at the origin, object -2
        divisor = model.wrap_prm[adr + j];
        record_point(data, point, Eigen::Vector3d::Zero(), -2);
      }
      ++j;
      continue;
    }
    // a site, then either a site, or a wrapping geom and a site (validate() says so)
    const int site0 = model.wrap_objid[adr + j];
    const int geom = is_wrapping_geom(type1) ? model.wrap_objid[adr + j + 1] : -1;
    const int site1 = model.wrap_objid[adr + j + (geom >= 0 ? 2 : 1)];
    Eigen::Vector3d x[4];
    int body[4];
    x[0] = data.site_xpos[site0];
    body[0] = model.site_bodyid[site0];
    double arc = -1;
    if (geom >= 0) {
      const int side = static_cast<int>(std::lround(model.wrap_prm[adr + j + 1]));
      arc = detail::wrap_around_geom(data.site_xpos[site0], data.site_xpos[site1],
                                     data.geom_xpos[geom], data.geom_xmat[geom],
                                     model.geom_size[geom][0], type1 == WrapType::kCylinder,
                                     side >= 0 ? &data.site_xpos[side] : nullptr, x[1], x[2]);
    }
    const int points = arc < 0 ? 2 : 4;  // straight, or site, two tangent points, site
    x[points - 1] = data.site_xpos[site1];
    body[points - 1] = model.site_bodyid[site1];
    if (arc < 0) {
      length += distance(x[0], x[1]) / divisor;
    } else {
      body[1] = body[2] = model.geom_bodyid[geom];
      length += (distance(x[0], x[1]) + arc + distance(x[2], x[3])) / divisor;
    }
    for (int k = 0; k + 1 < points; ++k) {
      if (body[k] == body[k + 1]) continue;  // a segment within one body keeps its length
      add_segment_jacobian(model, data, body[k], x[k], body[k + 1], x[k + 1], 1 / divisor, J);
    }
    // the points up to (not including) site1, which starts the next stretch
    record_point(data, point, x[0], -1);
    if (arc >= 0) {
      record_point(data, point, x[1], geom);
      record_point(data, point, x[2], geom);
    }
    j += geom >= 0 ? 2 : 1;
    // site1 ends the path or a branch: recorded here, as nothing starts from it
    if (j == num - 1 || model.wrap_type[adr + j + 1] == WrapType::kPulley) {
      record_point(data, point, x[points - 1], -1);
    }
  }
  return length;
}

}  // namespace

void unchecked::tendon(const Model& model, Data& data) {
  const int nv = model.nv;
  int point = 0;
  for (int t = 0; t < model.ntendon; ++t) {
    double* const J = data.ten_J.data() + static_cast<std::ptrdiff_t>(t) * nv;
    for (int j = 0; j < nv; ++j) J[j] = 0.0;
    data.ten_wrapadr[t] = point;
    if (model.wrap_type[model.tendon_adr[t]] == WrapType::kJoint) {
      data.ten_length[t] = fixed_tendon(model, data, t, J);
    } else {
      data.ten_length[t] = spatial_tendon(model, data, t, J, point);
    }
    data.ten_wrapnum[t] = point - data.ten_wrapadr[t];
  }
}

void unchecked::tendon_velocity(const Model& model, Data& data) {
  const int nv = model.nv;
  // summed as MuJoCo sums ten_J's rows: in order where it holds them sparse, else as mju_dot
  const bool sparse = sparse_jacobian(model.opt, nv);
  for (int t = 0; t < model.ntendon; ++t) {
    const double* const J = data.ten_J.data() + static_cast<std::ptrdiff_t>(t) * nv;
    data.ten_velocity[t] = row_dot_as_mujoco(sparse, J, data.qvel.data(), 0, nv, nv);
  }
}

void add_tendon_passive(const Model& model, Data& data) {
  const int nv = model.nv;
  double* const qfrc = data.qfrc_passive.data();
  for (int t = 0; t < model.ntendon; ++t) {
    const double f = -model.tendon_stiffness[t] * (data.ten_length[t] - model.tendon_lengthspring[t]) -
                     model.tendon_damping[t] * data.ten_velocity[t];
    const double* const J = data.ten_J.data() + static_cast<std::ptrdiff_t>(t) * nv;
    for (int j = 0; j < nv; ++j) qfrc[j] += J[j] * f;
  }
}

void tendon(const Model& model, Data& data) {
  check_entry(model, data, "lever::tendon");
  unchecked::tendon(model, data);
  unchecked::tendon_velocity(model, data);
}

}  // namespace lever
