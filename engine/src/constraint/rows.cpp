// MuJoCo 2.2.2's soft constraints (engine_core_constraint.c): the rows' order and their soft
// parameters; joint limits and contacts (equality constraints: equality.cpp; friction loss:
// friction_loss.cpp). MuJoCo's order: equality rows, friction-loss rows, limits, contacts.
//
// Rows: a joint within `margin` of a stop gives one (J = +-e_dof), a tendon within its margin of
// a stop one (J = +-ten_J, after every joint's); a contact (data.contact, from
// collision()) without friction one, J = n^T (J_2 - J_1) at its point. With friction, a pyramidal
// cone gives two rows per friction direction, the pyramid's edges n +- mu_k t_k (condim 3: two
// tangents; 4: and the spin about n; 6: and two rolling axes, from the rotational Jacobians); an
// elliptic cone gives the condim rows themselves, the normal first, then the friction directions.
// A row's target is the reference acceleration a_ref = -B v - K imp (pos - margin); an elliptic
// cone's friction rows have no position (pos = margin = 0, K = 0).
//
// Limit, frictionless and pyramidal rows are one-sided (a limit pushes, a pyramid edge pushes),
// and the forces that MuJoCo's Newton solver converges to satisfy, with A = J M^-1 J^T and R the
// regularizer, f >= 0, w = (A + R) f + (J qacc_smooth - a_ref) >= 0, f.w = 0 (a linear
// complementarity problem with a symmetric positive definite matrix, so its solution is unique).
// It is found exactly, in the smaller space: with no more rows than dofs by Murty's least-index
// principal pivoting on the rows (finite for such matrices; one row takes one step), with more
// rows than dofs (contacts) by active sets in dof space (solve_active_set). A model with elliptic
// cones, equality constraints or friction loss is solved by the Newton solver of
// constraint/newton.cpp instead (an elliptic cone, an equality row that pulls both ways and a
// friction-loss row's box on its force are not one-sided rows).
#include <lever/constraint.hpp>
#include <lever/dynamics.hpp>
#include <lever/error.hpp>
#include <lever/kinematics.hpp>

#include <Eigen/Cholesky>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <span>
#include <type_traits>

#include "constraint/constraint_room.hpp"
#include "model/model_room.hpp"
#include "smooth/smooth.hpp"

namespace lever {

namespace {

using detail::kMaxImp;
using detail::kMinImp;
using detail::kMinVal;

}  // namespace

void bound_solimp(std::array<double, 5>& solimp) {
  solimp[0] = std::min(kMaxImp, std::max(kMinImp, solimp[0]));
  solimp[1] = std::min(kMaxImp, std::max(kMinImp, solimp[1]));
  solimp[2] = std::max(0.0, solimp[2]);
  solimp[3] = std::min(kMaxImp, std::max(kMinImp, solimp[3]));
  solimp[4] = std::max(1.0, solimp[4]);
}

// solref and solimp sanitized as MuJoCo's getsolparam: the standard (positive) and direct
// (negative) forms cannot be mixed; a time constant no shorter than two steps (refsafe); solimp
// within its bounds.
void sanitize(const Model& model, std::array<double, 2>& solref, std::array<double, 5>& solimp) {
  if ((solref[0] > 0) != (solref[1] > 0)) solref = {0.02, 1.0};
  if (solref[0] > 0 && !model.opt.disabled(kDisableRefsafe)) {
    solref[0] = std::max(solref[0], 2 * model.opt.timestep);
  }
  bound_solimp(solimp);
}

// solref and solimp of a joint's limit, sanitized as MuJoCo's getsolparam does.
void limit_parameters(const Model& model, int jnt, std::array<double, 2>& solref,
                      std::array<double, 5>& solimp) {
  solref = model.jnt_solref[jnt];
  solimp = model.jnt_solimp[jnt];
  sanitize(model, solref, solimp);
}

namespace {

// Whether libm's pow(x, 2) is p = x * x (rounded), for x in (0, 1), found mostly without calling
// it. libm's pow (glibc's and musl's, both ARM's optimized routines) is within 0.54 ulp of the
// true x^2 = p + e: where |e| < 0.45 ulp of p (p not a power of two: one ulp on both sides), every
// other double is more than 0.55 ulp away, so pow returns p. e is exact by Dekker's product
// (Veltkamp's split, no fused multiply-add). About one x in ten is left to pow.
bool square_is_pow(double x, double& p) {
  p = x * x;
  const double c = 134217729.0 * x;  // 2^27 + 1
  const double hi = c - (c - x), lo = x - hi;
  const double e = ((hi * hi - p) + 2 * hi * lo) + lo * lo;
  std::uint64_t bits;
  std::memcpy(&bits, &p, sizeof bits);
  const std::uint64_t exponent = bits >> 52;  // p > 0
  if (exponent <= 200 || (bits & ((std::uint64_t{1} << 52) - 1)) == 0) return false;
  const std::uint64_t ulp_bits = (exponent - 52) << 52;
  double ulp;
  std::memcpy(&ulp, &ulp_bits, sizeof ulp);
  return std::abs(e) < 0.45 * ulp;
}

}  // namespace

// Impedance at a violation: solimp's sigmoid from d0 (at the margin) to dmax (width past it).
// With slope != nullptr, also d imp / d pos (zero on the flat parts; one-sided at their ends).
double impedance(const std::array<double, 5>& solimp, double pos, double margin, double* slope) {
  const double d0 = solimp[0], dmax = solimp[1], width = solimp[2];
  const double mid = solimp[3], power = solimp[4];
  if (slope != nullptr) *slope = 0.0;
  if (d0 == dmax || width <= kMinVal) return 0.5 * (d0 + dmax);
  const double x = std::abs((pos - margin) / width);
  if (x >= 1) return dmax;
  if (x <= 0) return d0;
  // y = a x^p up to the midpoint, 1 - b (1 - x)^p past it, a = 1 / mid^(p-1) and
  // b = 1 / (1 - mid)^(p-1), with pow as MuJoCo calls it: pow(x, 2) is not always x * x (libm's
  // pow is within an ulp, not correctly rounded), and that ulp reaches R and efc_D. The default
  // p = 2 spares the powers of mid and the slope's power (u^1 is u exactly) and mostly u^2's.
  double y, dy_dx;
  if (power == 1) {
    y = x;
    dy_dx = 1;
  } else {
    const bool near = x <= mid;
    const double u = near ? x : 1 - x;  // the distance from the flat end the branch starts at
    const double base = near ? mid : 1 - mid;
    const double scale = 1 / (power == 2 ? base : std::pow(base, power - 1));
    // (pow is called with the power as a variable: a constant 2 would be folded into u * u)
    double raised;
    if (!(power == 2 && square_is_pow(u, raised))) raised = std::pow(u, power);
    const double power_u = scale * raised;
    y = near ? power_u : 1 - power_u;
    dy_dx = power * scale * (power == 2 ? u : std::pow(u, power - 1));
  }
  if (slope != nullptr) {
    const double dx_dpos = (pos - margin < 0 ? -1.0 : 1.0) / width;
    *slope = (dmax - d0) * dy_dx * dx_dpos;
  }
  return d0 + y * (dmax - d0);
}

namespace {

// Room for `rows` more rows, or a StateError that changes nothing (MuJoCo warns and drops them).
void require_rows(const Model& model, const Data& data, int n, int rows) {
  if (n + rows > data.nefc_max) {
    throw StateError("lever::make_constraint: the contacts need more than the model's njmax = " +
                     std::to_string(model.njmax) +
                     " constraint rows; raise <size njmax=...> (MuJoCo would drop rows).");
  }
}

// Row n: joint j's stop on `sign`'s side (+1 lower, -1 upper) at distance dist.
void add_limit_row(const Model& model, Data& data, int n, int j, double sign, double dist) {
  if (n >= data.nefc_max) {
    throw StateError("lever::make_constraint: joint " + std::to_string(j) +
                     "'s limit was switched on after this Data was made, which has no room for "
                     "its rows; make a new Data for the edited model");
  }
  const int dof = model.jnt_dofadr[j];
  data.efc_type[n] = ConstraintType::kLimitJoint;
  data.efc_id[n] = j;
  data.efc_dof[n] = dof;
  data.efc_sign[n] = sign;
  data.efc_J.row(n).setZero();
  data.efc_J(n, dof) = sign;
  data.efc_pos[n] = dist;
  data.efc_margin[n] = model.jnt_margin[j];
}

// The limit rows after the n already made: lower stop, then upper, of each limited joint within
// margin of it. Returns the rows made so far.
int add_limit_rows(const Model& model, Data& data, int n) {
  const uint8_t* const limited = model.jnt_limited.data();
  const int* const qposadr = model.jnt_qposadr.data();
  const auto* const range = model.jnt_range.data();
  const double* const margin_of = model.jnt_margin.data();
  const double* const qpos = data.qpos.data();
  for (int j = 0; j < model.njnt; ++j) {
    if (!limited[j]) continue;
    const double q = qpos[qposadr[j]];
    const double margin = margin_of[j];
    // dist < 0 means past the stop; strict: resting exactly at the stop makes no row
    const double lower = q - range[j][0], upper = range[j][1] - q;
    if (lower < margin) add_limit_row(model, data, n++, j, 1.0, lower);
    if (upper < margin) add_limit_row(model, data, n++, j, -1.0, upper);
  }
  return n;
}

// The tendon limit rows after the n already made (MuJoCo's mj_instantiateLimit, after the joints'):
// lower stop (J = ten_J, distance L - lower), then upper (J = -ten_J, distance upper - L), each
// within the tendon's margin, with the tendon's limit solref, solimp and tendon_invweight0.
int add_tendon_limit_rows(const Model& model, Data& data, int n) {
  const int nv = model.nv;
  for (int t = 0; t < model.ntendon; ++t) {
    if (!model.tendon_limited[t]) continue;
    const double length = data.ten_length[t];
    const double margin = model.tendon_margin[t];
    const double* const J = data.ten_J.data() + static_cast<std::ptrdiff_t>(t) * nv;
    const double dist[2] = {length - model.tendon_range[t][0], model.tendon_range[t][1] - length};
    for (int side = 0; side < 2; ++side) {
      if (!(dist[side] < margin)) continue;
      const double sign = side == 0 ? 1.0 : -1.0;
      data.efc_type[n] = ConstraintType::kLimitTendon;
      data.efc_id[n] = t;
      data.efc_dof[n] = -1;
      data.efc_sign[n] = 0.0;
      for (int j = 0; j < nv; ++j) data.efc_J(n, j) = sign * J[j];
      data.efc_pos[n] = dist[side];
      data.efc_margin[n] = margin;
      std::array<double, 2> solref = model.tendon_solref_lim[t];
      std::array<double, 5> solimp = model.tendon_solimp_lim[t];
      sanitize(model, solref, solimp);
      const SoftParameters soft = soft_parameters(solref, solimp, dist[side], margin);
      set_soft_row(data, n, soft, soft.K, regularizer(soft, model.tendon_invweight0[t]));
      ++n;
    }
  }
  return n;
}

// The dofs that move a point of `body`, from its nearest body with dofs to the root, descending
// (MuJoCo's dof chain): into chain, returning how many.
int dof_chain(const Model& model, int body, int* chain) {
  while (body > 0 && model.body_dofnum[body] == 0) body = model.body_parentid[body];
  if (body == 0) return 0;
  int n = 0;
  for (int i = model.body_dofadr[body] + model.body_dofnum[body] - 1; i >= 0;
       i = model.dof_parentid[i]) {
    chain[n++] = i;
  }
  return n;
}

// The dofs that move two bodies' points against each other: each body's dof chain (into
// w.dof_chain: body 1's, then body 2's from nv on) without the dofs on both, and the span from
// the smallest to the largest of them. The contacts of one geom pair come one after another:
// found once for them.
struct PairDofs {
  int b1 = -1, b2 = -1;
  int n1 = 0, n2 = 0;  // the chains' lengths
  int lo = 0, span = 0;
};

void find_pair_dofs(const Model& model, Data& data, int b1, int b2, PairDofs& pair) {
  if (pair.b1 == b1 && pair.b2 == b2) return;
  const int nv = model.nv;
  int* chain1 = data.work.dof_chain.data();
  int* chain2 = chain1 + nv;
  int n1 = dof_chain(model, b1, chain1), n2 = dof_chain(model, b2, chain2);
  // the dofs on both paths are the common ancestors: the chains' common end
  while (n1 > 0 && n2 > 0 && chain1[n1 - 1] == chain2[n2 - 1]) --n1, --n2;
  // the span: from the smallest to the largest dof on one path only (chains descend)
  const int lo = std::min(n1 > 0 ? chain1[n1 - 1] : nv, n2 > 0 ? chain2[n2 - 1] : nv);
  const int hi = std::max(n1 > 0 ? chain1[0] : -1, n2 > 0 ? chain2[0] : -1);
  const int span = hi >= lo ? hi - lo + 1 : 0;
  pair = {b1, b2, n1, n2, span > 0 ? lo : 0, span};
}

// Contact i's frame rows, w.contact_frame_J rows first.., over its span of dofs: the relative
// velocity of the point on body 2 to the point on body 1 (MuJoCo's mj_jacDifPair, then frame * J
// summed as mju_mulMatMat). A dof on both bodies' paths to the root moves both points alike (the
// same cdof and the same tree's centre of mass: the difference is exactly zero), so the rows are
// nonzero only on the dofs of one path; the world has no dofs.
void contact_frame_rows(const Model& model, Data& data, int i, int first, PairDofs& pair) {
  const Contact& con = data.contact[i];
  auto& w = data.work;
  const int nv = model.nv;
  const int b1 = model.geom_bodyid[con.geom1], b2 = model.geom_bodyid[con.geom2];
  find_pair_dofs(model, data, b1, b2, pair);
  const int* chain1 = w.dof_chain.data();
  const int* chain2 = chain1 + nv;
  const int n1 = pair.n1, n2 = pair.n2, lo = pair.lo, span = pair.span;
  w.contact_span[2 * i] = lo;
  w.contact_span[2 * i + 1] = span;
  double* const C = w.contact_frame_J.data() + static_cast<std::ptrdiff_t>(first) * nv;
  if (n1 + n2 < span) {  // dofs of neither path inside the span (the two paths are disjoint)
    for (int k = 0; k < con.dim; ++k) {
      for (int j = lo; j < lo + span; ++j) C[k * nv + j] = 0.0;
    }
  }

  const Eigen::Vector3d offset1 = con.pos - data.subtree_com[model.body_rootid[b1]];
  const Eigen::Vector3d offset2 = con.pos - data.subtree_com[model.body_rootid[b2]];
  const Mat3 frame = con.frame;  // read once for every dof
  // the rows by the contact's dim: a constant for the common dims 3 and 1
  const auto dofs = [&](auto fixed_dim) {
    const int dim = fixed_dim > 0 ? static_cast<int>(fixed_dim) : con.dim;
    const int translations = dim < 3 ? dim : 3;   // the normal, then the two tangents
    const int rotations = dim > 3 ? dim - 3 : 0;  // spin, then the two rolls
    for (int pass = 0; pass < 2; ++pass) {
      const bool body2 = pass == 0;
      const int* chain = body2 ? chain2 : chain1;
      const int n = body2 ? n2 : n1;
      const Eigen::Vector3d& offset = body2 ? offset2 : offset1;
      for (int k = 0; k < n; ++k) {
        const int dof = chain[k];
        // the point's velocity per unit rate of the dof (as jac_point); body 1's counts negative
        const Motion& S = data.cdof[dof];
        Eigen::Vector3d p = S.tail<3>() + cross(S.head<3>(), offset);
        Eigen::Vector3d r = S.head<3>();
        if (!body2) {  // 0 - x rather than -x: MuJoCo's jac2 - jac1 with jac2 zero keeps zeros +0
          p = Eigen::Vector3d::Zero() - p;
          r = Eigen::Vector3d::Zero() - r;
        }
        const auto along_row = [&](int row, const Eigen::Vector3d& v) {
          return frame(row, 0) * v[0] + frame(row, 1) * v[1] + frame(row, 2) * v[2];
        };
        for (int row = 0; row < translations; ++row) C[row * nv + dof] = along_row(row, p);
        for (int row = 0; row < rotations; ++row) C[(3 + row) * nv + dof] = along_row(row, r);
      }
    }
  };
  if (con.dim == 3) {
    dofs(std::integral_constant<int, 3>{});
  } else if (con.dim == 1) {
    dofs(std::integral_constant<int, 1>{});
  } else {
    dofs(std::integral_constant<int, 0>{});
  }
}

// A pair of a pyramid's edges over `span` dofs: plus = normal + mu tangent, minus = normal - mu
// tangent (efc_J's rows and the frame's rows, which do not overlap: the loop runs on pairs of
// numbers).
void pyramid_edges(const double* __restrict normal, const double* __restrict tangent, double mu,
                   int span, double* __restrict plus, double* __restrict minus) {
  for (int j = 0; j < span; ++j) {
    plus[j] = normal[j] + mu * tangent[j];
    minus[j] = normal[j] - mu * tangent[j];
  }
}

// A contact's rows after the n already made (MuJoCo's mj_instantiateContact): its frame's rows,
// then its efc_J rows from them, dense.
int add_contact_rows(const Model& model, Data& data, int i, int n, PairDofs& pair) {
  Contact& con = data.contact[i];
  const int dim = con.dim;
  const bool elliptic = dim > 1 && model.opt.cone == Cone::kElliptic;
  const bool pyramid = dim > 1 && !elliptic;
  const int rows = pyramid ? 2 * (dim - 1) : elliptic ? dim : 1;
  require_rows(model, data, n, rows);
  contact_frame_rows(model, data, i, n, pair);
  con.efc_address = n;
  for (int r = n; r < n + rows; ++r) {
    data.efc_type[r] = pyramid    ? ConstraintType::kContactPyramidal
                       : elliptic ? ConstraintType::kContactElliptic
                                  : ConstraintType::kContactFrictionless;
    data.efc_id[r] = i;
    data.efc_dof[r] = -1;
    data.efc_sign[r] = 0.0;
    // an elliptic cone's friction rows have no distance of their own
    const bool friction_row = elliptic && r > n;
    data.efc_pos[r] = friction_row ? 0.0 : con.dist;
    data.efc_margin[r] = friction_row ? 0.0 : con.includemargin;
  }
  const int nv = model.nv;
  const int lo = data.work.contact_span[2 * i], span = data.work.contact_span[2 * i + 1];
  const double* C = data.work.contact_frame_J.data() + static_cast<std::ptrdiff_t>(n) * nv + lo;
  double* J = data.efc_J.data() + static_cast<std::ptrdiff_t>(n) * nv;
  for (int j = 0; j < rows * nv; ++j) J[j] = 0.0;
  J += lo;
  if (!pyramid) {  // the contact frame's rows as they are: normal, tangents, spin, rolls
    for (int k = 0; k < rows; ++k) {
      for (int j = 0; j < span; ++j) J[k * nv + j] = C[k * nv + j];
    }
    return n + rows;
  }
  // one pair of the pyramid's edges per friction direction: n + mu t, n - mu t
  for (int k = 1; k < dim; ++k, J += 2 * nv) {
    pyramid_edges(C, C + k * nv, con.friction[k - 1], span, J, J + nv);
  }
  return n + rows;
}

}  // namespace

void contact_normal_row(const Model& model, Data& data, int i, double* row) {
  const Contact& con = data.contact[i];
  const int nv = model.nv;
  for (int j = 0; j < nv; ++j) row[j] = 0.0;
  const int b1 = model.geom_bodyid[con.geom1], b2 = model.geom_bodyid[con.geom2];
  PairDofs pair;
  find_pair_dofs(model, data, b1, b2, pair);
  const int* chain1 = data.work.dof_chain.data();
  const int* chain2 = chain1 + nv;
  const Eigen::Vector3d normal = con.frame.row(0).transpose();
  for (int pass = 0; pass < 2; ++pass) {
    const bool body2 = pass == 0;
    const int* chain = body2 ? chain2 : chain1;
    const int n = body2 ? pair.n2 : pair.n1;
    const Eigen::Vector3d offset =
        con.pos - data.subtree_com[model.body_rootid[body2 ? b2 : b1]];
    for (int k = 0; k < n; ++k) {
      // as contact_frame_rows: the point's velocity per unit rate of the dof, body 1's negative
      const Motion& S = data.cdof[chain[k]];
      Eigen::Vector3d p = S.tail<3>() + cross(S.head<3>(), offset);
      if (!body2) p = Eigen::Vector3d::Zero() - p;
      row[chain[k]] = normal[0] * p[0] + normal[1] * p[1] + normal[2] * p[2];
    }
  }
}

SoftParameters soft_parameters(const std::array<double, 2>& solref,
                               const std::array<double, 5>& solimp, double pos, double margin) {
  SoftParameters soft;
  soft.imp = impedance(solimp, pos, margin, nullptr);
  const double dmax = solimp[1];
  if (solref[0] > 0) {
    soft.K = 1 / std::max(kMinVal, dmax * dmax * solref[0] * solref[0] * solref[1] * solref[1]);
  } else {
    soft.K = -solref[0] / std::max(kMinVal, dmax * dmax);
  }
  if (solref[1] > 0) {
    soft.B = 2 / std::max(kMinVal, dmax * solref[0]);
  } else {
    soft.B = -solref[1] / std::max(kMinVal, dmax);
  }
  return soft;
}

// Row r's soft parameters (MuJoCo's mj_makeImpedance) from its impedance, K, B and regularizer R:
// D = 1 / R, and the diagApprox that R was made from, R imp / (1 - imp).
void set_soft_row(Data& data, int r, const SoftParameters& soft, double K, double R) {
  set_soft_rows(data, r, 1, soft, K, R);
}

void set_soft_rows(Data& data, int first, int count, const SoftParameters& soft, double K,
                   double R) {
  const double D = 1 / R, diag = R * soft.imp / (1 - soft.imp);
  for (int r = first; r < first + count; ++r) {
    data.efc_imp[r] = soft.imp;
    data.efc_K[r] = K;
    data.efc_B[r] = soft.B;
    data.efc_R[r] = R;
    data.efc_D[r] = D;
    data.efc_diagApprox[r] = diag;
  }
}

// The regularizer R = (1 - imp) / imp * diagApprox of a row with approximate inverse inertia
// `diag` (MuJoCo's mj_diagApprox: frozen at qpos0 through dof_invweight0 and body_invweight0, not
// the current inverse inertia).
double regularizer(const SoftParameters& soft, double diag) {
  return std::max(kMinVal, (1 - soft.imp) * diag / soft.imp);
}

namespace {

// The limit rows' soft parameters (rows first..end).
void set_limit_soft_rows(const Model& model, Data& data, int first, int end) {
  for (int r = first; r < end; ++r) {
    std::array<double, 2> solref;
    std::array<double, 5> solimp;
    limit_parameters(model, data.efc_id[r], solref, solimp);
    const SoftParameters soft =
        soft_parameters(solref, solimp, data.efc_pos[r], data.efc_margin[r]);
    set_soft_row(data, r, soft, soft.K, regularizer(soft, model.dof_invweight0[data.efc_dof[r]]));
  }
}

// The soft parameters of the contact made last, for the next one: the contacts of one geom pair
// come one after another with the same solref and solimp (their sanitized values, K and B
// follow), and often at the same distance (a box flat on a plane: its four corners), where the
// impedance is the same too.
struct ContactSoftCache {
  bool valid = false;
  std::array<double, 2> solref;  // as the contact has them, before sanitize
  std::array<double, 5> solimp;
  double dist = 0, includemargin = 0;
  std::array<double, 2> sanitized_solref;
  std::array<double, 5> sanitized_solimp;
  SoftParameters soft;
};

// Contact i's soft parameters (its solref and solimp sanitized, then the impedance at its
// distance, K and B), from the cache where the previous contact had the same inputs.
SoftParameters contact_soft_parameters(const Model& model, const Contact& con,
                                       ContactSoftCache& cache) {
  const bool same_parameters =
      cache.valid && cache.solref == con.solref && cache.solimp == con.solimp;
  if (!same_parameters) {
    cache.solref = con.solref;
    cache.solimp = con.solimp;
    cache.sanitized_solref = con.solref;
    cache.sanitized_solimp = con.solimp;
    sanitize(model, cache.sanitized_solref, cache.sanitized_solimp);
    cache.valid = true;
  } else if (cache.dist == con.dist && cache.includemargin == con.includemargin) {
    return cache.soft;
  }
  cache.dist = con.dist;
  cache.includemargin = con.includemargin;
  cache.soft = soft_parameters(cache.sanitized_solref, cache.sanitized_solimp, con.dist,
                               con.includemargin);
  return cache.soft;
}

// Contact i's rows' soft parameters, computed once for the contact: its rows share its distance,
// so its impedance, K and B, and their R follow from the first row's. The first row's
// diagApprox is the two bodies' translational weights (a pyramid's first edge n + mu_0 t_0 adds
// mu_0^2 times the tangent's, translational too). Friction's regularizer: the first friction
// row's R_1 = R_0 / impratio sets the regularized cone's mu = friction_0 sqrt(R_1 / R_0). An
// elliptic cone's other friction rows get the R that keeps R_j friction_j^2 equal across
// directions; a pyramid's edges share one R, 2 mu^2 R_0, matching the elliptic cone's friction
// impedance. An elliptic cone's friction rows have no position to restore (K = 0).
// The rows of the contact made last whose every row has the same soft parameters (frictionless
// or pyramidal: one R for all): the next contact with the same impedance, K and B, bodies'
// weights, friction and rows gets the same R, D and diagApprox (the contacts of a box flat on
// a plane), copied from that contact's rows instead of made again through their chain of
// divisions.
struct ContactRowsCache {
  bool valid = false;
  SoftParameters soft{};
  double translation = 0, mu0 = 0;
  ConstraintType type = ConstraintType::kContactFrictionless;
  int rows = 0;
  int first = 0;  // the rows to copy
  double mu = 0;
};

void set_contact_soft_rows(const Model& model, Data& data, int i, ContactSoftCache& cache,
                           ContactRowsCache& made) {
  Contact& con = data.contact[i];
  const int first = con.efc_address;
  const SoftParameters soft = contact_soft_parameters(model, con, cache);
  const int b1 = model.geom_bodyid[con.geom1], b2 = model.geom_bodyid[con.geom2];
  const double translation = model.body_invweight0[b1][0] + model.body_invweight0[b2][0];
  const ConstraintType type = data.efc_type[first];
  const double mu0 = con.friction[0];
  const int rows = type == ConstraintType::kContactPyramidal ? 2 * (con.dim - 1) : 1;
  if (type != ConstraintType::kContactElliptic) {
    if (made.valid && made.type == type && made.rows == rows && made.soft.imp == soft.imp &&
        made.soft.K == soft.K && made.soft.B == soft.B && made.translation == translation &&
        made.mu0 == mu0) {
      for (int r = first; r < first + rows; ++r) {
        data.efc_imp[r] = data.efc_imp[made.first];
        data.efc_K[r] = data.efc_K[made.first];
        data.efc_B[r] = data.efc_B[made.first];
        data.efc_R[r] = data.efc_R[made.first];
        data.efc_D[r] = data.efc_D[made.first];
        data.efc_diagApprox[r] = data.efc_diagApprox[made.first];
      }
      if (type == ConstraintType::kContactPyramidal) con.mu = made.mu;
      return;
    }
    made = {true, soft, translation, mu0, type, rows, first, 0.0};
  }
  if (type == ConstraintType::kContactFrictionless) {
    set_soft_row(data, first, soft, soft.K, regularizer(soft, translation));
    return;
  }
  const bool pyramid = type == ConstraintType::kContactPyramidal;
  const double R0 =
      regularizer(soft, pyramid ? translation + mu0 * mu0 * translation : translation);
  const double R1 = R0 / std::max(kMinVal, model.opt.impratio);
  con.mu = mu0 * std::sqrt(R1 / R0);
  if (pyramid) {
    const double shared = 2 * con.mu * con.mu * R0;
    set_soft_rows(data, first, 2 * (con.dim - 1), soft, soft.K, shared);
    made.mu = con.mu;
    return;
  }
  set_soft_row(data, first, soft, soft.K, R0);
  set_soft_row(data, first + 1, soft, 0.0, R1);
  for (int k = 1; k < con.dim - 1; ++k) {
    set_soft_row(data, first + k + 1, soft, 0.0,
                 R1 * con.friction[0] * con.friction[0] / (con.friction[k] * con.friction[k]));
  }
}

}  // namespace

void unchecked::make_constraint(const Model& model, Data& data) {
  const Options& opt = model.opt;
  data.work.sparse_row_sums = sparse_jacobian(opt, model.nv);
  if (opt.disabled(kDisableConstraint)) {  // no rows at all (and no contacts: see set_const)
    data.ne = data.nf = data.nefc = 0;
    return;
  }
  data.ne =
      opt.disabled(kDisableEquality) || model.neq == 0 ? 0 : add_equality_rows(model, data, 0);
  data.nf = opt.disabled(kDisableFrictionloss) || !model.has_friction_loss
                ? 0
                : add_friction_loss_rows(model, data, data.ne) - data.ne;
  int n = data.ne + data.nf;
  if (!opt.disabled(kDisableLimit)) {
    const int limits = add_limit_rows(model, data, n);
    set_limit_soft_rows(model, data, n, limits);
    n = add_tendon_limit_rows(model, data, limits);
  }
  PairDofs pair;
  ContactSoftCache soft_cache;
  ContactRowsCache rows_cache;
  const int ncon = opt.disabled(kDisableContact) ? 0 : data.ncon;
  for (int i = 0; i < ncon; ++i) {
    Contact& con = data.contact[i];
    con.efc_address = -1;
    if (con.exclude) continue;
    n = add_contact_rows(model, data, i, n, pair);
    set_contact_soft_rows(model, data, i, soft_cache, rows_cache);
  }
  data.nefc = n;
  for (int r = data.ne + data.nf; r < n; ++r) data.efc_frictionloss[r] = 0.0;
}

void make_constraint(const Model& model, Data& data) {
  check_entry(model, data, "lever::make_constraint");
  unchecked::make_constraint(model, data);
}

namespace {

// to[i] -= from[i] * scale for i < count (two columns of one matrix: they do not overlap).
void subtract_scaled(const double* __restrict from, double scale, int count,
                     double* __restrict to) {
  for (int i = 0; i < count; ++i) to[i] -= from[i] * scale;
}

// x = H^-1 x for a symmetric positive definite H given by its lower triangle, which is replaced
// by its Cholesky factor L (H = L L^T). nv x nv with nv a few dozen at most: plain loops, column
// by column (right-looking: each finished column updates the ones after it), each column's loops
// ending at its last nonzero (the dofs of trees that no contact joins never meet: a gripper and
// a free box are two blocks). column_end: nv ints of scratch.
void cholesky_solve(Eigen::Ref<Eigen::MatrixXd> H, Eigen::Ref<Eigen::VectorXd> x,
                    std::span<int> column_end) {
  const int nv = static_cast<int>(x.size());
  int* const end = column_end.data();  // one past column j's last nonzero
  for (int j = 0; j < nv; ++j) {
    double* Lj = H.data() + static_cast<std::ptrdiff_t>(j) * nv;
    int e = nv;  // column j is final here: every column before it has updated it
    while (e > j + 1 && Lj[e - 1] == 0.0) --e;
    end[j] = e;
    const double Ljj = std::sqrt(Lj[j]);
    Lj[j] = Ljj;
    for (int i = j + 1; i < e; ++i) Lj[i] /= Ljj;
    for (int k = j + 1; k < e; ++k) {
      if (Lj[k] == 0.0) continue;
      subtract_scaled(Lj + k, Lj[k], e - k, H.data() + static_cast<std::ptrdiff_t>(k) * nv + k);
    }
  }
  // L y = x, column by column: y_j, once final, leaves the rows below
  for (int j = 0; j < nv; ++j) {
    x[j] /= H(j, j);
    for (int i = j + 1; i < end[j]; ++i) x[i] -= H(i, j) * x[j];
  }
  for (int i = nv - 1; i >= 0; --i) {  // L^T x = y
    double sum = x[i];
    for (int k = i + 1; k < end[i]; ++k) sum -= H(k, i) * x[k];
    x[i] = sum / H(i, i);
  }
}

// H += weight v v^T, v over the span of `count` dofs from `lo`: the whole block, though only
// its lower triangle is read (a loop of one length vectorizes; one of falling lengths does not).
void add_rank_one(Eigen::Ref<Eigen::MatrixXd> H, int lo, int count, double weight,
                  const double* v) {
  const Eigen::Index nv = H.rows();
  double* column = H.data() + (lo * nv + lo);  // column lo + b from its row lo, for each b
  for (int b = 0; b < count; ++b, column += nv) {
    if (v[b] == 0.0) continue;
    const double wb = weight * v[b];
    for (int a = 0; a < count; ++a) column[a] += wb * v[a];
  }
}

// Two neighbouring numbers of a column, worked on together (the same sums, one per number).
using Pair = Eigen::Array2d;

// column[a] += sum_k wc_k c_k[a] for a < count (H's column and the frame's rows do not overlap),
// two numbers at a time.
template <int Dim>
void add_weighted_rows(const double* __restrict c, Eigen::Index stride, const double* wc,
                       int count, double* __restrict column) {
  int a = 0;
  for (; a + 2 <= count; a += 2) {
    Pair sum = Pair::Map(c + a) * wc[0];
    for (int k = 1; k < Dim; ++k) sum += Pair::Map(c + k * stride + a) * wc[k];
    Pair::Map(column + a) += sum;
  }
  for (; a < count; ++a) {
    double sum = wc[0] * c[a];
    for (int k = 1; k < Dim; ++k) sum += wc[k] * c[k * stride + a];
    column[a] += sum;
  }
}

// H += sum_k W_k c_k c_k^T over the span of `count` dofs from `lo`, c_k a contact's frame row k
// (rows `stride` apart): one pass over the block's lower triangle (what the solve reads; the
// columns' numbers two at a time) for all of the frame's rows. Dim is a template argument so that
// the sum over the rows unrolls.
template <int Dim>
void add_frame_weights(Eigen::Ref<Eigen::MatrixXd> H, int lo, int count, const double* c,
                       Eigen::Index stride, const double* W) {
  const Eigen::Index nv = H.rows();
  double* column = H.data() + (lo * nv + lo);  // column lo + b from its row lo, for each b
  for (int b = 0; b < count; ++b, column += nv) {
    double wc[Dim];
    bool any = false;
    for (int k = 0; k < Dim; ++k) {
      wc[k] = W[k] * c[k * stride + b];
      any = any || wc[k] != 0.0;
    }
    if (!any) continue;
    // the column from the diagonal down: the lower triangle, which is all the solve reads
    add_weighted_rows<Dim>(c + b, stride, wc, count - b, column + b);
  }
}

// kernel(Dim) with a contact's dim (1 to 6) as a compile-time constant (std::integral_constant),
// so that the kernels' loops over the frame's rows unroll
template <class Kernel>
void with_dim(int dim, Kernel&& kernel) {
  switch (dim) {
    case 1: return kernel(std::integral_constant<int, 1>{});
    case 2: return kernel(std::integral_constant<int, 2>{});
    case 3: return kernel(std::integral_constant<int, 3>{});
    case 4: return kernel(std::integral_constant<int, 4>{});
    case 5: return kernel(std::integral_constant<int, 5>{});
    default: return kernel(std::integral_constant<int, 6>{});
  }
}

// out[lo..lo + span) += sum_k a_k f_k over `count` rows a_k (`stride` apart) with nonzero forces
// f_k, each out[j] adding the rows' products in the rows' order, as MuJoCo's J^T f adds them row
// after row. Count is a template argument so that the loop over the rows unrolls.
template <int Count>
void add_rows_at(const double* const* a, const double* f, int lo, int span,
                 double* __restrict out) {
  const double* row[Count];
  double force[Count];
  for (int k = 0; k < Count; ++k) row[k] = a[k], force[k] = f[k];
  int j = lo;
  for (; j + 2 <= lo + span; j += 2) {  // two dofs at a time
    Pair o = Pair::Map(out + j);
    for (int k = 0; k < Count; ++k) o += Pair::Map(row[k] + j) * force[k];
    Pair::Map(out + j) = o;
  }
  for (; j < lo + span; ++j) {
    double o = out[j];
    for (int k = 0; k < Count; ++k) o += row[k][j] * force[k];
    out[j] = o;
  }
}

void add_rows(const double* const* a, const double* f, int count, int lo, int span, double* out) {
  switch (count) {
    case 1: return add_rows_at<1>(a, f, lo, span, out);
    case 2: return add_rows_at<2>(a, f, lo, span, out);
    case 3: return add_rows_at<3>(a, f, lo, span, out);
    case 4: return add_rows_at<4>(a, f, lo, span, out);
    default:
      for (int j = lo; j < lo + span; ++j) {
        double o = out[j];
        for (int k = 0; k < count; ++k) o += a[k][j] * f[k];
        out[j] = o;
      }
  }
}

}  // namespace

void rows_times(const Data& data, const double* x, double* out) {
  const int nv = static_cast<int>(data.efc_J.cols());
  const bool sparse = data.work.sparse_row_sums;
  for (int r = 0; r < data.nefc;) {
    if (dense_row(data.efc_type[r])) {
      out[r] = row_dot_as_mujoco(sparse, data.efc_J.row(r).data(), x, 0, nv, nv);
      ++r;
      continue;
    }
    if (data.efc_dof[r] >= 0) {  // a limit row: J_r = sign e_dof
      out[r] = data.efc_sign[r] * x[data.efc_dof[r]];
      ++r;
      continue;
    }
    const int i = data.efc_id[r];
    const Contact& con = data.contact[i];
    const int lo = data.work.contact_span[2 * i], span = data.work.contact_span[2 * i + 1];
    // efc_J's rows over the span, zero outside it: the frame's own rows, or a pyramid's edges
    // n +- mu t as efc_J holds them (c0 +- mu ck from the frame's products rounds otherwise)
    const int rows =
        data.efc_type[r] == ConstraintType::kContactPyramidal ? 2 * (con.dim - 1) : con.dim;
    if (sparse) {
      rows_dot_in_order(data.efc_J.row(r).data(), nv, rows, x, lo, lo + span, out + r);
    } else {
      rows_dot_as_mujoco(data.efc_J.row(r).data(), nv, rows, x, lo, lo + span, nv, out + r);
    }
    r += rows;
  }
}

void rows_jar(const Data& data, const double* x, double* out) {
  rows_times(data, x, out);
  for (int r = 0; r < data.nefc; ++r) out[r] -= data.efc_aref[r];
}

void add_rows_transpose(const Data& data, const double* f, double* out) {
  const int nv = static_cast<int>(data.efc_J.cols());
  for (int r = 0; r < data.nefc;) {
    if (dense_row(data.efc_type[r])) {
      const double* J = data.efc_J.row(r).data();
      if (f[r] != 0.0) {
        for (int j = 0; j < nv; ++j) out[j] += J[j] * f[r];
      }
      ++r;
      continue;
    }
    if (data.efc_dof[r] >= 0) {
      out[data.efc_dof[r]] += data.efc_sign[r] * f[r];
      ++r;
      continue;
    }
    const int i = data.efc_id[r];
    const Contact& con = data.contact[i];
    const int lo = data.work.contact_span[2 * i], span = data.work.contact_span[2 * i + 1];
    // efc_J's rows over the span with a force, added in turn as MuJoCo's J^T f adds them (a
    // row without one adds nothing): the frame's own rows, or a pyramid's edges n +- mu t
    const int end =
        r + (data.efc_type[r] == ConstraintType::kContactPyramidal ? 2 * (con.dim - 1) : con.dim);
    const double* rows[10];
    double forces[10];
    int count = 0;
    for (; r < end; ++r) {
      if (f[r] == 0.0) continue;
      rows[count] = data.efc_J.row(r).data();
      forces[count++] = f[r];
    }
    if (count > 0) add_rows(rows, forces, count, lo, span, out);
  }
}

void add_rows_hessian(Data& data, const double* weight, Eigen::Ref<Eigen::MatrixXd> H) {
  const auto& C = data.work.contact_frame_J;
  const int nv = static_cast<int>(data.efc_J.cols());
  for (int r = 0; r < data.nefc;) {
    if (dense_row(data.efc_type[r])) {
      if (weight[r] != 0.0) add_rank_one(H, 0, nv, weight[r], data.efc_J.row(r).data());
      ++r;
      continue;
    }
    if (data.efc_dof[r] >= 0) {  // a limit row: J_r = sign e_dof, sign^2 = 1
      H(data.efc_dof[r], data.efc_dof[r]) += weight[r];
      ++r;
      continue;
    }
    const int i = data.efc_id[r];
    const Contact& con = data.contact[i];
    const int lo = data.work.contact_span[2 * i], span = data.work.contact_span[2 * i + 1];
    const int frame = r;
    double frame_weight[6] = {};  // along the frame's rows
    if (data.efc_type[r] != ConstraintType::kContactPyramidal) {
      for (int k = 0; k < con.dim; ++k) frame_weight[k] = weight[r++];
    } else {
      // A pair of edges n +- mu t that both push adds d+ (n + mu t)(..)^T + d- (n - mu t)(..)^T
      // = (d+ + d-) n n^T + mu^2 (d+ + d-) t t^T when d+ = d- (the edges of a pyramid share R):
      // a weight along t, and the normal's gathered over the pairs. A lone edge adds its own.
      for (int k = 1; k < con.dim; ++k, r += 2) {
        const double plus = weight[r], minus = weight[r + 1];
        if (plus != 0.0 && plus == minus) {
          const double mu = con.friction[k - 1];
          frame_weight[0] += plus + minus;
          frame_weight[k] = mu * mu * (plus + minus);
        } else {
          if (plus != 0.0) add_rank_one(H, lo, span, plus, data.efc_J.row(r).data() + lo);
          if (minus != 0.0) add_rank_one(H, lo, span, minus, data.efc_J.row(r + 1).data() + lo);
        }
      }
    }
    with_dim(con.dim, [&](auto dim) {
      add_frame_weights<dim>(H, lo, span, C.row(frame).data() + lo, C.cols(), frame_weight);
    });
  }
}

void add_frame_hessian(Data& data, int i, const double* W, Eigen::Ref<Eigen::MatrixXd> H) {
  const Contact& con = data.contact[i];
  const int dim = con.dim, first = con.efc_address;
  const int lo = data.work.contact_span[2 * i], span = data.work.contact_span[2 * i + 1];
  const auto C = data.work.contact_frame_J.block(first, lo, dim, span);
  // G = W C over the span (dim x span), then the lower triangle of C^T G
  double* G = data.work.frame_scratch.data();
  for (int k = 0; k < dim; ++k) {
    for (int j = 0; j < span; ++j) {
      double sum = 0.0;
      for (int l = 0; l < dim; ++l) sum += W[k * dim + l] * C(l, j);
      G[k * span + j] = sum;
    }
  }
  for (int b = 0; b < span; ++b) {
    double* column = H.data() + static_cast<std::ptrdiff_t>(lo + b) * H.rows() + lo;
    for (int a = b; a < span; ++a) {
      double sum = 0.0;
      for (int k = 0; k < dim; ++k) sum += C(k, a) * G[k * span + b];
      column[a] += sum;
    }
  }
}

void solve_with_hessian(Data& data, Eigen::Ref<Eigen::MatrixXd> H, Eigen::Ref<Eigen::VectorXd> x) {
  cholesky_solve(H, x, data.work.hessian_envelope);
}

void unchecked::reference_constraint(const Model& /*model*/, Data& data) {
  if (data.nefc == 0) return;
  rows_times(data, data.qvel.data(), data.efc_vel.data());
  for (int r = 0; r < data.nefc; ++r) {
    data.efc_aref[r] = -data.efc_B[r] * data.efc_vel[r] -
                       data.efc_K[r] * data.efc_imp[r] * (data.efc_pos[r] - data.efc_margin[r]);
  }
}

void reference_constraint(const Model& model, Data& data) {
  check_entry(model, data, "lever::reference_constraint");
  unchecked::reference_constraint(model, data);
}

bool active_set_round(Data& data, const int* active) {
  auto& w = data.work;
  const int n = data.nefc;
  auto& a = w.newton_dir;
  const double* D = data.efc_D.data();
  const double* aref = data.efc_aref.data();
  // a = M a_smooth + J_S^T D_S aref_S, where M a_smooth is qfrc_smooth (as MuJoCo's gradient
  // M a - qfrc_smooth has it), and H = M + J_S^T D_S J_S, each contact's part in its frame
  for (int r = 0; r < n; ++r) w.lcp_f[r] = active[r] ? D[r] * aref[r] : 0.0;
  a = data.qfrc_smooth;
  add_rows_transpose(data, w.lcp_f.data(), a.data());
  for (int r = 0; r < n; ++r) w.lcp_f[r] = active[r] ? D[r] : 0.0;
  w.newton_H = data.M;
  add_rows_hessian(data, w.lcp_f.data(), w.newton_H);
  solve_with_hessian(data, w.newton_H, a);
  // the rows that push at a; the same set: settled
  rows_jar(data, a.data(), w.newton_jar.data());
  for (int r = 0; r < n; ++r) {
    if ((w.newton_jar[r] < 0) != (active[r] != 0)) return false;
  }
  return true;
}

bool solved_by_active_sets(const Model& model, const Data& data) {
  const Options& opt = model.opt;
  return opt.solver != Solver::kPGS && !(opt.solver == Solver::kCG && opt.tolerance > 0) &&
         opt.cone != Cone::kElliptic && data.ne + data.nf == 0 && data.nefc > model.nv;
}

bool settled_active_set_factor(const Model& model, const Data& data) {
  if (!solved_by_active_sets(model, data)) return false;
  // its last round settled: qacc is that round's a, each row's weight is what active_set_round
  // gave it (D pushing, 0 not) and each force what solve_active_set made of its jar; the
  // pivoting, which takes over when the rounds do not settle, leaves its own forces in lcp_f
  const auto& w = data.work;
  for (int i = 0; i < model.nv; ++i) {
    if (data.qacc[i] != w.newton_dir[i]) return false;
  }
  for (int r = 0; r < data.nefc; ++r) {
    const bool pushing = data.efc_state[r] == ConstraintState::kActive;
    const double D = data.efc_D[r];
    if (w.lcp_f[r] != (pushing ? D : 0.0)) return false;
    if (data.efc_force[r] != (pushing ? -D * w.newton_jar[r] : 0.0)) return false;
  }
  return true;
}

namespace {

// Most rounds of the active-set solve before the pivoting takes over: settling takes one or two
// (a contact that starts or stops pushing moves one row), a cycle is what the bound catches.
constexpr int kMaxActiveSetRounds = 8;

// The one-sided rows' problem solved in dof space. For a set S of pushing rows the cost
// 1/2 |a - a_smooth|_M^2 + sum_S 1/2 D_r (J_r a - aref_r)^2 is one quadratic, minimized by
//   (M + J_S^T D_S J_S) a = M a_smooth + J_S^T D_S aref_S         (nv x nv, whatever the rows)
// (Newton's step for MuJoCo's primal problem, exact because the cost is quadratic on S; M a_smooth
// is qfrc_smooth). If the rows that push at that a, {r : jar_r = J_r a - aref_r < 0}, are S
// again, a is the minimizer: f = -D jar > 0 on S and jar >= 0 off it is the complementarity the
// LCP asks for, whose solution is unique. Otherwise S becomes that set and the round repeats,
// from S = the rows that push at a_smooth. False (nothing written) when the set has not settled
// after kMaxActiveSetRounds rounds: the pivoting, which always finishes, decides then.
bool solve_active_set(Data& data) {
  auto& w = data.work;
  const int n = data.nefc;
  auto& active = w.lcp_active;
  const double* D = data.efc_D.data();
  for (int r = 0; r < n; ++r) active[r] = data.efc_b[r] < 0;

  for (int round = 0; round < kMaxActiveSetRounds; ++round) {
    if (!active_set_round(data, active.data())) {  // the rows that push at a, next round
      for (int r = 0; r < n; ++r) active[r] = w.newton_jar[r] < 0;
      continue;
    }
    data.qacc = w.newton_dir;
    for (int r = 0; r < n; ++r) {
      data.efc_force[r] = active[r] ? -D[r] * w.newton_jar[r] : 0.0;
      data.efc_state[r] = active[r] ? ConstraintState::kActive : ConstraintState::kSatisfied;
    }
    add_rows_transpose(data, data.efc_force.data(), data.qfrc_constraint.data());
    return true;
  }
  return false;
}

}  // namespace

void row_space_matrix(const Model& model, Data& data) {
  const int n = data.nefc, nv = model.nv;
  auto& w = data.work;
  // With M = L^T D L, J M^-1 J^T = Y^T Y for Y = D^-1/2 L^-T J^T: one half solve per row, over
  // its dofs and their ancestors, then each dof scaled by 1 / sqrt(D) (MuJoCo's qLDiagSqrtInv)
  auto& inv_sqrt_d = w.vec3;
  for (int k = 0; k < nv; ++k) inv_sqrt_d[k] = 1.0 / std::sqrt(data.qLD(k, k));
  for (int r = 0; r < n; ++r) {
    auto y = w.halfJ.col(r);
    y = data.efc_J.row(r).transpose();
    solve_mass_half(model, data, y);
    y.array() *= inv_sqrt_d.array();
  }
  // the lower triangle, each coefficient summed over the dofs in order
  for (int c = 0; c < n; ++c) {
    const double* yc = w.halfJ.col(c).data();
    for (int r = c; r < n; ++r) {
      const double* yr = w.halfJ.col(r).data();
      double sum = 0.0;
      for (int k = 0; k < nv; ++k) sum += yr[k] * yc[k];
      w.A(r, c) = sum;
    }
    w.A(c, c) += data.efc_R[c];
  }
}

namespace {

// The same problem in row space, exactly, by Murty's least-index principal pivoting on
// A = J M^-1 J^T + R: finite for a positive definite A, whatever the start. Two rows or more:
// the forces in w.lcp_f and the set in w.lcp_active.
void pivot_rows(const Model& model, Data& data) {
  const int n = data.nefc;
  auto& w = data.work;
  const auto b = data.efc_b.head(n);
  row_space_matrix(model, data);
  auto A = w.A.topLeftCorner(n, n);

  // Murty's least-index principal pivoting, starting from the rows that are pushed into the
  // stop. A + R is positive definite (R > 0), so the LCP has one solution and the method reaches
  // it from any start.
  auto f = w.lcp_f.head(n);
  auto residual = w.lcp_w.head(n);
  auto& active = w.lcp_active;
  auto& idx = w.lcp_index;
  for (int r = 0; r < n; ++r) active[r] = b[r] < 0;
  const int max_pivots = 64 * n + 64;
  for (int pivot = 0; pivot <= max_pivots; ++pivot) {
    // forces of the active rows S: (A + R)_SS f_S = -b_S, the others 0
    int m = 0;
    for (int r = 0; r < n; ++r) {
      if (active[r]) idx[m++] = r;
    }
    f.setZero();
    if (m == 1) {  // one active row: Cholesky's sqrt(A) and its two solves
      const double l = std::sqrt(A(idx[0], idx[0]));
      f[idx[0]] = -b[idx[0]] / l / l;
    } else if (m > 1) {
      auto A_SS = w.L.topLeftCorner(m, m);  // gathered, then factored in place
      auto f_S = w.lcp_rhs.head(m);
      for (int k = 0; k < m; ++k) {
        for (int c = 0; c <= k; ++c) A_SS(k, c) = A(idx[k], idx[c]);
        f_S[k] = -b[idx[k]];
      }
      Eigen::LLT<Eigen::Ref<Eigen::MatrixXd>> factor(A_SS);
      factor.solveInPlace(f_S);
      for (int k = 0; k < m; ++k) f[idx[k]] = f_S[k];
    }
    // the first row that breaks complementarity changes side
    residual = b;
    residual.noalias() += A.selfadjointView<Eigen::Lower>() * f;
    int flip = -1;
    for (int r = 0; r < n && flip < 0; ++r) {
      if ((active[r] && f[r] < 0) || (!active[r] && residual[r] < 0)) flip = r;
    }
    if (flip < 0) break;
    active[flip] = !active[flip];
  }
}

// One row (an arm against one stop, the common case): A = J M^-1 J^T + R is a number, and
// Murty's method ends after its first set: the row pushes (f = -b / A > 0, w = 0) exactly when
// b < 0, else f = 0 and w = b >= 0. The same arithmetic as pivot_rows for one row, without its
// matrices.
void solve_one_row(const Model& model, Data& data) {
  auto& w = data.work;
  auto y = w.halfJ.col(0);
  y = data.efc_J.row(0).transpose();
  solve_mass_half(model, data, y);
  auto y_scaled = w.halfJ_scaled.col(0);
  y_scaled = y.cwiseProduct(data.qLDiagInv);
  const double A = y.cwiseProduct(y_scaled).sum() + data.efc_R[0];
  const double b = data.efc_b[0];
  const bool pushes = b < 0;
  w.lcp_active[0] = pushes;
  if (pushes) {
    const double l = std::sqrt(A);  // as Cholesky's factor of the 1 x 1 A
    w.lcp_f[0] = -b / l / l;
  } else {
    w.lcp_f[0] = 0.0;
  }
}

// The one-sided rows' problem in row space (pivot_rows; one row: solve_one_row), then the joint
// forces and accelerations its forces give. For few rows, and the fallback of solve_active_set.
void solve_by_pivoting(const Model& model, Data& data) {
  const int n = data.nefc;
  auto& w = data.work;
  auto& active = w.lcp_active;
  auto f = w.lcp_f.head(n);
  if (n == 1) {
    solve_one_row(model, data);
  } else {
    pivot_rows(model, data);
  }

  // forces, joint forces and accelerations
  for (int r = 0; r < n; ++r) {
    data.efc_force[r] = active[r] ? f[r] : 0.0;
    data.efc_state[r] = active[r] ? ConstraintState::kActive : ConstraintState::kSatisfied;
  }
  add_rows_transpose(data, data.efc_force.data(), data.qfrc_constraint.data());
  // qacc = qacc_smooth + M^-1 J^T f
  w.vec1 = data.qfrc_constraint;
  unchecked::solve_mass(model, data, w.vec1.data());
  data.qacc += w.vec1;
}
}  // namespace

namespace {

// Where every solve starts (and ends, without rows): no constraint force, qacc = qacc_smooth.
void start_unconstrained(const Model& model, Data& data) {
  double* const qfrc = data.qfrc_constraint.data();
  double* const qacc = data.qacc.data();
  const double* const qacc_smooth = data.qacc_smooth.data();
  for (int i = 0; i < model.nv; ++i) {
    qfrc[i] = 0.0;
    qacc[i] = qacc_smooth[i];
  }
}

// Where both one-sided solves start: no constraint force, qacc = qacc_smooth, and each row's
// b = J qacc_smooth - a_ref (its jar without constraint forces).
void start_one_sided(const Model& model, Data& data) {
  start_unconstrained(model, data);
  rows_jar(data, data.qacc_smooth.data(), data.efc_b.data());
}

// The solve itself, by opt.solver and the rows (solve_constraint saves its qacc after).
void solve_rows(const Model& model, Data& data) {
  data.solver_iter = 0;
  // MuJoCo's projected Gauss-Seidel, its sweeps as MuJoCo runs them (at tolerance 0 too: they
  // approach the minimizer without reaching it, so the exact solve would not be PGS's answer)
  if (model.opt.solver == Solver::kPGS) {
    start_unconstrained(model, data);
    if (data.nefc > 0) data.solver_iter = solve_constraint_pgs(model, data);
    return;
  }
  // MuJoCo's conjugate gradients, stopped where MuJoCo stops them, for every kind of row; at
  // tolerance 0 the exact solve below (the minimizer CG converges to; cg.cpp says why)
  if (model.opt.solver == Solver::kCG && model.opt.tolerance > 0) {
    start_unconstrained(model, data);
    if (data.nefc > 0) data.solver_iter = solve_constraint_cg(model, data);
    return;
  }
  // rows that are not one-sided (elliptic cones, equality, friction loss): Newton's method
  if (data.nefc == 0 || model.opt.cone == Cone::kElliptic || data.ne + data.nf > 0) {
    start_unconstrained(model, data);
    if (data.nefc > 0) data.solver_iter = solve_constraint_newton(model, data);
    return;
  }
  start_one_sided(model, data);
  // in the smaller space: rows (pivoting on A, nefc x nefc) when there are no more rows than
  // dofs (a limit or two on an arm), dofs (active sets on H, nv x nv) otherwise (a box resting
  // on four corners has 16 pyramid rows and 6 dofs)
  if (solved_by_active_sets(model, data) && solve_active_set(data)) return;
  solve_by_pivoting(model, data);
}

}  // namespace

void unchecked::solve_constraint(const Model& model, Data& data) {
  solve_rows(model, data);
  data.qacc_warmstart = data.qacc;  // where the next PGS solve starts, as MuJoCo saves it
}

void solve_constraint(const Model& model, Data& data) {
  check_entry(model, data, "lever::solve_constraint");
  unchecked::solve_constraint(model, data);
}

void solve_constraint_pivoting(const Model& model, Data& data) {
  check_entry(model, data, "lever::solve_constraint_pivoting");
  if (data.ne + data.nf > 0) {
    throw StateError(
        "lever::solve_constraint_pivoting: the rows include equality constraints or friction loss, "
        "which are not one-sided; solve_constraint solves them by Newton's method.");
  }
  start_one_sided(model, data);
  if (data.nefc > 0) solve_by_pivoting(model, data);
}

}  // namespace lever
