// lever model: what a compiled model contains.
//
//   lever model MODEL [--json] [--infer-inertia]
//   lever model --schema
//
// Text: joints, motors, sites, bodies (mass, principal moments, explicit or inferred inertia)
// and options, like section (1) of lesson 5.1. --json: one object keyed by mjModel's field names,
// arrays flattened row-major, full precision. --infer-inertia: ignore every <inertial> and infer
// masses from the geoms. --schema: the supported MJCF subset as Markdown (docs/mjcf-subset.md).
// Exit 0; a model that cannot be loaded prints the error and exits 2.
#include <cstdio>
#include <lever/mjcf.hpp>
#include <string>
#include <vector>

#include "cli.hpp"
#include "commands.hpp"

namespace lever::cli {

namespace {

const char* const kUsage =
    "usage: lever model MODEL [--json] [--infer-inertia]\n"
    "       lever model --schema\n"
    "  --json            one JSON object keyed by mjModel's field names\n"
    "  --infer-inertia   ignore every <inertial>: masses and inertias from the geoms\n"
    "  --schema          print the supported MJCF subset as Markdown\n";

// ---- text ----------------------------------------------------------------------------------

std::string vec(const Eigen::Ref<const Eigen::VectorXd>& v) {
  std::string s = "(";
  for (Eigen::Index i = 0; i < v.size(); ++i) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%s%.6g", i ? ", " : "", v[i]);
    s += buf;
  }
  return s + ")";
}

std::string pair(const std::array<double, 2>& r) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "[%.6g, %.6g]", r[0], r[1]);
  return buf;
}

std::string label(const std::string& name, int id) {
  return name.empty() ? std::string("#").append(std::to_string(id)) : name;
}

void print_options(std::FILE* out, const Model& m) {
  std::fprintf(out, "options: timestep %g s, integrator %s, gravity %s m/s^2\n", m.opt.timestep,
               m.opt.integrator == Integrator::kRK4 ? "RK4" : "Euler", vec(m.opt.gravity).c_str());
  std::fprintf(out, "  inertiagrouprange %d %d, inertia from geoms %s\n",
               m.compiler.inertiagrouprange[0], m.compiler.inertiagrouprange[1],
               m.compiler.inertia_from_geoms_allowed ? "allowed" : "off (inertiafromgeom=false)");
}

void print_joints(std::FILE* out, const Model& m) {
  std::fprintf(out, "joints (%d):\n", m.njnt);
  for (int j = 0; j < m.njnt; ++j) {
    const bool hinge = m.jnt_type[j] == JointType::kHinge;
    const int dof = m.jnt_dofadr[j];
    std::fprintf(out,
                 "  %-12s %-6s body %-10s axis %s  range %s %s  limited %s  damping %g %s  "
                 "armature %g  stiffness %g\n",
                 label(m.jnt_name[j], j).c_str(), hinge ? "hinge" : "slide",
                 label(m.body_name[m.jnt_bodyid[j]], m.jnt_bodyid[j]).c_str(),
                 vec(m.jnt_axis[j]).c_str(), pair(m.jnt_range[j]).c_str(), hinge ? "rad" : "m",
                 m.jnt_limited[j] ? "yes" : "no", m.dof_damping[dof], hinge ? "N m s/rad" : "N s/m",
                 m.dof_armature[dof], m.jnt_stiffness[j]);
  }
}

void print_motors(std::FILE* out, const Model& m) {
  std::fprintf(out, "motors (%d):\n", m.nu);
  for (int a = 0; a < m.nu; ++a) {
    const int j = m.actuator_trnid[a];
    const bool hinge = m.jnt_type[j] == JointType::kHinge;
    std::fprintf(out,
                 "  %-12s joint %-10s gear %g  ctrlrange %s  ctrllimited %s  forcerange %s %s  "
                 "forcelimited %s\n",
                 label(m.actuator_name[a], a).c_str(), label(m.jnt_name[j], j).c_str(),
                 m.actuator_gear[a][0], pair(m.actuator_ctrlrange[a]).c_str(),
                 m.actuator_ctrllimited[a] ? "yes" : "no", pair(m.actuator_forcerange[a]).c_str(),
                 hinge ? "N m" : "N", m.actuator_forcelimited[a] ? "yes" : "no");
  }
}

void print_sites(std::FILE* out, const Model& m) {
  std::fprintf(out, "sites (%d):\n", m.nsite);
  for (int s = 0; s < m.nsite; ++s) {
    std::fprintf(out, "  %-12s body %-10s pos %s\n", label(m.site_name[s], s).c_str(),
                 label(m.body_name[m.site_bodyid[s]], m.site_bodyid[s]).c_str(),
                 vec(m.site_pos[s]).c_str());
  }
}

void print_bodies(std::FILE* out, const Model& m) {
  std::fprintf(out, "bodies (%d, world excluded):\n", m.nbody - 1);
  for (int b = 1; b < m.nbody; ++b) {
    const char* source = m.body_explicit_inertial[b] ? "explicit <inertial>"
                         : m.body_mass[b] > 0        ? "inferred from geoms"
                                                     : "no mass";
    std::fprintf(out,
                 "  %-12s parent %-10s mass %g kg  principal moments %s kg m^2  centre of mass %s"
                 "  %s\n",
                 label(m.body_name[b], b).c_str(),
                 label(m.body_name[m.body_parentid[b]], m.body_parentid[b]).c_str(), m.body_mass[b],
                 vec(m.body_inertia[b]).c_str(), vec(m.body_ipos[b]).c_str(), source);
  }
}

// ---- json ------------------------------------------------------------------------------------

template <class V>
void rows(Json& json, const std::string& key, const std::vector<V>& v) {
  json.key(key).begin_array();
  for (const V& row : v) {
    for (Eigen::Index i = 0; i < row.size(); ++i) json.value(static_cast<double>(row[i]));
  }
  json.end_array();
}

template <size_t N>
void rows(Json& json, const std::string& key, const std::vector<std::array<double, N>>& v) {
  json.key(key).begin_array();
  for (const auto& row : v) {
    for (const double x : row) json.value(x);
  }
  json.end_array();
}

void numbers(Json& json, const std::string& key, const std::vector<double>& v) {
  json.key(key).begin_array();
  for (const double x : v) json.value(x);
  json.end_array();
}

template <class T>
void integers(Json& json, const std::string& key, const std::vector<T>& v) {
  json.key(key).begin_array();
  for (const T& x : v) json.value(static_cast<int>(x));
  json.end_array();
}

void flags(Json& json, const std::string& key, const std::vector<bool>& v) {
  json.key(key).begin_array();
  for (const bool x : v) json.value(x ? 1 : 0);
  json.end_array();
}

void names(Json& json, const std::string& key, const std::vector<std::string>& v) {
  json.key(key).begin_array();
  for (const std::string& s : v) json.value(s);
  json.end_array();
}

// joints, motors, sites, bodies (mass, principal moments, explicit or inferred) and options
void print_model_text(std::FILE* out, const Model& m) {
  std::fprintf(out, "model %s%s%s\n", m.name.c_str(), m.source.empty() ? "" : " from ",
               m.source.c_str());
  std::fprintf(out, "nq %d  nv %d  nu %d  nbody %d  njnt %d  ngeom %d  nsite %d\n", m.nq, m.nv,
               m.nu, m.nbody, m.njnt, m.ngeom, m.nsite);
  print_joints(out, m);
  print_motors(out, m);
  print_sites(out, m);
  print_bodies(out, m);
  print_options(out, m);
}

// one object: mjModel's field names, arrays flattened row-major, full double precision
void print_model_json(Json& json, const Model& m) {
  json.begin_object();
  json.key("model").value(m.name);
  json.key("source").value(m.source);
  for (const auto& [key, n] : {std::pair{"nq", m.nq},
                               {"nv", m.nv},
                               {"nu", m.nu},
                               {"nbody", m.nbody},
                               {"njnt", m.njnt},
                               {"nsite", m.nsite},
                               {"ngeom", m.ngeom}}) {
    json.key(key).value(n);
  }
  names(json, "body_name", m.body_name);
  integers(json, "body_parentid", m.body_parentid);
  integers(json, "body_rootid", m.body_rootid);
  integers(json, "body_jntnum", m.body_jntnum);
  integers(json, "body_jntadr", m.body_jntadr);
  integers(json, "body_dofnum", m.body_dofnum);
  integers(json, "body_dofadr", m.body_dofadr);
  integers(json, "body_geomnum", m.body_geomnum);
  integers(json, "body_geomadr", m.body_geomadr);
  rows(json, "body_pos", m.body_pos);
  rows(json, "body_quat", m.body_quat);
  rows(json, "body_ipos", m.body_ipos);
  rows(json, "body_iquat", m.body_iquat);
  numbers(json, "body_mass", m.body_mass);
  rows(json, "body_inertia", m.body_inertia);
  numbers(json, "body_subtreemass", m.body_subtreemass);
  flags(json, "body_explicit_inertial", m.body_explicit_inertial);
  names(json, "jnt_name", m.jnt_name);
  integers(json, "jnt_type", m.jnt_type);
  integers(json, "jnt_qposadr", m.jnt_qposadr);
  integers(json, "jnt_dofadr", m.jnt_dofadr);
  integers(json, "jnt_bodyid", m.jnt_bodyid);
  rows(json, "jnt_pos", m.jnt_pos);
  rows(json, "jnt_axis", m.jnt_axis);
  flags(json, "jnt_limited", m.jnt_limited);
  rows(json, "jnt_range", m.jnt_range);
  numbers(json, "jnt_margin", m.jnt_margin);
  rows(json, "jnt_solref", m.jnt_solref);
  rows(json, "jnt_solimp", m.jnt_solimp);
  numbers(json, "jnt_stiffness", m.jnt_stiffness);
  json.key("qpos0").values(m.qpos0);
  json.key("qpos_spring").values(m.qpos_spring);
  integers(json, "dof_bodyid", m.dof_bodyid);
  integers(json, "dof_jntid", m.dof_jntid);
  integers(json, "dof_parentid", m.dof_parentid);
  numbers(json, "dof_damping", m.dof_damping);
  numbers(json, "dof_armature", m.dof_armature);
  numbers(json, "dof_invweight0", m.dof_invweight0);
  numbers(json, "dof_M0", m.dof_M0);
  names(json, "geom_name", m.geom_name);
  integers(json, "geom_type", m.geom_type);
  integers(json, "geom_bodyid", m.geom_bodyid);
  integers(json, "geom_contype", m.geom_contype);
  integers(json, "geom_conaffinity", m.geom_conaffinity);
  integers(json, "geom_group", m.geom_group);
  rows(json, "geom_size", m.geom_size);
  rows(json, "geom_pos", m.geom_pos);
  rows(json, "geom_quat", m.geom_quat);
  rows(json, "geom_rgba", m.geom_rgba);
  numbers(json, "geom_mass", m.geom_mass);
  names(json, "site_name", m.site_name);
  integers(json, "site_bodyid", m.site_bodyid);
  rows(json, "site_pos", m.site_pos);
  rows(json, "site_quat", m.site_quat);
  rows(json, "site_size", m.site_size);
  names(json, "actuator_name", m.actuator_name);
  // mjModel's actuator_trnid is (nu x 2): the joint, then -1 for a joint transmission
  json.key("actuator_trnid").begin_array();
  for (const int j : m.actuator_trnid) json.value(j).value(-1);
  json.end_array();
  rows(json, "actuator_gear", m.actuator_gear);
  rows(json, "actuator_ctrlrange", m.actuator_ctrlrange);
  rows(json, "actuator_forcerange", m.actuator_forcerange);
  flags(json, "actuator_ctrllimited", m.actuator_ctrllimited);
  flags(json, "actuator_forcelimited", m.actuator_forcelimited);
  json.key("opt_timestep").value(m.opt.timestep);
  json.key("opt_gravity").values(m.opt.gravity);
  json.key("opt_integrator").value(static_cast<int>(m.opt.integrator));
  json.end_object();
  json.newline();
}

}  // namespace

int cmd_model(const std::vector<std::string>& argv) {
  const Args args(argv, {}, {"json", "infer-inertia", "schema", "help"});
  if (args.has("help")) {
    std::fputs(kUsage, stdout);
    return kOk;
  }
  if (args.has("schema")) {
    std::fputs(mjcf::schema_markdown().c_str(), stdout);
    return kOk;
  }
  if (args.positional().size() != 1) throw UsageError{std::string("expects one MODEL\n") + kUsage};
  mjcf::LoadOptions options;
  options.infer_inertia_from_geoms = args.has("infer-inertia");
  const Model model = mjcf::load_file(args.positional()[0], options);
  if (args.has("json")) {
    Json json(stdout);
    print_model_json(json, model);
  } else {
    print_model_text(stdout, model);
  }
  return kOk;
}

}  // namespace lever::cli
