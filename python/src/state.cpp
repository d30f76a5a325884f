// lever.Model and lever.Data as plain Python values, and back (see state.hpp).
#include "state.hpp"

#include <pybind11/stl.h>

#include <lever/error.hpp>
#include <lever/fields.hpp>

#include <cstdint>
#include <cstring>
#include <string>

namespace lever_python {

namespace {

// Bumped when the layout of the state changes, so that an old pickle is refused by name rather
// than misread.
constexpr int kStateVersion = 3;

// The structs outside the field table are carried member by member below. A member added to one
// of them changes its size and stops the build here: carry the new member too, then update the
// size.
static_assert(sizeof(lever::Options) == 224, "lever::Options changed: pickle its new member");
static_assert(sizeof(lever::CompilerInfo) == 12, "lever::CompilerInfo changed: pickle it");
static_assert(sizeof(lever::VisualInfo) == 8 * sizeof(std::vector<std::string>) +
                                               2 * sizeof(std::string),
              "lever::VisualInfo changed: pickle its new member");
static_assert(sizeof(lever::WarningStat) == 2 * sizeof(int), "lever::WarningStat changed");

std::size_t scalar_bytes(lever::Scalar scalar) {
  switch (scalar) {
    case lever::Scalar::kDouble: return sizeof(double);
    case lever::Scalar::kInt: return sizeof(int32_t);
    case lever::Scalar::kByte: return sizeof(uint8_t);
  }
  return 1;
}

py::bytes bytes_of(const void* data, std::size_t n) {
  return {static_cast<const char*>(data), n};
}

// Copies `value` (bytes of exactly `n`) to `into`; `what` names it in the error.
void write_bytes(const py::handle& value, void* into, std::size_t n, const std::string& what) {
  const std::string text = value.cast<std::string>();
  if (text.size() != n) {
    throw lever::StateError("lever: cannot unpickle: " + what + " holds " +
                            std::to_string(text.size()) + " bytes where this model needs " +
                            std::to_string(n) + ".");
  }
  if (n > 0) std::memcpy(into, text.data(), n);
}

py::handle item(const py::dict& d, const char* key, const char* what) {
  if (!d.contains(key)) {
    throw lever::StateError(std::string("lever: cannot unpickle ") + what + ": no '" + key +
                            "' (not a state lever wrote).");
  }
  return d[key];
}

void check_version(const py::dict& state, const char* what) {
  const int version = item(state, "version", what).cast<int>();
  if (version != kStateVersion) {
    throw lever::StateError(std::string("lever: cannot unpickle ") + what + " of state version " +
                            std::to_string(version) + ": this lever reads version " +
                            std::to_string(kStateVersion) + ".");
  }
}

// The counts that size a model (size_model reads them) and the capacities of its Data.
#define LEVER_PYTHON_MODEL_COUNTS(X) \
  X(nq) X(nv) X(nu) X(nbody) X(njnt) X(ngeom) X(nsite) X(nkey) X(npair) X(nexclude) X(nconmax) X(njmax) \
  X(nmesh) X(nmeshvert) X(nmeshgraph) X(nmeshface) X(nsensor) X(nsensordata) X(neq) X(nmocap) \
  X(nuser_body) X(nuser_jnt) X(nuser_geom) X(nuser_site) X(nuser_tendon) X(nuser_actuator) \
  X(nuser_sensor) \
  X(ntendon) X(nwrap) X(na)

// a keyframe array (nkey x n, row-major) as bytes, and back
py::bytes matrix_bytes(const lever::ArenaRowMatrix& a) {
  return bytes_of(a.data(), sizeof(double) * static_cast<std::size_t>(a.size()));
}

}  // namespace

// ---- Model ---------------------------------------------------------------------------------------

py::dict model_state(const lever::Model& model) {
  py::dict state;
  state["version"] = kStateVersion;
  state["name"] = model.name;
  state["source"] = model.source;
  state["warnings"] = model.warnings;

  py::dict counts;
#define LEVER_PYTHON_PUT_COUNT(count) counts[#count] = model.count;
  LEVER_PYTHON_MODEL_COUNTS(LEVER_PYTHON_PUT_COUNT)
#undef LEVER_PYTHON_PUT_COUNT
  state["counts"] = counts;

  py::dict names;
#define LEVER_PYTHON_PUT_NAMES(member, count) names[#member] = model.member;
  LEVER_MODEL_NAMES(LEVER_PYTHON_PUT_NAMES)
#undef LEVER_PYTHON_PUT_NAMES
  state["names"] = names;

  py::dict keys;
  keys["key_time"] = bytes_of(model.key_time.data(), sizeof(double) * model.key_time.size());
  keys["key_qpos"] = matrix_bytes(model.key_qpos);
  keys["key_qvel"] = matrix_bytes(model.key_qvel);
  keys["key_ctrl"] = matrix_bytes(model.key_ctrl);
  keys["key_act"] = matrix_bytes(model.key_act);
  keys["key_mpos"] = matrix_bytes(model.key_mpos);
  keys["key_mquat"] = matrix_bytes(model.key_mquat);
  state["keys"] = keys;

  const lever::Options& o = model.opt;
  py::dict opt;
  opt["timestep"] = o.timestep;
  opt["gravity"] = bytes_of(o.gravity.data(), 3 * sizeof(double));
  opt["integrator"] = static_cast<int>(o.integrator);
  opt["cone"] = static_cast<int>(o.cone);
  opt["solver"] = static_cast<int>(o.solver);
  opt["impratio"] = o.impratio;
  opt["iterations"] = o.iterations;
  opt["tolerance"] = o.tolerance;
  opt["jacobian"] = static_cast<int>(o.jacobian);
  opt["mpr_tolerance"] = o.mpr_tolerance;
  opt["mpr_iterations"] = o.mpr_iterations;
  opt["magnetic"] = bytes_of(o.magnetic.data(), 3 * sizeof(double));
  opt["viscosity"] = o.viscosity;
  opt["density"] = o.density;
  opt["wind"] = bytes_of(o.wind.data(), 3 * sizeof(double));
  opt["o_margin"] = o.o_margin;
  opt["o_solref"] = bytes_of(o.o_solref.data(), 2 * sizeof(double));
  opt["o_solimp"] = bytes_of(o.o_solimp.data(), 5 * sizeof(double));
  opt["disableflags"] = o.disableflags;
  opt["enableflags"] = o.enableflags;
  state["opt"] = opt;

  py::dict compiler;
  compiler["inertiagrouprange"] = model.compiler.inertiagrouprange;
  compiler["inertia_from_geoms_allowed"] = model.compiler.inertia_from_geoms_allowed;
  state["compiler"] = compiler;

  const lever::VisualInfo& v = model.visual;
  py::dict visual;
  visual["meshdir"] = v.meshdir;
  visual["texturedir"] = v.texturedir;
  visual["mesh_name"] = v.mesh_name;
  visual["mesh_file"] = v.mesh_file;
  visual["material_name"] = v.material_name;
  visual["texture_name"] = v.texture_name;
  visual["light_name"] = v.light_name;
  visual["camera_name"] = v.camera_name;
  visual["geom_mesh"] = v.geom_mesh;
  visual["geom_material"] = v.geom_material;
  state["visual"] = visual;

  py::dict fields;
  for (const lever::FieldView& f : lever::model_fields(model)) {
    fields[f.info->name] =
        bytes_of(f.data, static_cast<std::size_t>(f.size()) * scalar_bytes(f.info->scalar));
  }
  state["fields"] = fields;
  return state;
}

namespace {

// Every array of the table from the state's bytes (each must be there, with this model's size).
void write_model_fields(lever::Model& model, const py::dict& fields) {
  for (lever::FieldView& f : lever::model_fields(model)) {
    const std::string name = f.info->name;
    write_bytes(item(fields, f.info->name, "a model"), f.data,
                static_cast<std::size_t>(f.size()) * scalar_bytes(f.info->scalar), "model." + name);
  }
}

void write_matrix(const py::dict& keys, const char* name, lever::ArenaRowMatrix& a) {
  write_bytes(item(keys, name, "a model"), a.data(),
              sizeof(double) * static_cast<std::size_t>(a.size()), std::string("model.") + name);
}

}  // namespace

std::shared_ptr<lever::Model> model_from_state(const py::dict& state) {
  check_version(state, "a model");
  auto model = std::make_shared<lever::Model>();
  lever::Model& m = *model;
  m.name = item(state, "name", "a model").cast<std::string>();
  m.source = item(state, "source", "a model").cast<std::string>();
  m.warnings = item(state, "warnings", "a model").cast<std::vector<std::string>>();

  const py::dict counts = item(state, "counts", "a model").cast<py::dict>();
#define LEVER_PYTHON_GET_COUNT(count) m.count = item(counts, #count, "a model").cast<int>();
  LEVER_PYTHON_MODEL_COUNTS(LEVER_PYTHON_GET_COUNT)
#undef LEVER_PYTHON_GET_COUNT
  lever::size_model(m);

  const py::dict names = item(state, "names", "a model").cast<py::dict>();
#define LEVER_PYTHON_GET_NAMES(member, count)                                                   \
  m.member = item(names, #member, "a model").cast<std::vector<std::string>>();                  \
  if (static_cast<int>(m.member.size()) != m.count) {                                            \
    throw lever::StateError("lever: cannot unpickle: model." #member " has " +                  \
                            std::to_string(m.member.size()) + " names for " #count " = " +      \
                            std::to_string(m.count) + ".");                                     \
  }
  LEVER_MODEL_NAMES(LEVER_PYTHON_GET_NAMES)
#undef LEVER_PYTHON_GET_NAMES

  const py::dict keys = item(state, "keys", "a model").cast<py::dict>();
  write_bytes(item(keys, "key_time", "a model"), m.key_time.data(),
              sizeof(double) * m.key_time.size(), "model.key_time");
  write_matrix(keys, "key_qpos", m.key_qpos);
  write_matrix(keys, "key_qvel", m.key_qvel);
  write_matrix(keys, "key_ctrl", m.key_ctrl);
  write_matrix(keys, "key_act", m.key_act);
  write_matrix(keys, "key_mpos", m.key_mpos);
  write_matrix(keys, "key_mquat", m.key_mquat);

  const py::dict opt = item(state, "opt", "a model").cast<py::dict>();
  m.opt.timestep = item(opt, "timestep", "a model").cast<double>();
  write_bytes(item(opt, "gravity", "a model"), m.opt.gravity.data(), 3 * sizeof(double),
              "model.opt.gravity");
  m.opt.integrator = static_cast<lever::Integrator>(item(opt, "integrator", "a model").cast<int>());
  m.opt.cone = static_cast<lever::Cone>(item(opt, "cone", "a model").cast<int>());
  m.opt.solver = static_cast<lever::Solver>(item(opt, "solver", "a model").cast<int>());
  m.opt.impratio = item(opt, "impratio", "a model").cast<double>();
  m.opt.iterations = item(opt, "iterations", "a model").cast<int>();
  m.opt.tolerance = item(opt, "tolerance", "a model").cast<double>();
  m.opt.jacobian = static_cast<lever::JacobianLayout>(item(opt, "jacobian", "a model").cast<int>());
  m.opt.mpr_tolerance = item(opt, "mpr_tolerance", "a model").cast<double>();
  m.opt.mpr_iterations = item(opt, "mpr_iterations", "a model").cast<int>();
  write_bytes(item(opt, "magnetic", "a model"), m.opt.magnetic.data(), 3 * sizeof(double),
              "model.opt.magnetic");
  m.opt.viscosity = item(opt, "viscosity", "a model").cast<double>();
  m.opt.density = item(opt, "density", "a model").cast<double>();
  write_bytes(item(opt, "wind", "a model"), m.opt.wind.data(), 3 * sizeof(double),
              "model.opt.wind");
  m.opt.o_margin = item(opt, "o_margin", "a model").cast<double>();
  write_bytes(item(opt, "o_solref", "a model"), m.opt.o_solref.data(), 2 * sizeof(double),
              "model.opt.o_solref");
  write_bytes(item(opt, "o_solimp", "a model"), m.opt.o_solimp.data(), 5 * sizeof(double),
              "model.opt.o_solimp");
  m.opt.disableflags = item(opt, "disableflags", "a model").cast<int>();
  m.opt.enableflags = item(opt, "enableflags", "a model").cast<int>();

  const py::dict compiler = item(state, "compiler", "a model").cast<py::dict>();
  m.compiler.inertiagrouprange =
      item(compiler, "inertiagrouprange", "a model").cast<std::array<int, 2>>();
  m.compiler.inertia_from_geoms_allowed =
      item(compiler, "inertia_from_geoms_allowed", "a model").cast<bool>();

  const py::dict visual = item(state, "visual", "a model").cast<py::dict>();
  lever::VisualInfo& v = m.visual;
  const auto strings = [&visual](const char* key) {
    return item(visual, key, "a model").cast<std::vector<std::string>>();
  };
  v.meshdir = item(visual, "meshdir", "a model").cast<std::string>();
  v.texturedir = item(visual, "texturedir", "a model").cast<std::string>();
  v.mesh_name = strings("mesh_name");
  v.mesh_file = strings("mesh_file");
  v.material_name = strings("material_name");
  v.texture_name = strings("texture_name");
  v.light_name = strings("light_name");
  v.camera_name = strings("camera_name");
  v.geom_mesh = strings("geom_mesh");
  v.geom_material = strings("geom_material");

  // set_const derives what lies outside the table (frames, the link tree, the collision
  // constants) from the parameters; the table's arrays are then written once more, so that each
  // holds the pickled bytes even where set_const would have computed another value
  const py::dict fields = item(state, "fields", "a model").cast<py::dict>();
  write_model_fields(m, fields);
  lever::set_const(m);
  write_model_fields(m, fields);
  return model;
}

// ---- Data ----------------------------------------------------------------------------------------

py::dict data_state(const lever::Model& model, const lever::Data& data) {
  lever::check_fit(model, data, "lever: pickling a Data");
  py::dict state;
  state["version"] = kStateVersion;
  state["time"] = data.time;
  state["ncon"] = data.ncon;
  state["nefc"] = data.nefc;

  py::dict fields;
  for (const lever::FieldView& f : lever::data_fields(model, data)) {
    fields[f.info->name] =
        bytes_of(f.data, static_cast<std::size_t>(f.size()) * scalar_bytes(f.info->scalar));
  }
  state["fields"] = fields;

  // outside the table: efc_J's live rows (row-major), the factor of M and the spatial inertias
  // (solve_mass and rnea read them after forward)
  state["efc_J"] = bytes_of(data.efc_J.data(), sizeof(double) * static_cast<std::size_t>(
                                                                     data.nefc * model.nv));
  state["qLD"] = bytes_of(data.qLD.data(), sizeof(double) * static_cast<std::size_t>(data.qLD.size()));
  std::vector<double> cinert;
  for (const lever::RigidInertia& c : data.cinert) {
    cinert.push_back(c.m);
    cinert.insert(cinert.end(), c.h.data(), c.h.data() + 3);
    cinert.insert(cinert.end(), c.I.data(), c.I.data() + 9);
  }
  state["cinert"] = bytes_of(cinert.data(), sizeof(double) * cinert.size());

  py::dict contact;
  for (const ContactMember& member : contact_members()) {
    const std::size_t bytes = (is_int(member) ? sizeof(int) : sizeof(double)) * member.count;
    std::string column;
    for (int i = 0; i < data.ncon; ++i) {
      const char* at = reinterpret_cast<const char*>(&data.contact[i]) + member.offset;
      column.append(at, bytes);
    }
    contact[member.name] = py::bytes(column);
  }
  state["contact"] = contact;

  py::list warnings;
  for (const lever::WarningStat& w : data.warning) warnings.append(py::make_tuple(w.number, w.lastinfo));
  state["warning"] = warnings;
  return state;
}

void restore_data(const lever::Model& model, lever::Data& data, const py::dict& state) {
  check_version(state, "a Data");
  data.time = item(state, "time", "a Data").cast<double>();
  const int ncon = item(state, "ncon", "a Data").cast<int>();
  const int nefc = item(state, "nefc", "a Data").cast<int>();
  if (ncon < 0 || ncon > static_cast<int>(data.contact.size()) || nefc < 0 ||
      nefc > data.nefc_max) {
    throw lever::StateError("lever: cannot unpickle a Data with " + std::to_string(ncon) +
                            " contacts and " + std::to_string(nefc) +
                            " constraint rows for this model (it holds at most " +
                            std::to_string(data.contact.size()) + " and " +
                            std::to_string(data.nefc_max) + ").");
  }
  data.ncon = ncon;
  data.nefc = nefc;  // the efc arrays of the table now have nefc rows

  const py::dict fields = item(state, "fields", "a Data").cast<py::dict>();
  for (lever::FieldView& f : lever::data_fields(model, data)) {
    write_bytes(item(fields, f.info->name, "a Data"), f.data,
                static_cast<std::size_t>(f.size()) * scalar_bytes(f.info->scalar),
                std::string("data.") + f.info->name);
  }
  write_bytes(item(state, "efc_J", "a Data"), data.efc_J.data(),
              sizeof(double) * static_cast<std::size_t>(nefc * model.nv), "data.efc_J");
  write_bytes(item(state, "qLD", "a Data"), data.qLD.data(),
              sizeof(double) * static_cast<std::size_t>(data.qLD.size()), "data.qLD");
  std::vector<double> cinert(13 * data.cinert.size());
  write_bytes(item(state, "cinert", "a Data"), cinert.data(), sizeof(double) * cinert.size(),
              "data.cinert");
  for (std::size_t b = 0; b < data.cinert.size(); ++b) {
    const double* c = &cinert[13 * b];
    data.cinert[b].m = c[0];
    std::copy(c + 1, c + 4, data.cinert[b].h.data());
    std::copy(c + 4, c + 13, data.cinert[b].I.data());
  }

  const py::dict contact = item(state, "contact", "a Data").cast<py::dict>();
  for (const ContactMember& member : contact_members()) {
    const std::size_t bytes = (is_int(member) ? sizeof(int) : sizeof(double)) * member.count;
    std::string column(bytes * ncon, '\0');
    write_bytes(item(contact, member.name, "a Data"), column.data(), column.size(),
                std::string("data.contact.") + member.name);
    for (int i = 0; i < ncon; ++i) {
      char* at = reinterpret_cast<char*>(&data.contact[i]) + member.offset;
      std::memcpy(at, column.data() + bytes * i, bytes);
    }
  }

  const py::list warnings = item(state, "warning", "a Data").cast<py::list>();
  if (warnings.size() != data.warning.size()) {
    throw lever::StateError("lever: cannot unpickle a Data with " +
                            std::to_string(warnings.size()) + " kinds of warning; this lever has " +
                            std::to_string(data.warning.size()) + ".");
  }
  for (std::size_t w = 0; w < data.warning.size(); ++w) {
    const auto pair = warnings[w].cast<std::pair<int, int>>();
    data.warning[w].number = pair.first;
    data.warning[w].lastinfo = pair.second;
  }
}

}  // namespace lever_python
