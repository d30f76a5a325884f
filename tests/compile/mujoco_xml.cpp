// MuJoCo loading and field-by-field comparison for the compile tests; see mujoco_xml.hpp.
#include "mujoco_xml.hpp"

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>

#include <lever/fields.hpp>
#include <lever/mjcf.hpp>
#include <lever/harness/mujoco_arrays.hpp>
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

MjModelHandle mujoco_compile(const std::string& xml, std::string* error,
                             const std::map<std::string, std::string>& files) {
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
  for (const auto& [file_name, bytes] : files) {  // MuJoCo's VFS looks files up without folders
    mj_makeEmptyFileVFS(vfs.get(), file_name.c_str(), static_cast<int>(bytes.size()));
    const int f = mj_findFileVFS(vfs.get(), file_name.c_str());
    std::copy(bytes.begin(), bytes.end(), static_cast<char*>(vfs->filedata[f]));
  }
  char buffer[1000] = "";
  mjModel* m = mj_loadXML(name, vfs.get(), buffer, sizeof buffer);
  mj_deleteVFS(vfs.get());
  if (error) *error = buffer;
  return MjModelHandle(m, mj_deleteModel);
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

  // a number that must be MuJoCo's to the bit
  void exact(const std::string& field, int index, double ours, double theirs) {
    if (ours != theirs) add(describe(field, index, ours, theirs) + " (compared bit for bit)");
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

  // (n, 4) quaternions: a quaternion and its negative are the same rotation
  void quats(const std::string& field, const FieldView& ours, const MjArray& theirs) {
    for (int i = 0; i < ours.rows; ++i) {
      bool same = true, opposite = true;
      for (int k = 0; k < 4; ++k) {
        const double x = element(ours, 4 * i + k), y = element(theirs, 4 * i + k);
        same = same && agrees(x, y);
        opposite = opposite && agrees(-x, y);
      }
      if (same || opposite) continue;
      for (int k = 0; k < 4; ++k) {
        add(describe(field, 4 * i + k, element(ours, 4 * i + k), element(theirs, 4 * i + k)) +
            " (compared up to sign)");
      }
    }
  }

  // the field table says MuJoCo has this array, with this element type and shape
  void missing(const std::string& field) {
    add(field +
        ": marked `mujoco` in lever/fields.hpp, but MuJoCo's mjModel has no array of "
        "that name, element type and width");
  }

  void reals(const std::string& field, const ArenaArray<double>& ours, const mjtNum* theirs) {
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

// What set_const derives (MuJoCo's mj_setConst): compared by compare_constants, not as
// compiled parameters.
bool is_constant(const std::string& name) {
  return name == "body_subtreemass" || name == "body_invweight0" || name == "dof_invweight0" ||
         name == "dof_M0" || name == "tendon_length0" || name == "tendon_invweight0" ||
         name == "actuator_length0" || name == "actuator_acc0";
}

// Every array of Model's table that MuJoCo has, against MuJoCo's array of the same name (found
// through MuJoCo's own MJMODEL_POINTERS), element by element. Special cases, and why:
//   *_quat          a unit quaternion and its negative are the same rotation (up to sign);
//   geom frames     mesh geoms' size, pos and quat are MuJoCo's fit to the mesh file, which
//                   lever computes only for the meshes it read (those that give a body mass or
//                   can collide, when lever can read the file);
//   mesh_*          compared per mesh lever read (compare_meshes);
//   names, options  not arrays of the table; keyframes have their own rows (compare_keyframes).
// geom_size, geom_pos, geom_quat, geom_rbound but of mesh geoms lever did not read: MuJoCo fits
// them to the mesh file (its size, its centre and principal axes, the bounding sphere of its box);
// lever keeps the frame as written and the size (so the bounding radius) zero unless it read the
// mesh (a geom that gives its body mass, or can collide): then its size, the bounding box, is
// positive
void compare_geom_frames(Differences& d, const Model& o, const FieldView& view, const MjArray& mj) {
  const std::string name = view.info->name;
  for (int g = 0; g < view.rows; ++g) {
    const size_t geom = static_cast<size_t>(g);
    if (o.geom_type[geom] == GeomType::kMesh && o.geom_size[geom].isZero()) continue;
    if (view.cols == 4) {
      bool same = true, opposite = true;
      for (int k = 0; k < 4; ++k) {
        const double x = element(view, 4 * g + k), y = element(mj, 4 * g + k);
        same = same && agrees(x, y);
        opposite = opposite && agrees(-x, y);
      }
      if (same || opposite) continue;
    }
    for (int k = 0; k < view.cols; ++k) {
      const int i = view.cols * g + k;
      d.real(name, i, element(view, i), element(mj, i));
    }
  }
}

// The meshes (mesh_vertadr, mesh_vertnum, mesh_graphadr, mesh_graph, mesh_facenum, mesh_face,
// and mesh_vert, floats in
// MuJoCo): lever reads a mesh only when a geom must give mass or can collide, so each mesh lever
// read is compared with MuJoCo's at each side's own addresses, vertex for vertex (exactly: both are
// the same floats) and its hull graph int for int; a mesh lever did not read has no vertices.
void compare_meshes(Differences& d, const Model& o, const mjModel& m) {
  if (!d.count("nmesh", o.nmesh, m.nmesh)) return;
  for (int k = 0; k < o.nmesh; ++k) {
    const int n = o.mesh_vertnum[static_cast<size_t>(k)];
    if (n == 0) continue;
    d.integer("mesh_vertnum", k, n, m.mesh_vertnum[k]);
    if (n != m.mesh_vertnum[k]) continue;
    const int ours = o.mesh_vertadr[static_cast<size_t>(k)], theirs = m.mesh_vertadr[k];
    for (int v = 0; v < n; ++v) {
      for (int i = 0; i < 3; ++i) {
        const double a = o.mesh_vert[static_cast<size_t>(ours + v)][i];
        const double b = m.mesh_vert[3 * (theirs + v) + i];
        if (a != b) d.real("mesh_vert", 3 * (theirs + v) + i, a, b);
      }
    }
    const int faces = o.mesh_facenum[static_cast<size_t>(k)];
    d.integer("mesh_facenum", k, faces, m.mesh_facenum[k]);
    if (faces == m.mesh_facenum[k]) {
      const int our_face = o.mesh_faceadr[static_cast<size_t>(k)], their_face = m.mesh_faceadr[k];
      for (int f = 0; f < faces; ++f) {
        for (int i = 0; i < 3; ++i) {
          const int a = o.mesh_face[static_cast<size_t>(our_face + f)][static_cast<size_t>(i)];
          const int b = m.mesh_face[3 * (their_face + f) + i];
          if (a != b) d.integer("mesh_face", 3 * (their_face + f) + i, a, b);
        }
      }
    }
    const int our_graph = o.mesh_graphadr[static_cast<size_t>(k)];
    const int their_graph = m.mesh_graphadr[k];
    d.integer("mesh_graphadr >= 0", k, our_graph >= 0, their_graph >= 0);
    if (our_graph < 0 || their_graph < 0) continue;
    const int* g = m.mesh_graph + their_graph;
    const int size = 2 + 3 * g[0] + 6 * g[1];
    for (int i = 0; i < size && our_graph + i < o.nmeshgraph; ++i) {
      d.integer("mesh_graph", their_graph + i, o.mesh_graph[static_cast<size_t>(our_graph + i)],
                g[i]);
    }
  }
}

void compare_table(Differences& d, const Model& o, const mjModel& m) {
  const std::map<std::string, MjArray> theirs = mujoco_model_arrays(&m);
  for (const FieldView& view : model_fields(o)) {
    const std::string name = view.info->name;
    if (!view.info->in_mujoco || is_constant(name) || name.starts_with("mesh_")) continue;
    const auto found = theirs.find(name);
    if (found == theirs.end() || !same_layout(view, found->second)) {
      d.missing(name);
      continue;
    }
    const MjArray& mj = found->second;
    if (name == "geom_size" || name == "geom_pos" || name == "geom_quat" || name == "geom_rbound") {
      compare_geom_frames(d, o, view, mj);
    } else if (name.starts_with("sensor_")) {
      // compiled from the text alone (ids, counts, the numbers as written): bit for bit
      for (long i = 0; i < view.size(); ++i) {
        d.exact(name, static_cast<int>(i), element(view, i), element(mj, i));
      }
    } else if (view.cols == 4 && name.ends_with("quat")) {
      d.quats(name, view, mj);
    } else if (view.info->scalar == Scalar::kDouble) {
      for (long i = 0; i < view.size(); ++i) {
        d.real(name, static_cast<int>(i), element(view, i), element(mj, i));
      }
    } else {
      for (long i = 0; i < view.size(); ++i) {
        d.integer(name, static_cast<int>(i), static_cast<int>(element(view, i)),
                  static_cast<int>(element(mj, i)));
      }
    }
  }
}

// keyframes are kept outside the table (their row count is nkey, not a model size)
void compare_keyframes(Differences& d, const Model& o, const mjModel& m) {
  if (!d.count("nkey", o.nkey, m.nkey)) return;
  d.names("key_name", o.key_name, m, mjOBJ_KEY);
  for (int k = 0; k < o.nkey; ++k) {
    d.real("key_time", k, o.key_time[static_cast<size_t>(k)], m.key_time[k]);
    for (int i = 0; i < o.nq; ++i)
      d.real("key_qpos", k * o.nq + i, o.key_qpos(k, i), m.key_qpos[k * m.nq + i]);
    for (int i = 0; i < o.nv; ++i)
      d.real("key_qvel", k * o.nv + i, o.key_qvel(k, i), m.key_qvel[k * m.nv + i]);
    for (int i = 0; i < o.nu; ++i)
      d.real("key_ctrl", k * o.nu + i, o.key_ctrl(k, i), m.key_ctrl[k * m.nu + i]);
    if (d.count("na", o.na, m.na)) {
      for (int i = 0; i < o.na; ++i)
        d.real("key_act", k * o.na + i, o.key_act(k, i), m.key_act[k * m.na + i]);
    }
  }
}

void compare_names(Differences& d, const Model& o, const mjModel& m) {
  d.names("body_name", o.body_name, m, mjOBJ_BODY);
  d.names("jnt_name", o.jnt_name, m, mjOBJ_JOINT);
  d.names("geom_name", o.geom_name, m, mjOBJ_GEOM);
  d.names("site_name", o.site_name, m, mjOBJ_SITE);
  d.names("actuator_name", o.actuator_name, m, mjOBJ_ACTUATOR);
  d.names("sensor_name", o.sensor_name, m, mjOBJ_SENSOR);
  d.names("eq_name", o.eq_name, m, mjOBJ_EQUALITY);
  d.names("tendon_name", o.tendon_name, m, mjOBJ_TENDON);
}

void compare_options(Differences& d, const Model& o, const mjModel& m) {
  d.real("opt_timestep", 0, o.opt.timestep, m.opt.timestep);
  for (int k = 0; k < 3; ++k) d.real("opt_gravity", k, o.opt.gravity[k], m.opt.gravity[k]);
  d.integer("opt_integrator", 0, static_cast<int>(o.opt.integrator), m.opt.integrator);
  // contact: lever's Cone and Solver values are mjtCone's and mjtSolver's
  d.integer("opt_cone", 0, static_cast<int>(o.opt.cone), m.opt.cone);
  d.real("opt_impratio", 0, o.opt.impratio, m.opt.impratio);
  d.integer("opt_iterations", 0, o.opt.iterations, m.opt.iterations);
  d.real("opt_tolerance", 0, o.opt.tolerance, m.opt.tolerance);
  d.integer("opt_solver", 0, static_cast<int>(o.opt.solver), m.opt.solver);
  d.integer("opt_jacobian", 0, static_cast<int>(o.opt.jacobian), m.opt.jacobian);
  d.integer("opt_noslip_iterations", 0, 0, m.opt.noslip_iterations);
  d.integer("opt_disableflags", 0, o.opt.disableflags, m.opt.disableflags);
  d.integer("opt_enableflags", 0, o.opt.enableflags, m.opt.enableflags);
  d.real("opt_o_margin", 0, o.opt.o_margin, m.opt.o_margin);
  for (int k = 0; k < 2; ++k) d.real("opt_o_solref", k, o.opt.o_solref[k], m.opt.o_solref[k]);
  for (int k = 0; k < 5; ++k) d.real("opt_o_solimp", k, o.opt.o_solimp[k], m.opt.o_solimp[k]);
  d.real("opt_mpr_tolerance", 0, o.opt.mpr_tolerance, m.opt.mpr_tolerance);
  d.integer("opt_mpr_iterations", 0, o.opt.mpr_iterations, m.opt.mpr_iterations);
  for (int k = 0; k < 3; ++k) d.real("opt_magnetic", k, o.opt.magnetic[k], m.opt.magnetic[k]);
  d.integer("nconmax", 0, o.nconmax, m.nconmax);
  d.integer("njmax", 0, o.njmax, m.njmax);
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
  sizes = d.count("npair", o.npair, m.npair) && sizes;
  sizes = d.count("nexclude", o.nexclude, m.nexclude) && sizes;
  sizes = d.count("nsensor", o.nsensor, m.nsensor) && sizes;
  sizes = d.count("nsensordata", o.nsensordata, m.nsensordata) && sizes;
  sizes = d.count("neq", o.neq, m.neq) && sizes;
  sizes = d.count("ntendon", o.ntendon, m.ntendon) && sizes;
  sizes = d.count("nwrap", o.nwrap, m.nwrap) && sizes;
  sizes = d.count("na", o.na, m.na) && sizes;
  if (sizes) {
    compare_table(d, o, m);
    compare_meshes(d, o, m);
    compare_names(d, o, m);
    compare_keyframes(d, o, m);
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
  if (d.count("ntendon", o.ntendon, m.ntendon) &&
      d.count("size of tendon_length0", static_cast<int>(o.tendon_length0.size()), m.ntendon) &&
      d.count("size of tendon_invweight0", static_cast<int>(o.tendon_invweight0.size()),
              m.ntendon)) {
    d.reals("tendon_length0", o.tendon_length0, m.tendon_length0);
    d.reals("tendon_invweight0", o.tendon_invweight0, m.tendon_invweight0);
  }
  if (d.count("nu", o.nu, m.nu) &&
      d.count("size of actuator_length0", static_cast<int>(o.actuator_length0.size()), m.nu) &&
      d.count("size of actuator_acc0", static_cast<int>(o.actuator_acc0.size()), m.nu)) {
    d.reals("actuator_length0", o.actuator_length0, m.actuator_length0);
    d.reals("actuator_acc0", o.actuator_acc0, m.actuator_acc0);
  }
  return d.list;
}

std::vector<std::string> compare_models(const Model& o, const mjModel& m) {
  std::vector<std::string> differences = compare_parameters(o, m);
  for (std::string& d : compare_constants(o, m)) differences.push_back(std::move(d));
  return differences;
}

std::vector<std::string> compile_differences(const std::string& name, const std::string& xml) {
  const Model ours = mjcf::load_string(xml, name);
  std::string error;
  const MjModelHandle theirs = mujoco_compile(xml, &error);
  if (!theirs) return {std::string("mujoco refuses ").append(name).append(": ").append(error)};
  return compare_models(ours, *theirs);
}

std::string load_refusal(const std::string& xml) {
  try {
    mjcf::load_string(xml, "refused.xml");
  } catch (const mjcf::ParseError& e) {
    return e.what();
  }
  return "";
}

}  // namespace lever::test
