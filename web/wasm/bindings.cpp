// lever for the browser: the engine and mjcf_lite behind a small embind interface that web/lever.js
// turns into MuJoCo's names (model/data objects whose arrays are typed-array views onto the wasm
// heap, mj_step, mj_forward, mj_resetData, mj_setConst).
//
// Every array is handed to JavaScript as (name, element type, heap address, rows, columns), so a
// view needs no copy: writing data.qpos[0] writes lever's Data. An address stays valid until the
// object is deleted or, for the model, until set_const() (which may rebuild derived arrays):
// `generation` counts those, and lever.js rebuilds its views when it changes or the heap grows.
#include <emscripten/bind.h>

#include <cstdint>
#include <exception>
#include <lever/check.hpp>
#include <lever/lever.hpp>
#include <lever/mjcf.hpp>
#include <memory>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

namespace {

/// One array as JavaScript sees it: `type` is "f64", "i32" or "u8"; rows x cols elements.
struct FieldView {
  std::string name;
  std::string type;
  uintptr_t address = 0;
  int rows = 0;
  int cols = 0;
};

template <typename T>
std::string type_name() {
  if constexpr (std::is_same_v<T, double>) return "f64";
  if constexpr (std::is_same_v<T, int> || std::is_enum_v<T>) return "i32";
  if constexpr (std::is_same_v<T, uint8_t>) return "u8";
}

// std::vector of scalars, of Eigen fixed-size vectors (contiguous, no padding) or of std::array
template <typename T>
void add(std::vector<FieldView>& out, const char* name, std::vector<T>& v) {
  if constexpr (std::is_arithmetic_v<T> || std::is_enum_v<T>) {
    out.push_back({name, type_name<T>(), reinterpret_cast<uintptr_t>(v.data()),
                   static_cast<int>(v.size()), 1});
  } else if constexpr (requires { T::RowsAtCompileTime; }) {
    static_assert(sizeof(T) == sizeof(double) * T::RowsAtCompileTime * T::ColsAtCompileTime);
    out.push_back({name, "f64", reinterpret_cast<uintptr_t>(v.data()), static_cast<int>(v.size()),
                   static_cast<int>(T::RowsAtCompileTime * T::ColsAtCompileTime)});
  } else {
    using E = typename T::value_type;
    static_assert(sizeof(T) == sizeof(E) * std::tuple_size_v<T>);
    out.push_back({name, type_name<E>(), reinterpret_cast<uintptr_t>(v.data()),
                   static_cast<int>(v.size()), static_cast<int>(std::tuple_size_v<T>)});
  }
}

void add(std::vector<FieldView>& out, const char* name, Eigen::VectorXd& v) {
  out.push_back(
      {name, "f64", reinterpret_cast<uintptr_t>(v.data()), static_cast<int>(v.size()), 1});
}

template <typename T>
void add_scalar(std::vector<FieldView>& out, const char* name, T& x) {
  out.push_back({name, type_name<T>(), reinterpret_cast<uintptr_t>(&x), 1, 0});
}

template <typename T, size_t N>
void add_fixed(std::vector<FieldView>& out, const char* name, T* x) {
  out.push_back({name, type_name<T>(), reinterpret_cast<uintptr_t>(x), 1, static_cast<int>(N)});
}

/// A compiled model; `error`/`error_line` say why a load failed (then the model is empty).
class WasmModel {
 public:
  static std::unique_ptr<WasmModel> load(const std::string& xml, const std::string& filename) {
    auto m = std::make_unique<WasmModel>();
    try {
      m->model_ = lever::mjcf::load_string(xml, filename);
      m->ok_ = true;
    } catch (const lever::mjcf::ParseError& e) {
      m->error_ = e.what();
      m->error_line_ = e.line();
    } catch (const std::exception& e) {
      m->error_ = e.what();
    }
    return m;
  }

  bool ok() const { return ok_; }
  std::string error() const { return error_; }
  int error_line() const { return error_line_; }
  int generation() const { return generation_; }
  lever::Model& model() { return model_; }

  /// lever::set_const after parameters were edited through the views; "" or the error.
  std::string set_const() {
    ++generation_;
    try {
      lever::set_const(model_);
    } catch (const std::exception& e) {
      return e.what();
    }
    return "";
  }

  int size(const std::string& what) const {
    if (what == "nq") return model_.nq;
    if (what == "nv") return model_.nv;
    if (what == "nu") return model_.nu;
    if (what == "nbody") return model_.nbody;
    if (what == "njnt") return model_.njnt;
    if (what == "ngeom") return model_.ngeom;
    if (what == "nsite") return model_.nsite;
    return -1;
  }

  /// kind: "body", "jnt", "geom", "site", "actuator"
  std::vector<std::string> names(const std::string& kind) const {
    if (kind == "body") return model_.body_name;
    if (kind == "jnt") return model_.jnt_name;
    if (kind == "geom") return model_.geom_name;
    if (kind == "site") return model_.site_name;
    if (kind == "actuator") return model_.actuator_name;
    return {};
  }

  std::vector<FieldView> fields() {
    lever::Model& m = model_;
    std::vector<FieldView> f;
    add_scalar(f, "opt.timestep", m.opt.timestep);
    add_fixed<double, 3>(f, "opt.gravity", m.opt.gravity.data());
    add(f, "body_parentid", m.body_parentid);
    add(f, "body_rootid", m.body_rootid);
    add(f, "body_jntnum", m.body_jntnum);
    add(f, "body_jntadr", m.body_jntadr);
    add(f, "body_dofnum", m.body_dofnum);
    add(f, "body_dofadr", m.body_dofadr);
    add(f, "body_geomnum", m.body_geomnum);
    add(f, "body_geomadr", m.body_geomadr);
    add(f, "body_pos", m.body_pos);
    add(f, "body_quat", m.body_quat);
    add(f, "body_ipos", m.body_ipos);
    add(f, "body_iquat", m.body_iquat);
    add(f, "body_mass", m.body_mass);
    add(f, "body_inertia", m.body_inertia);
    add(f, "body_subtreemass", m.body_subtreemass);
    add(f, "jnt_type", m.jnt_type);
    add(f, "jnt_qposadr", m.jnt_qposadr);
    add(f, "jnt_dofadr", m.jnt_dofadr);
    add(f, "jnt_bodyid", m.jnt_bodyid);
    add(f, "jnt_solref", m.jnt_solref);
    add(f, "jnt_solimp", m.jnt_solimp);
    add(f, "jnt_pos", m.jnt_pos);
    add(f, "jnt_axis", m.jnt_axis);
    add(f, "jnt_stiffness", m.jnt_stiffness);
    add(f, "jnt_range", m.jnt_range);
    add(f, "jnt_margin", m.jnt_margin);
    add(f, "qpos0", m.qpos0);
    add(f, "qpos_spring", m.qpos_spring);
    add(f, "dof_bodyid", m.dof_bodyid);
    add(f, "dof_jntid", m.dof_jntid);
    add(f, "dof_parentid", m.dof_parentid);
    add(f, "dof_armature", m.dof_armature);
    add(f, "dof_damping", m.dof_damping);
    add(f, "dof_invweight0", m.dof_invweight0);
    add(f, "dof_M0", m.dof_M0);
    add(f, "geom_type", m.geom_type);
    add(f, "geom_bodyid", m.geom_bodyid);
    add(f, "geom_contype", m.geom_contype);
    add(f, "geom_conaffinity", m.geom_conaffinity);
    add(f, "geom_group", m.geom_group);
    add(f, "geom_size", m.geom_size);
    add(f, "geom_pos", m.geom_pos);
    add(f, "geom_quat", m.geom_quat);
    add(f, "geom_rgba", m.geom_rgba);
    add(f, "site_bodyid", m.site_bodyid);
    add(f, "site_pos", m.site_pos);
    add(f, "site_quat", m.site_quat);
    add(f, "site_size", m.site_size);
    add(f, "actuator_gear", m.actuator_gear);
    add(f, "actuator_ctrlrange", m.actuator_ctrlrange);
    add(f, "actuator_forcerange", m.actuator_forcerange);
    // Not here yet: the std::vector<bool> flags (jnt_limited, actuator_ctrllimited, ...), which
    // cannot be viewed until Model stores them as uint8_t; actuator_trnid, whose shape differs
    // from MuJoCo's (nu x 2 there).
    return f;
  }

 private:
  lever::Model model_;
  bool ok_ = false;
  std::string error_;
  int error_line_ = 0;
  int generation_ = 0;
};

/// The state of one simulation of a model (which must outlive it).
class WasmData {
 public:
  explicit WasmData(WasmModel& model) : model_(model), data_(model.model()) {}

  std::vector<FieldView> fields() {
    lever::Data& d = data_;
    std::vector<FieldView> f;
    add_scalar(f, "time", d.time);
    add_scalar(f, "nefc", d.nefc);
    add(f, "qpos", d.qpos);
    add(f, "qvel", d.qvel);
    add(f, "ctrl", d.ctrl);
    add(f, "qfrc_applied", d.qfrc_applied);
    add(f, "xpos", d.xpos);
    add(f, "xquat", d.xquat);
    add(f, "xipos", d.xipos);
    add(f, "site_xpos", d.site_xpos);
    add(f, "xanchor", d.xanchor);
    add(f, "xaxis", d.xaxis);
    add(f, "subtree_com", d.subtree_com);
    add(f, "actuator_length", d.actuator_length);
    add(f, "actuator_velocity", d.actuator_velocity);
    add(f, "qfrc_passive", d.qfrc_passive);
    add(f, "qfrc_bias", d.qfrc_bias);
    add(f, "actuator_force", d.actuator_force);
    add(f, "qfrc_actuator", d.qfrc_actuator);
    add(f, "qfrc_smooth", d.qfrc_smooth);
    add(f, "qacc_smooth", d.qacc_smooth);
    add(f, "qfrc_constraint", d.qfrc_constraint);
    add(f, "qacc", d.qacc);
    add(f, "qfrc_inverse", d.qfrc_inverse);
    add_fixed<double, 2>(f, "energy", d.energy.data());
    // M is symmetric, so its column-major storage reads the same as MuJoCo's row-major one
    f.push_back({"qM_full", "f64", reinterpret_cast<uintptr_t>(d.M.data()),
                 static_cast<int>(d.M.rows()), static_cast<int>(d.M.cols())});
    // Not here yet: xmat, ximat, site_xmat (column-major in lever until issue 11 makes them
    // row-major as MuJoCo's), and the efc_ arrays (their length changes with nefc).
    return f;
  }

  // The simulation calls; "" or the error (a model/data mismatch, an invalid model).
  std::string step() {
    return guarded([this] { lever::step(model_.model(), data_); });
  }
  std::string forward() {
    return guarded([this] { lever::forward(model_.model(), data_); });
  }
  std::string reset() {
    return guarded([this] { lever::reset(model_.model(), data_); });
  }
  /// n steps in one call (for the page's real-time loop and for timing)
  std::string steps(int n) {
    return guarded([this, n] {
      for (int i = 0; i < n; ++i) lever::step(model_.model(), data_);
    });
  }
  std::string warnings() const { return lever::warning_text(data_); }

 private:
  template <typename F>
  static std::string guarded(F f) {
    try {
      f();
    } catch (const std::exception& e) {
      return e.what();
    }
    return "";
  }

  WasmModel& model_;
  lever::Data data_;
};

/// `lever check` on MJCF text: the six checks of lesson 5.1 as the command prints them (text) or
/// as its JSON; section (4) loads the same text again with every mass inferred from the geoms, as
/// check_file() does with the file. A model that cannot be loaded gives its diagnostic instead.
std::string check_model_text(const std::string& xml, const std::string& filename, bool json) {
  try {
    lever::Model model = lever::mjcf::load_string(xml, filename);
    model.source = filename;
    std::optional<lever::Model> inferred;
    std::string inferred_error;
    try {
      inferred = lever::mjcf::load_string(xml, filename, {.infer_inertia_from_geoms = true});
    } catch (const lever::Error& e) {
      inferred_error = e.what();
    }
    const lever::check::Report report =
        lever::check::run_check({model, inferred ? &*inferred : nullptr, inferred_error});
    return json ? lever::check::to_json(report) : lever::check::to_text(report);
  } catch (const std::exception& e) {
    return std::string("error: ") + e.what();
  }
}

}  // namespace

EMSCRIPTEN_BINDINGS(lever) {
  using namespace emscripten;
  function("check_model_text", &check_model_text);
  value_object<FieldView>("FieldView")
      .field("name", &FieldView::name)
      .field("type", &FieldView::type)
      .field("address", &FieldView::address)
      .field("rows", &FieldView::rows)
      .field("cols", &FieldView::cols);
  register_vector<FieldView>("FieldViews");
  register_vector<std::string>("Strings");
  class_<WasmModel>("WasmModel")
      .class_function("load", &WasmModel::load)
      .function("ok", &WasmModel::ok)
      .function("error", &WasmModel::error)
      .function("error_line", &WasmModel::error_line)
      .function("generation", &WasmModel::generation)
      .function("set_const", &WasmModel::set_const)
      .function("size", &WasmModel::size)
      .function("names", &WasmModel::names)
      .function("fields", &WasmModel::fields);
  class_<WasmData>("WasmData")
      .constructor<WasmModel&>()
      .function("fields", &WasmData::fields)
      .function("step", &WasmData::step)
      .function("forward", &WasmData::forward)
      .function("reset", &WasmData::reset)
      .function("steps", &WasmData::steps)
      .function("warnings", &WasmData::warnings);
  constant("version", std::string(lever::version_string()));
}
