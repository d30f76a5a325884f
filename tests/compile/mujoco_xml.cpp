// MuJoCo loading and field-by-field comparison for the compile tests; see mujoco_xml.hpp.
#include "mujoco_xml.hpp"

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <regex>
#include <sstream>

#include <lever/harness/tolerance.hpp>

namespace lever::test {

namespace {

// mujoco's compile step prints warnings to stdout and MUJOCO_LOG.TXT; the tests read them back
// from the error buffer instead
void quiet(const char*) {}

// an error outside the compiler (which catches its own) would otherwise wait for Enter
[[noreturn]] void fatal(const char* message) {
  std::fprintf(stderr, "MuJoCo error: %s\n", message);
  std::abort();
}

// an extra first <compiler>: later ones override it, so the file's own settings stand
std::string with_autolimits(const std::string& xml) {
  const size_t root = xml.find("<mujoco");
  const size_t end = root == std::string::npos ? root : xml.find('>', root);
  if (end == std::string::npos || xml[end - 1] == '/') return xml;
  return xml.substr(0, end + 1) + "<compiler autolimits=\"true\"/>" + xml.substr(end + 1);
}

}  // namespace

MjModelHandle mujoco_compile(const std::string& xml, std::string* error) {
  mju_user_warning = quiet;
  mju_user_error = fatal;
  // mujoco's file system refuses an empty file; a blank one is just as empty to the XML parser
  const std::string text = xml.empty() ? std::string(" ") : with_autolimits(xml);
  auto vfs = std::make_unique<mjVFS>();
  mj_defaultVFS(vfs.get());
  const char* name = "model.xml";
  mj_makeEmptyFileVFS(vfs.get(), name, static_cast<int>(text.size()));
  const int file = mj_findFileVFS(vfs.get(), name);
  std::copy(text.begin(), text.end(), static_cast<char*>(vfs->filedata[file]));
  char buffer[1000] = "";
  mjModel* m = mj_loadXML(name, vfs.get(), buffer, sizeof buffer);
  mj_deleteVFS(vfs.get());
  if (error) *error = buffer;
  return MjModelHandle(m, mj_deleteModel);
}

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string without_inertials(const std::string& xml) {
  static const std::regex inertial(R"(<inertial[^>]*/>|<inertial[^>]*>\s*</inertial>)");
  return std::regex_replace(xml, inertial, "");
}

namespace {

// collects the differences, one line each
class Differences {
 public:
  void integer(const std::string& field, int index, int ours, int theirs) {
    if (ours != theirs) {
      add(field + "[" + std::to_string(index) + "]: lever " + std::to_string(ours) + " vs mujoco " +
          std::to_string(theirs));
    }
  }

  void real(const std::string& field, int index, double ours, double theirs) {
    if (!agrees(ours, theirs)) add(describe(field, index, ours, theirs));
  }

  bool count(const std::string& field, int ours, int theirs) {
    integer(field, 0, ours, theirs);
    return ours == theirs;
  }

  // rows of `width` numbers: lever's rows against mujoco's flat row-major array
  template <class Rows>
  void rows(const std::string& field, const Rows& ours, const mjtNum* theirs, int width) {
    for (size_t i = 0; i < ours.size(); ++i) {
      for (int k = 0; k < width; ++k) {
        real(field, static_cast<int>(i) * width + k, ours[i][k], theirs[i * width + k]);
      }
    }
  }

  // a quaternion and its negative are the same rotation
  void quats(const std::string& field, const std::vector<Eigen::Vector4d>& ours,
             const mjtNum* theirs) {
    for (size_t i = 0; i < ours.size(); ++i) {
      bool same = true, opposite = true;
      for (int k = 0; k < 4; ++k) {
        same = same && agrees(ours[i][k], theirs[4 * i + k]);
        opposite = opposite && agrees(-ours[i][k], theirs[4 * i + k]);
      }
      if (same || opposite) continue;
      for (int k = 0; k < 4; ++k) {
        add(describe(field, static_cast<int>(i) * 4 + k, ours[i][k], theirs[4 * i + k]) +
            " (compared up to sign)");
      }
    }
  }

  template <class T>
  void integers(const std::string& field, const std::vector<T>& ours, const int* theirs) {
    for (size_t i = 0; i < ours.size(); ++i) {
      integer(field, static_cast<int>(i), static_cast<int>(ours[i]), theirs[i]);
    }
  }

  void flags(const std::string& field, const std::vector<uint8_t>& ours, const mjtByte* theirs) {
    for (size_t i = 0; i < ours.size(); ++i) {
      integer(field, static_cast<int>(i), ours[i] ? 1 : 0, theirs[i]);
    }
  }

  void reals(const std::string& field, const std::vector<double>& ours, const mjtNum* theirs) {
    for (size_t i = 0; i < ours.size(); ++i) real(field, static_cast<int>(i), ours[i], theirs[i]);
  }

  void names(const std::string& field, const std::vector<std::string>& ours, const mjModel& m,
             int type) {
    for (size_t i = 0; i < ours.size(); ++i) {
      const char* theirs = mj_id2name(&m, type, static_cast<int>(i));
      const std::string t = theirs ? theirs : "";
      if (ours[i] != t) {
        add(field + "[" + std::to_string(i) + "]: lever '" + ours[i] + "' vs mujoco '" + t + "'");
      }
    }
  }

  std::vector<std::string> list;

 private:
  void add(std::string s) { list.push_back(std::move(s)); }
};

void compare_bodies(Differences& d, const Model& o, const mjModel& m) {
  d.integers("body_parentid", o.body_parentid, m.body_parentid);
  d.integers("body_rootid", o.body_rootid, m.body_rootid);
  d.integers("body_jntnum", o.body_jntnum, m.body_jntnum);
  d.integers("body_jntadr", o.body_jntadr, m.body_jntadr);
  d.integers("body_dofnum", o.body_dofnum, m.body_dofnum);
  d.integers("body_dofadr", o.body_dofadr, m.body_dofadr);
  d.integers("body_geomnum", o.body_geomnum, m.body_geomnum);
  d.integers("body_geomadr", o.body_geomadr, m.body_geomadr);
  d.rows("body_pos", o.body_pos, m.body_pos, 3);
  d.quats("body_quat", o.body_quat, m.body_quat);
  d.rows("body_ipos", o.body_ipos, m.body_ipos, 3);
  d.quats("body_iquat", o.body_iquat, m.body_iquat);
  d.reals("body_mass", o.body_mass, m.body_mass);
  d.rows("body_inertia", o.body_inertia, m.body_inertia, 3);
  d.names("body_name", o.body_name, m, mjOBJ_BODY);
}

void compare_joints(Differences& d, const Model& o, const mjModel& m) {
  d.integers("jnt_type", o.jnt_type, m.jnt_type);
  d.integers("jnt_qposadr", o.jnt_qposadr, m.jnt_qposadr);
  d.integers("jnt_dofadr", o.jnt_dofadr, m.jnt_dofadr);
  d.integers("jnt_bodyid", o.jnt_bodyid, m.jnt_bodyid);
  d.rows("jnt_pos", o.jnt_pos, m.jnt_pos, 3);
  d.rows("jnt_axis", o.jnt_axis, m.jnt_axis, 3);
  d.flags("jnt_limited", o.jnt_limited, m.jnt_limited);
  d.rows("jnt_range", o.jnt_range, m.jnt_range, 2);
  d.reals("jnt_margin", o.jnt_margin, m.jnt_margin);
  d.rows("jnt_solref", o.jnt_solref, m.jnt_solref, mjNREF);
  d.rows("jnt_solimp", o.jnt_solimp, m.jnt_solimp, mjNIMP);
  d.reals("jnt_stiffness", o.jnt_stiffness, m.jnt_stiffness);
  d.names("jnt_name", o.jnt_name, m, mjOBJ_JOINT);
  for (int i = 0; i < o.nq; ++i) {
    d.real("qpos0", i, o.qpos0[i], m.qpos0[i]);
    d.real("qpos_spring", i, o.qpos_spring[i], m.qpos_spring[i]);
  }
  d.integers("dof_bodyid", o.dof_bodyid, m.dof_bodyid);
  d.integers("dof_jntid", o.dof_jntid, m.dof_jntid);
  d.integers("dof_parentid", o.dof_parentid, m.dof_parentid);
  d.reals("dof_damping", o.dof_damping, m.dof_damping);
  d.reals("dof_armature", o.dof_armature, m.dof_armature);
}

void compare_geoms_sites(Differences& d, const Model& o, const mjModel& m) {
  d.integers("geom_type", o.geom_type, m.geom_type);
  d.integers("geom_bodyid", o.geom_bodyid, m.geom_bodyid);
  d.integers("geom_group", o.geom_group, m.geom_group);
  d.integers("geom_contype", o.geom_contype, m.geom_contype);
  d.integers("geom_conaffinity", o.geom_conaffinity, m.geom_conaffinity);
  d.rows("geom_size", o.geom_size, m.geom_size, 3);
  d.rows("geom_pos", o.geom_pos, m.geom_pos, 3);
  d.quats("geom_quat", o.geom_quat, m.geom_quat);
  d.names("geom_name", o.geom_name, m, mjOBJ_GEOM);
  d.integers("site_bodyid", o.site_bodyid, m.site_bodyid);
  d.rows("site_pos", o.site_pos, m.site_pos, 3);
  d.quats("site_quat", o.site_quat, m.site_quat);
  d.rows("site_size", o.site_size, m.site_size, 3);
  d.names("site_name", o.site_name, m, mjOBJ_SITE);
}

void compare_actuators(Differences& d, const Model& o, const mjModel& m) {
  for (int a = 0; a < o.nu; ++a) {
    d.integer("actuator_trnid", 2 * a, o.actuator_trnid[static_cast<size_t>(a)],
              m.actuator_trnid[2 * a]);
    d.integer("actuator_trnid", 2 * a + 1, -1, m.actuator_trnid[2 * a + 1]);
    d.integer("actuator_trntype", a, mjTRN_JOINT, m.actuator_trntype[a]);
    d.integer("actuator_gaintype", a, mjGAIN_FIXED, m.actuator_gaintype[a]);
    d.integer("actuator_biastype", a, mjBIAS_NONE, m.actuator_biastype[a]);
  }
  d.rows("actuator_gear", o.actuator_gear, m.actuator_gear, 6);
  d.rows("actuator_ctrlrange", o.actuator_ctrlrange, m.actuator_ctrlrange, 2);
  d.rows("actuator_forcerange", o.actuator_forcerange, m.actuator_forcerange, 2);
  d.flags("actuator_ctrllimited", o.actuator_ctrllimited, m.actuator_ctrllimited);
  d.flags("actuator_forcelimited", o.actuator_forcelimited, m.actuator_forcelimited);
  d.names("actuator_name", o.actuator_name, m, mjOBJ_ACTUATOR);
}

void compare_options(Differences& d, const Model& o, const mjModel& m) {
  d.real("opt_timestep", 0, o.opt.timestep, m.opt.timestep);
  for (int k = 0; k < 3; ++k) d.real("opt_gravity", k, o.opt.gravity[k], m.opt.gravity[k]);
  d.integer("opt_integrator", 0, static_cast<int>(o.opt.integrator), m.opt.integrator);
}

}  // namespace

std::vector<std::string> compare_parameters(const Model& o, const mjModel& m) {
  Differences d;
  bool sizes = d.count("nq", o.nq, m.nq);
  sizes = d.count("nv", o.nv, m.nv) && sizes;
  sizes = d.count("nu", o.nu, m.nu) && sizes;
  sizes = d.count("nbody", o.nbody, m.nbody) && sizes;
  sizes = d.count("njnt", o.njnt, m.njnt) && sizes;
  sizes = d.count("ngeom", o.ngeom, m.ngeom) && sizes;
  sizes = d.count("nsite", o.nsite, m.nsite) && sizes;
  if (sizes) {
    compare_bodies(d, o, m);
    compare_joints(d, o, m);
    compare_geoms_sites(d, o, m);
    compare_actuators(d, o, m);
  }
  compare_options(d, o, m);
  return d.list;
}

std::vector<std::string> compare_constants(const Model& o, const mjModel& m) {
  Differences d;
  if (!d.count("nbody", o.nbody, m.nbody) || !d.count("nv", o.nv, m.nv)) return d.list;
  if (!d.count("size of dof_invweight0", static_cast<int>(o.dof_invweight0.size()), m.nv) ||
      !d.count("size of dof_M0", static_cast<int>(o.dof_M0.size()), m.nv) ||
      !d.count("size of body_subtreemass", static_cast<int>(o.body_subtreemass.size()), m.nbody) ||
      !d.count("size of body_invweight0", static_cast<int>(o.body_invweight0.size()), m.nbody)) {
    return d.list;
  }
  d.reals("dof_invweight0", o.dof_invweight0, m.dof_invweight0);
  d.reals("dof_M0", o.dof_M0, m.dof_M0);
  d.reals("body_subtreemass", o.body_subtreemass, m.body_subtreemass);
  d.rows("body_invweight0", o.body_invweight0, m.body_invweight0, 2);
  return d.list;
}

}  // namespace lever::test
