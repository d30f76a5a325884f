// lever model: what a compiled model contains.
//
//   lever model MODEL [--json] [--infer-inertia]
//   lever model --schema
// (declare_model has the options and their help)
//
// Text: joints, motors, sites, bodies (mass, principal moments, explicit or inferred inertia),
// sensors and options, like section (1) of lesson 5.1. --json: one object keyed by mjModel's field names,
// arrays flattened row-major, full precision. --infer-inertia: ignore every <inertial> and infer
// masses from the geoms. --schema: the supported MJCF subset as Markdown (docs/mjcf-subset.md).
// Exit 0; a model that cannot be loaded prints the error and exits 2.
#include <cstdio>
#include <lever/io/serialize.hpp>
#include <lever/mjcf.hpp>
#include <string>
#include <vector>

#include "cli.hpp"
#include "commands.hpp"
#include "forward_state.hpp"

namespace lever::cli {

namespace {

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
               integrator_name(m.opt.integrator), vec(m.opt.gravity).c_str());
  std::fprintf(out, "  inertiagrouprange %d %d, inertia from geoms %s\n",
               m.compiler.inertiagrouprange[0], m.compiler.inertiagrouprange[1],
               m.compiler.inertia_from_geoms_allowed ? "allowed" : "off (inertiafromgeom=false)");
  // the flags that differ from MuJoCo's defaults, by their MJCF names
  std::string flags;
  for (int k = 0; k < kDisableBits; ++k) {
    if (m.opt.disableflags & (1 << k)) flags += std::string(" ") + kDisableNames[k] + "=disable";
  }
  for (int k = 0; k < kEnableBits; ++k) {
    if (m.opt.enableflags & (1 << k)) flags += std::string(" ") + kEnableNames[k] + "=enable";
  }
  if (!flags.empty()) std::fprintf(out, "  flags:%s\n", flags.c_str());
}

// A joint's kind and the units of its range, damping and force: a free joint moves along and
// about axes (its three translations first), a ball joint's range is its largest angle.
struct JointWords {
  const char* kind;
  const char* range;
  const char* damping;
  const char* force;
};

JointWords joint_words(JointType type) {
  switch (type) {
    case JointType::kFree: return {"free", "-", "N s/m, N m s/rad", "N, N m"};
    case JointType::kBall: return {"ball", "rad", "N m s/rad", "N m"};
    case JointType::kSlide: return {"slide", "m", "N s/m", "N"};
    default: return {"hinge", "rad", "N m s/rad", "N m"};
  }
}

void print_joints(std::FILE* out, const Model& m) {
  std::fprintf(out, "joints (%d):\n", m.njnt);
  for (int j = 0; j < m.njnt; ++j) {
    const JointWords words = joint_words(m.jnt_type[j]);
    const bool one_axis = m.jnt_type[j] == JointType::kHinge || m.jnt_type[j] == JointType::kSlide;
    const int dof = m.jnt_dofadr[j];
    // a free joint has no axis and no range; a ball joint no axis, and its range is [0, angle]
    const std::string axis = one_axis ? "axis " + vec(m.jnt_axis[j]) + "  " : "";
    const std::string range = m.jnt_type[j] == JointType::kFree
                                  ? ""
                                  : "range " + pair(m.jnt_range[j]) + " " + words.range + "  ";
    std::fprintf(out,
                 "  %-12s %-6s body %-10s %s%slimited %s  damping %g %s  armature %g  "
                 "stiffness %g\n",
                 label(m.jnt_name[j], j).c_str(), words.kind,
                 label(m.body_name[m.jnt_bodyid[j]], m.jnt_bodyid[j]).c_str(), axis.c_str(),
                 range.c_str(), m.jnt_limited[j] ? "yes" : "no", m.dof_damping[dof],
                 words.damping, m.dof_armature[dof], m.jnt_stiffness[j]);
  }
}

void print_motors(std::FILE* out, const Model& m) {
  std::fprintf(out, "motors (%d):\n", m.nu);
  for (int a = 0; a < m.nu; ++a) {
    const TransmissionText target = transmission_text(m, a);
    std::fprintf(out,
                 "  %-12s %s %-10s gear %g  ctrlrange %s  ctrllimited %s  forcerange %s %s  "
                 "forcelimited %s\n",
                 label(m.actuator_name[a], a).c_str(), target.kind, target.object.c_str(),
                 m.actuator_gear[a][0], pair(m.actuator_ctrlrange[a]).c_str(),
                 m.actuator_ctrllimited[a] ? "yes" : "no", pair(m.actuator_forcerange[a]).c_str(),
                 actuator_force_units(m, a),
                 m.actuator_forcelimited[a] ? "yes" : "no");
    const bool motor = m.actuator_gaintype[a] == GainType::kFixed &&
                       m.actuator_gainprm[a][0] == 1.0 && m.actuator_biastype[a] == BiasType::kNone;
    if (motor && m.actuator_dyntype[a] == DynType::kNone) continue;
    const auto& g = m.actuator_gainprm[a];
    if (m.actuator_gaintype[a] == GainType::kMuscle) {
      const auto& r = m.actuator_lengthrange[a];
      std::fprintf(out,
                   "    muscle: range [%g, %g]  force %g  scale %g  lmin %g  lmax %g  vmax %g  "
                   "fpmax %g  fvmax %g  lengthrange [%g, %g]  timeconst %g %g\n",
                   g[0], g[1], g[2], g[3], g[4], g[5], g[6], g[7], g[8], r[0], r[1],
                   m.actuator_dynprm[a][0], m.actuator_dynprm[a][1]);
      continue;
    }
    // force = gain input + bias, with gain and bias affine in the actuator's length and velocity;
    // the input is ctrl, or the activation act of an actuator with dynamics
    const char* input = m.actuator_dyntype[a] == DynType::kNone ? "ctrl" : "act";
    const auto& b = m.actuator_biasprm[a];
    std::fprintf(out, "    force = (%g", g[0]);
    if (m.actuator_gaintype[a] == GainType::kAffine) {
      std::fprintf(out, " %+g length %+g velocity", g[1], g[2]);
    }
    std::fprintf(out, ") %s", input);
    if (m.actuator_biastype[a] == BiasType::kAffine) {
      std::fprintf(out, " %+g %+g length %+g velocity", b[0], b[1], b[2]);
    }
    if (m.actuator_kind[a] == ActuatorKind::kPositionServo && g[0] > 0 &&
        m.actuator_gaintype[a] == GainType::kFixed) {
      std::fprintf(out, "  (position servo: kp %g, kv %g)", g[0], -b[2]);
    }
    std::fprintf(out, "\n");
  }
}

void print_keyframes(std::FILE* out, const Model& m) {
  if (m.nkey == 0) return;
  std::fprintf(out, "keyframes (%d):\n", m.nkey);
  for (int k = 0; k < m.nkey; ++k) {
    std::fprintf(out, "  %-12s time %g  qpos", label(m.key_name[k], k).c_str(), m.key_time[k]);
    for (int i = 0; i < m.nq; ++i) std::fprintf(out, " %g", m.key_qpos(k, i));
    std::fprintf(out, "\n");
  }
}

void print_warnings(std::FILE* out, const Model& m) {
  for (const std::string& w : m.warnings) std::fprintf(out, "warning: %s\n", w.c_str());
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

// Each sensor: its type, the object it reads (and its reference frame), where its numbers are in
// sensordata, and its cutoff and noise where set.
void print_sensors(std::FILE* out, const Model& m) {
  if (m.nsensor == 0) return;
  std::fprintf(out, "sensors (%d, %d numbers in sensordata):\n", m.nsensor, m.nsensordata);
  const auto object = [&m](ObjectType type, int id) -> std::string {
    switch (type) {
      case ObjectType::kBody: return "body " + label(m.body_name[id], id);
      case ObjectType::kXBody: return "xbody " + label(m.body_name[id], id);
      case ObjectType::kGeom: return "geom " + label(m.geom_name[id], id);
      case ObjectType::kSite: return "site " + label(m.site_name[id], id);
      case ObjectType::kJoint: return "joint " + label(m.jnt_name[id], id);
      case ObjectType::kActuator: return "actuator " + label(m.actuator_name[id], id);
      default: return "-";
    }
  };
  for (int s = 0; s < m.nsensor; ++s) {
    std::string line = object(m.sensor_objtype[s], m.sensor_objid[s]);
    if (m.sensor_refid[s] >= 0) line += " in " + object(m.sensor_reftype[s], m.sensor_refid[s]);
    const int adr = m.sensor_adr[s], dim = m.sensor_dim[s];
    std::fprintf(out, "  %-16s %-14s %-28s sensordata[%d%s]", label(m.sensor_name[s], s).c_str(),
                 sensor_type_name(m.sensor_type[s]), line.c_str(), adr,
                 dim > 1 ? (".." + std::to_string(adr + dim - 1)).c_str() : "");
    if (m.sensor_cutoff[s] > 0) std::fprintf(out, "  cutoff %g", m.sensor_cutoff[s]);
    if (m.sensor_noise[s] > 0) std::fprintf(out, "  noise %g", m.sensor_noise[s]);
    std::fprintf(out, "\n");
  }
}

// ---- json ------------------------------------------------------------------------------------

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
  print_sensors(out, m);
  print_keyframes(out, m);
  print_options(out, m);
  print_warnings(out, m);
}

// one object: the sizes, names and every array of the field table (lever/fields.hpp) under
// mjModel's names, flattened row-major, full double precision
void print_model_json(Json& json, const Model& m) {
  json.begin_object();
  write_model_fields(json, m);
  json.end_object();
  json.newline();
}

}  // namespace

void declare_model(CLI::App& command) {
  command.add_option("MODEL", "the model file (MJCF); not with --schema")->type_name("FILE");
  add_switch(command, "json", "one JSON object keyed by mjModel's field names");
  add_switch(command, "infer-inertia",
             "ignore every <inertial>: masses and inertias from the geoms");
  add_switch(command, "schema", "print the supported MJCF subset as Markdown")->excludes("MODEL");
  command.footer("Exit status: 0, or 2 when the model cannot be loaded.");
}

int cmd_model(const Args& args) {
  if (args.has("schema")) {
    std::fputs(mjcf::schema_markdown().c_str(), stdout);
    return kOk;
  }
  if (args.positional().size() != 1) throw UsageError{"expects one MODEL (or --schema)"};
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
