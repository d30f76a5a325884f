#include <algorithm>
#include <cstddef>
#include <cstdio>
#include <lever/diff/compare.hpp>
#include <lever/diff/rk4.hpp>
#include <lever/dynamics.hpp>
#include <lever/fields.hpp>
#include <lever/forward.hpp>
#include <lever/kinematics.hpp>
#include <map>
#include <string>
#include <vector>

#include <lever/harness/mujoco_arrays.hpp>

namespace lever::diff {

namespace {

// ---- labels: what element i of a flattened array is -----------------------------------------

std::string quoted(const std::vector<std::string>& names, int i) {
  std::string out = names[i].empty() ? std::string("#") : "'" + names[i] + "' #";
  out += std::to_string(i);
  return out;
}

const char* axis_name(int c) { return c == 0 ? "x" : c == 1 ? "y" : c == 2 ? "z" : "w"; }

std::string dof_label(const Model& model, int i) {
  return "dof " + std::to_string(i) + " (joint " + quoted(model.jnt_name, model.dof_jntid[i]) + ")";
}

Labeler per_dof(const Model& model) {
  return [&model](int i) { return dof_label(model, i); };
}

}  // namespace

Labeler per_coordinate(const Model& model) {
  return [&model](int i) {
    int j = model.njnt - 1;
    while (j > 0 && model.jnt_qposadr[j] > i) --j;
    const int within = i - model.jnt_qposadr[j];
    return "qpos " + std::to_string(i) + " (joint " + quoted(model.jnt_name, j) +
           (joint_nq(model.jnt_type[j]) > 1 ? ", coordinate " + std::to_string(within) : "") + ")";
  };
}

namespace {

Labeler per_actuator(const Model& model) {
  return [&model](int i) { return "actuator " + quoted(model.actuator_name, i); };
}

// nv x nv, row-major
Labeler mass_matrix(const Model& model) {
  return [&model](int i) {
    return "row " + dof_label(model, i / model.nv) + ", column " + dof_label(model, i % model.nv);
  };
}

// one 3 x nv Jacobian per site, row-major
Labeler jacobian(const Model& model) {
  return [&model](int i) {
    const int per_site = 3 * model.nv, s = i / per_site, r = (i % per_site) / model.nv;
    return "site " + quoted(model.site_name, s) + ", " + axis_name(r) + " row, column " +
           dof_label(model, i % model.nv);
  };
}

// sensordata's number i: the sensor it belongs to, and which of its numbers
Labeler sensor_number(const Model& model) {
  return [&model](int i) {
    int s = model.nsensor - 1;
    while (s > 0 && model.sensor_adr[s] > i) --s;
    return "sensor " + quoted(model.sensor_name, s) + " (" + sensor_type_name(model.sensor_type[s]) +
           ")" + (model.sensor_dim[s] > 1 ? ", number " + std::to_string(i - model.sensor_adr[s]) : "");
  };
}

Labeler limit_row(const Model& model, const Data& data) {
  return [&model, &data](int r) {
    if (data.efc_type[r] == ConstraintType::kEquality) {
      return "row " + std::to_string(r) + " (equality " + quoted(model.eq_name, data.efc_id[r]) +
             ")";
    }
    if (data.efc_type[r] == ConstraintType::kFrictionDof) {
      return "row " + std::to_string(r) + " (friction loss, " + dof_label(model, data.efc_id[r]) +
             ")";
    }
    if (data.efc_type[r] == ConstraintType::kFrictionTendon) {
      return "row " + std::to_string(r) + " (friction loss, tendon " +
             quoted(model.tendon_name, data.efc_id[r]) + ")";
    }
    if (data.efc_type[r] == ConstraintType::kLimitTendon) {
      return "row " + std::to_string(r) + " (tendon " + quoted(model.tendon_name, data.efc_id[r]) +
             " limit)";
    }
    if (data.efc_type[r] != ConstraintType::kLimitJoint) {
      return "row " + std::to_string(r) + " (contact " + std::to_string(data.efc_id[r]) + ")";
    }
    return "row " + std::to_string(r) + " (joint " + quoted(model.jnt_name, data.efc_id[r]) +
           (data.efc_sign[r] > 0 ? ", lower stop)" : ", upper stop)");
  };
}

// ---- labels chosen from the table: what a row of an array is, then which of its columns ------

std::string column_label(int c, int cols) {
  char text[32] = "";
  switch (cols) {
    case 1: break;
    case 3: std::snprintf(text, sizeof text, "%s", axis_name(c)); break;
    case 6:
      std::snprintf(text, sizeof text, "%s %s", c < 3 ? "angular" : "linear", axis_name(c % 3));
      break;
    case 9: std::snprintf(text, sizeof text, "(%d, %d)", c / 3, c % 3); break;
    default: std::snprintf(text, sizeof text, "component %d", c); break;
  }
  return text;
}

Labeler row_labeler(const Model& model, const Data& data, Size rows) {
  switch (rows) {
    case Size::kNbody: return [&model](int i) { return "body " + quoted(model.body_name, i); };
    case Size::kNjnt: return [&model](int i) { return "joint " + quoted(model.jnt_name, i); };
    case Size::kNsite: return [&model](int i) { return "site " + quoted(model.site_name, i); };
    case Size::kNgeom: return [&model](int i) { return "geom " + quoted(model.geom_name, i); };
    case Size::kNu: return per_actuator(model);
    case Size::kNq: return per_coordinate(model);
    case Size::kNv: return per_dof(model);
    case Size::kNefc: return limit_row(model, data);
    case Size::kNpair: return [](int i) { return "pair " + std::to_string(i); };
    case Size::kNexclude: return [](int i) { return "exclude " + std::to_string(i); };
    case Size::kNmesh: return [](int i) { return "mesh " + std::to_string(i); };
    case Size::kNmeshvert: return [](int i) { return "mesh vertex " + std::to_string(i); };
    case Size::kNmeshgraph: return [](int i) { return "mesh graph " + std::to_string(i); };
    case Size::kNmeshface: return [](int i) { return "mesh face " + std::to_string(i); };
    case Size::kNsensor: return [&model](int i) { return "sensor " + quoted(model.sensor_name, i); };
    case Size::kNsensordata: return sensor_number(model);
    case Size::kNeq: return [&model](int i) { return "equality " + quoted(model.eq_name, i); };
    case Size::kNmocap: return [](int i) { return "mocap " + std::to_string(i); };
    case Size::kNtendon: return [&model](int i) { return "tendon " + quoted(model.tendon_name, i); };
    case Size::kNwrap: return [](int i) { return "wrap " + std::to_string(i); };
    case Size::kNa:  // an activation: its actuator's, the stateful ones coming last
      return [&model](int i) {
        return "actuator " + quoted(model.actuator_name, i + model.nu - model.na);
      };
    case Size::kOne:
    case Size::kNuserBody:  // the user numbers' widths count columns, never rows
    case Size::kNuserJnt:
    case Size::kNuserGeom:
    case Size::kNuserSite:
    case Size::kNuserTendon:
    case Size::kNuserActuator:
    case Size::kNuserSensor: break;
  }
  return [](int) { return std::string(); };
}

Labeler element_labeler(const Model& model, const Data& data, const FieldView& view) {
  const Labeler row = row_labeler(model, data, view.info->rows);
  const int cols = view.cols;
  return [row, cols](int i) {
    const std::string r = row(i / cols), c = column_label(i % cols, cols);
    return r.empty() ? c : c.empty() ? r : r + ", " + c;
  };
}

// lever stores rotations row by row, as MuJoCo does (lever::Mat3)
std::vector<double> row_major(const Eigen::MatrixXd& A) {
  std::vector<double> out;
  for (Eigen::Index r = 0; r < A.rows(); ++r) {
    for (Eigen::Index c = 0; c < A.cols(); ++c) out.push_back(A(r, c));
  }
  return out;
}

// ---- the forward outputs, driven by the field table ----------------------------------------

bool compared_in_forward(const FieldInfo& info) {
  // energy and qfrc_inverse are written by their own functions and compared by compare_energy
  // and compare_inverse
  return info.stage == Stage::kState || info.stage == Stage::kPosition ||
         info.stage == Stage::kVelocity || info.stage == Stage::kAcceleration;
}

// Whether lever's constraint rows are MuJoCo's rows (count, then type and object row by row);
// reported as nefc, efc_type and efc_id.
bool compare_row_identity(const Twin& t, int k, Report& r) {
  const Data& data = t.data;
  const mjData* d = t.d.get();
  r.compare("nefc", k, data.nefc, d->nefc);
  r.compare("ne", k, data.ne, d->ne);
  r.compare("nf", k, data.nf, d->nf);
  if (data.nefc != d->nefc || data.ne != d->ne || data.nf != d->nf) return false;
  bool same_rows = true;
  for (int i = 0; i < data.nefc; ++i) {
    const std::string row = "row " + std::to_string(i);
    r.compare("efc_type", k, static_cast<int>(data.efc_type[i]), d->efc_type[i], row);
    r.compare("efc_id", k, data.efc_id[i], d->efc_id[i], row);
    same_rows = same_rows && static_cast<int>(data.efc_type[i]) == d->efc_type[i] &&
                data.efc_id[i] == d->efc_id[i];
  }
  return same_rows;
}

// The rows' arrays MuJoCo holds in another layout: efc_J (dense here: lever's, row-major; a
// sparse model's, MuJoCo's rows of nonzeros made dense) and efc_KBIP (lever's efc_K, efc_B,
// efc_imp as three arrays).
void compare_row_layouts(const Twin& t, int k, Report& r) {
  const Model& model = t.model;
  const Data& data = t.data;
  const mjData* d = t.d.get();
  const int n = data.nefc, nv = model.nv;
  const Labeler row = limit_row(model, data);
  std::vector<double> jac(static_cast<std::size_t>(n) * nv, 0.0);
  for (int i = 0; i < n; ++i) {
    for (int c = 0; c < nv; ++c) jac[static_cast<std::size_t>(i) * nv + c] = data.efc_J(i, c);
  }
  std::vector<double> mujoco_jac;
  const double* mujoco_rows = d->efc_J;
  if (mj_isSparse(t.m.get())) {
    // MuJoCo's sparse layout (mj_isSparse: jacobian="sparse", or "auto" with nv >= 60) keeps
    // each row's stored entries only (efc_J_rownnz, efc_J_rowadr, efc_J_colind): zero elsewhere
    mujoco_jac.assign(jac.size(), 0.0);
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < d->efc_J_rownnz[i]; ++j) {
        const int at = d->efc_J_rowadr[i] + j;
        mujoco_jac[static_cast<std::size_t>(i) * nv + d->efc_J_colind[at]] = d->efc_J[at];
      }
    }
    mujoco_rows = mujoco_jac.data();
  }
  r.compare("efc_J", k, jac.data(), mujoco_rows, n * nv,
            [&](int i) { return row(i / nv) + ", column " + dof_label(model, i % nv); });
  std::vector<double> stiffness(n), damping(n), impedance(n);
  for (int i = 0; i < n; ++i) {
    stiffness[i] = d->efc_KBIP[4 * i];
    damping[i] = d->efc_KBIP[4 * i + 1];
    impedance[i] = d->efc_KBIP[4 * i + 2];
  }
  r.compare("efc_imp", k, data.efc_imp.data(), impedance.data(), n, row);
  r.compare("efc_K", k, data.efc_K.data(), stiffness.data(), n, row);
  r.compare("efc_B", k, data.efc_B.data(), damping.data(), n, row);
}

// Where each field of lever's contact table lies in MuJoCo's mjContact (the same names).
const std::vector<std::ptrdiff_t>& mujoco_contact_offsets() {
  static const std::vector<std::ptrdiff_t> offsets = {
#define LEVER_MJCONTACT_OFFSET(name, type, count, origin) offsetof(mjContact, name),
      LEVER_CONTACT_FIELDS(LEVER_MJCONTACT_OFFSET)
#undef LEVER_MJCONTACT_OFFSET
  };
  return offsets;
}

// The contacts (mjData.contact): their number, then every field of the contact table: the
// integers (geoms, dim, exclude, efc_address) exactly, and the numbers within the bound when the
// lists name the same geoms.
void compare_contacts(const Twin& t, int k, Report& r) {
  const Data& data = t.data;
  const mjData* d = t.d.get();
  r.compare("ncon", k, data.ncon, d->ncon);
  if (data.ncon != d->ncon) return;
  const std::vector<ContactField>& fields = contact_field_table();
  const std::vector<std::ptrdiff_t>& theirs_at = mujoco_contact_offsets();
  for (int i = 0; i < data.ncon; ++i) {
    const Contact& ours = data.contact[i];
    const mjContact& theirs = d->contact[i];
    const auto* theirs_bytes = reinterpret_cast<const char*>(&theirs);
    const std::string label = "contact " + std::to_string(i);
    const bool same_geoms = ours.geom1 == theirs.geom1 && ours.geom2 == theirs.geom2;
    for (int pass = 0; pass < 2; ++pass) {  // integers first: they say whether the rest compare
      for (std::size_t f = 0; f < fields.size(); ++f) {
        const ContactField& field = fields[f];
        const bool is_int = field.scalar == Scalar::kInt;
        if (is_int != (pass == 0) || (!is_int && !same_geoms)) continue;
        const std::string quantity = std::string("contact ") + field.name;
        const void* mine = field.in(ours);
        const void* mujoco = theirs_bytes + theirs_at[f];
        std::vector<double> a(field.count), b(field.count);
        for (int c = 0; c < field.count; ++c) {
          a[c] = is_int ? static_cast<const int*>(mine)[c] : static_cast<const double*>(mine)[c];
          b[c] = is_int ? static_cast<const int*>(mujoco)[c] : static_cast<const double*>(mujoco)[c];
        }
        if (field.count == 1) {
          r.compare(quantity, k, a[0], b[0], label);
        } else {
          r.compare(quantity, k, a.data(), b.data(), field.count,
                    [&label](int c) { return label + ", " + std::to_string(c); });
        }
      }
    }
  }
}

// Every array of Data's table that MuJoCo has and forward() writes, against MuJoCo's array of
// the same name (found through MuJoCo's own MJDATA_POINTERS), element by element, in the
// table's order. The special cases, and why they stay special:
//   xquat      a unit quaternion and its negative are the same rotation: lever's is compared
//              with MuJoCo's sign;
//   M          MuJoCo keeps qM sparse (its own layout, `own` in the table): compared with the
//              full matrix mj_fullM makes of it;
//   efc_*      the limit rows are compared only when they are the same rows (count, type and
//              joint, reported as nefc and efc_id); efc_J (sparse in a sparse model) and
//              efc_KBIP are laid out otherwise (compare_row_layouts);
//   geom_x*    a mesh geom lever did not read (it gives no mass and cannot collide, or lever
//              cannot read its file: size zero in lever) keeps the frame its element wrote, where
//              MuJoCo moves it to the mesh's centre and principal axes: such rows are left out;
//   wrap_*     compared over the tendons' live points (ten_wrapnum's sum), the rest stale;
//   ten_J      MuJoCo's sparse layout (a sparse model's) made dense;
//   efc_state  lever's ConstraintState values are MuJoCo's mjtConstraintState (0 satisfied,
//              1 quadratic = active, 2 and 3 a friction-loss row's linear sides, 4 cone):
//              compared as integers.
void compare_forward_outputs(const Twin& t, int k, Report& r) {
  const Model& model = t.model;
  const Data& data = t.data;
  const mjModel* m = t.m.get();
  const mjData* d = t.d.get();
  const std::map<std::string, test::MjArray> theirs = test::mujoco_data_arrays(m, d);
  const std::vector<FieldView> ours = data_fields(model, data);
  // declared first, so that a state where the rows differ keeps the table's order
  for (const FieldView& view : ours) {
    if (compared_in_forward(*view.info) &&
        (view.info->in_mujoco || view.info->name == std::string("M"))) {
      r.declare(view.info->name);
    }
  }
  for (const char* q : {"nefc", "ne", "nf", "efc_J", "efc_imp", "efc_K", "efc_B"}) r.declare(q);
  compare_contacts(t, k, r);

  const bool same_rows = compare_row_identity(t, k, r);
  std::vector<double> lever_values, mujoco_values;
  for (const FieldView& view : ours) {
    const FieldInfo& info = *view.info;
    const std::string name = info.name;
    if (!compared_in_forward(info)) continue;
    if (name == "M") {
      const int nv = model.nv;
      std::vector<double> full_m(static_cast<std::size_t>(nv) * nv);
      mj_fullM(m, full_m.data(), d->qM);
      r.compare("M", k, row_major(data.M).data(), full_m.data(), nv * nv, mass_matrix(model));
      continue;
    }
    if (!info.in_mujoco) continue;
    if (name == "efc_id" || name == "efc_type") continue;  // compared by compare_row_identity
    if (info.rows == Size::kNefc && !same_rows) continue;
    const auto found = theirs.find(name);
    if (found == theirs.end() || !test::same_layout(view, found->second)) {
      // the table says MuJoCo has this array: a wrong `mujoco` flag fails the comparison
      r.compare(name + " (not in MuJoCo's mjData with this type and shape)", k, 0.0, 1.0);
      continue;
    }
    const test::MjArray& mj = found->second;
    long n = view.size();
    if (name == "wrap_xpos" || name == "wrap_obj") {
      // MuJoCo writes the live points of the tendons' paths only (ten_wrapnum's sum; its counts
      // are compared as ten_wrapnum): the entries past them keep older values
      long points = 0;
      for (int tendon = 0; tendon < m->ntendon; ++tendon) points += d->ten_wrapnum[tendon];
      n = std::min(n, points * (name == "wrap_xpos" ? 3 : 1));
    }
    lever_values.resize(static_cast<std::size_t>(n));
    mujoco_values.resize(static_cast<std::size_t>(n));
    for (long i = 0; i < n; ++i) {
      lever_values[i] = test::element(view, i);
      mujoco_values[i] = test::element(mj, i);
    }
    if (name == "ten_J" && mj_isSparse(m)) {
      // MuJoCo's sparse layout (mj_isSparse: jacobian="sparse", or "auto" with nv >= 60) keeps
      // each row's nonzeros only (ten_J_rownnz, ten_J_rowadr, ten_J_colind): made dense here
      std::fill(mujoco_values.begin(), mujoco_values.end(), 0.0);
      for (int row = 0; row < m->ntendon; ++row) {
        for (int j = 0; j < d->ten_J_rownnz[row]; ++j) {
          const int at = d->ten_J_rowadr[row] + j;
          mujoco_values[static_cast<std::size_t>(row) * m->nv + d->ten_J_colind[at]] =
              d->ten_J[at];
        }
      }
    }
    if (name == "xquat") {
      for (long b = 0; b < view.rows; ++b) {
        double dot = 0.0;
        for (int c = 0; c < 4; ++c) dot += lever_values[4 * b + c] * mujoco_values[4 * b + c];
        if (dot < 0) {
          for (int c = 0; c < 4; ++c) lever_values[4 * b + c] = -lever_values[4 * b + c];
        }
      }
    }
    if (name == "geom_xpos" || name == "geom_xmat") {
      for (int g = 0; g < model.ngeom; ++g) {
        if (model.geom_type[g] != GeomType::kMesh || !model.geom_size[g].isZero()) continue;
        for (int c = 0; c < view.cols; ++c) {
          mujoco_values[g * view.cols + c] = lever_values[g * view.cols + c];
        }
      }
    }
    r.compare(name, k, lever_values.data(), mujoco_values.data(), static_cast<int>(n),
              element_labeler(model, data, view));
  }
  if (same_rows && data.nefc > 0) compare_row_layouts(t, k, r);
}

void compare_energy(const Twin& t, int k, Report& r) {
  r.compare("energy (potential)", k, t.data.energy[0], t.d->energy[0]);
  r.compare("energy (kinetic)", k, t.data.energy[1], t.d->energy[1]);
}

void compare_site_jacobians(const Twin& t, int k, Report& r) {
  const Model& model = t.model;
  const int nv = model.nv, ns = model.nsite;
  std::vector<double> ours_p(3 * nv * ns), ours_r(3 * nv * ns);
  std::vector<double> mj_p(3 * nv * ns), mj_r(3 * nv * ns);
  Eigen::MatrixXd jacp(3, nv), jacr(3, nv);
  for (int s = 0; s < ns; ++s) {
    jac_site(model, t.data, s, jacp, jacr);
    const std::vector<double> p = row_major(jacp), q = row_major(jacr);
    std::copy(p.begin(), p.end(), ours_p.begin() + 3 * nv * s);
    std::copy(q.begin(), q.end(), ours_r.begin() + 3 * nv * s);
    mj_jacSite(t.m.get(), t.d.get(), mj_p.data() + 3 * nv * s, mj_r.data() + 3 * nv * s, s);
  }
  r.compare("jacp", k, ours_p.data(), mj_p.data(), 3 * nv * ns, jacobian(model));
  r.compare("jacr", k, ours_r.data(), mj_r.data(), 3 * nv * ns, jacobian(model));
}

}  // namespace

void compare_model_constants(const Twin& t, Report& r) {
  const Model& model = t.model;
  const mjModel* m = t.m.get();
  std::vector<double> body_invweight0;
  for (const auto& w : model.body_invweight0)
    body_invweight0.insert(body_invweight0.end(), w.begin(), w.end());
  // model constants: the "state" number 0 stands for qpos0
  r.compare("dof_invweight0", 0, model.dof_invweight0.data(), m->dof_invweight0, model.nv,
            per_dof(model));
  r.compare("dof_M0", 0, model.dof_M0.data(), m->dof_M0, model.nv, per_dof(model));
  r.compare("body_invweight0", 0, body_invweight0.data(), m->body_invweight0, 2 * model.nbody,
            [&model](int i) {
              return "body " + quoted(model.body_name, i / 2) +
                     (i % 2 ? ", rotational" : ", translational");
            });
  r.compare("body_subtreemass", 0, model.body_subtreemass.data(), m->body_subtreemass, model.nbody,
            [&model](int i) { return "body " + quoted(model.body_name, i); });
  // the anchors and relative poses set_const completes at qpos0 (mj_setConst's)
  if (model.neq == m->neq && model.neq > 0) {
    std::vector<double> eq_data;
    for (const auto& row : model.eq_data) eq_data.insert(eq_data.end(), row.begin(), row.end());
    r.compare("eq_data", 0, eq_data.data(), m->eq_data, model.neq * kEqualityData, [&model](int i) {
      return "equality " + quoted(model.eq_name, i / kEqualityData) + ", " +
             std::to_string(i % kEqualityData);
    });
  }
}

void compare_forward(Twin& t, const test::State& s, int k, Report& r) {
  t.set_state(s);
  forward(t.model, t.data);
  compute_energy(t.model, t.data);
  t.mujoco_forward();
  compare_forward_outputs(t, k, r);
  compare_energy(t, k, r);
  compare_site_jacobians(t, k, r);
}

void compare_inverse(Twin& t, const test::State& s, const Eigen::VectorXd& qacc,
                     const std::string& label, int k, Report& r) {
  t.set_state(s);
  t.data.qacc = qacc;
  for (int i = 0; i < t.model.nv; ++i) t.d->qacc[i] = qacc[i];
  inverse(t.model, t.data);
  mj_inverse(t.m.get(), t.d.get());
  r.compare("qfrc_inverse (" + label + ")", k, t.data.qfrc_inverse.data(), t.d->qfrc_inverse,
            t.model.nv, per_dof(t.model));
}

void compare_step(Twin& t, const test::State& s, Integrator integrator, int k, Report& r) {
  const Integrator own = t.model.opt.integrator;
  t.set_integrator(integrator);
  t.set_state(s);
  step(t.model, t.data);
  if (integrator == Integrator::kRK4) {
    // MuJoCo's stages at the states lever's step went through (lever/diff/rk4.hpp says why)
    MujocoRk4Stages stages;
    mujoco_rk4_step(t.m.get(), t.d.get(), t.restart_mujoco_solver, &t.data.work.rk_qacc, &stages);
    compare_rk4_stages(t.model, t.data, stages, k, r);
  } else {
    mujoco_step_converged(t.m.get(), t.d.get(), t.restart_mujoco_solver);
  }
  const std::string name = integrator_name(integrator);
  r.compare("qpos after one " + name + " step", k, t.data.qpos.data(), t.d->qpos, t.model.nq,
            per_coordinate(t.model));
  r.compare("qvel after one " + name + " step", k, t.data.qvel.data(), t.d->qvel, t.model.nv,
            per_dof(t.model));
  r.compare("time after one " + name + " step", k, t.data.time, t.d->time);
  t.set_integrator(own);
}

void compare_state(Twin& t, const test::State& s, const Eigen::VectorXd& random_qacc, int k,
                   Report& r) {
  compare_forward(t, s, k, r);
  const Eigen::VectorXd forward_qacc = Eigen::Map<const Eigen::VectorXd>(t.d->qacc, t.model.nv);
  compare_inverse(t, s, forward_qacc, "at the forward qacc", k, r);
  compare_inverse(t, s, random_qacc, "at a random qacc", k, r);
  compare_step(t, s, Integrator::kEuler, k, r);
  compare_step(t, s, Integrator::kRK4, k, r);
  compare_step(t, s, Integrator::kImplicit, k, r);
}

}  // namespace lever::diff
