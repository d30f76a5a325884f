// lever for the browser: the engine and mjcf_lite behind a small embind interface that web/lever.js
// turns into MuJoCo's names (model/data objects whose arrays are typed-array views onto the wasm
// heap, mj_step, mj_forward, mj_resetData, mj_setConst).
//
// Every array of the field table (lever/fields.hpp, as MuJoCo's mjxmacro.h) is handed to
// JavaScript as (name, element type, heap address, rows, columns), so a view needs no copy:
// writing data.qpos[0] writes lever's Data. An address stays valid until the object is deleted or,
// for the model, until set_const() (which may rebuild derived arrays): `generation` counts those,
// and lever.js rebuilds its views when it changes or the heap grows. The efc_ arrays have as many
// rows as there are live rows (data.nefc: limits, then contacts), which lever.js reads at each
// access; efc_J (nefc x nv, row-major) likewise. data.contact's first data.ncon entries are
// described by contact_layout() (each member's offset in lever::Contact), so that lever.js views
// them in place as well.
#include <emscripten/bind.h>

#include <cstdint>
#include <exception>
#include <lever/check.hpp>
#include <lever/fields.hpp>
#include <lever/lever.hpp>
#include <lever/mjcf.hpp>
#include <memory>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

namespace {

/// One array as JavaScript sees it: `type` is "f64", "i32" or "u8"; rows x cols elements; cols 0
/// for a single number. `live_rows` is the address of data.nefc for the efc_ arrays, else 0.
struct JsField {
  std::string name;
  std::string type;
  uintptr_t address = 0;
  int rows = 0;
  int cols = 0;
  uintptr_t live_rows = 0;
};

const char* type_name(lever::Scalar scalar) {
  switch (scalar) {
    case lever::Scalar::kDouble: return "f64";
    case lever::Scalar::kInt: return "i32";
    default: return "u8";
  }
}

JsField js_field(const lever::FieldView& v) {
  return {v.info->name,
          type_name(v.info->scalar),
          reinterpret_cast<uintptr_t>(v.data),
          v.rows,
          v.cols,
          0};
}

void add_number(std::vector<JsField>& out, const char* name, double& x) {
  out.push_back({name, "f64", reinterpret_cast<uintptr_t>(&x), 1, 0, 0});
}
void add_number(std::vector<JsField>& out, const char* name, int& x) {
  out.push_back({name, "i32", reinterpret_cast<uintptr_t>(&x), 1, 0, 0});
}

/// Where a member of lever::Contact lies: its offset in bytes, its element type and count.
struct JsMember {
  std::string name;
  std::string type;
  int offset = 0;
  int count = 0;  ///< 0 for a single number
};

/// The layout of lever::Contact (MuJoCo's mjContact's fields): lever's contact field table.
std::vector<JsMember> contact_layout() {
  std::vector<JsMember> members;
  for (const lever::ContactField& f : lever::contact_field_table()) {
    const bool is_int = f.scalar == lever::Scalar::kInt;
    members.push_back({f.name, is_int ? "i32" : "f64", static_cast<int>(f.offset),
                       f.count == 1 ? 0 : f.count});
  }
  return members;
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
    if (what == "na") return model_.na;
    if (what == "nbody") return model_.nbody;
    if (what == "njnt") return model_.njnt;
    if (what == "ngeom") return model_.ngeom;
    if (what == "nsite") return model_.nsite;
    if (what == "npair") return model_.npair;
    if (what == "nexclude") return model_.nexclude;
    if (what == "nmesh") return model_.nmesh;
    if (what == "neq") return model_.neq;
    if (what == "nmocap") return model_.nmocap;
    if (what == "ntendon") return model_.ntendon;
    if (what == "nwrap") return model_.nwrap;
    if (what == "nkey") return model_.nkey;
    if (what == "nsensor") return model_.nsensor;
    if (what == "nsensordata") return model_.nsensordata;
    return -1;
  }

  /// kind: "body", "jnt", "geom", "site", "actuator", "sensor", "eq", "tendon", "key"
  std::vector<std::string> names(const std::string& kind) const {
    if (kind == "sensor") return model_.sensor_name;
    if (kind == "body") return model_.body_name;
    if (kind == "jnt") return model_.jnt_name;
    if (kind == "geom") return model_.geom_name;
    if (kind == "site") return model_.site_name;
    if (kind == "actuator") return model_.actuator_name;
    if (kind == "eq") return model_.eq_name;
    if (kind == "tendon") return model_.tendon_name;
    if (kind == "key") return model_.key_name;
    return {};
  }

  std::vector<JsField> fields() {
    std::vector<JsField> f;
    add_number(f, "opt.timestep", model_.opt.timestep);
    f.push_back(
        {"opt.gravity", "f64", reinterpret_cast<uintptr_t>(model_.opt.gravity.data()), 1, 3, 0});
    // MuJoCo's mjtDisableBit and mjtEnableBit bits, writable (<option><flag>)
    add_number(f, "opt.disableflags", model_.opt.disableflags);
    add_number(f, "opt.enableflags", model_.opt.enableflags);
    add_number(f, "opt.o_margin", model_.opt.o_margin);
    f.push_back(
        {"opt.o_solref", "f64", reinterpret_cast<uintptr_t>(model_.opt.o_solref.data()), 1, 2, 0});
    f.push_back(
        {"opt.o_solimp", "f64", reinterpret_cast<uintptr_t>(model_.opt.o_solimp.data()), 1, 5, 0});
    for (const lever::FieldView& v : lever::model_fields(model_)) f.push_back(js_field(v));
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

  std::vector<JsField> fields() {
    std::vector<JsField> f;
    add_number(f, "time", data_.time);
    add_number(f, "nefc", data_.nefc);
    add_number(f, "ne", data_.ne);
    add_number(f, "nf", data_.nf);
    add_number(f, "ncon", data_.ncon);
    // efc_J's storage has nefc_max rows; row-major, so its first nefc rows are the live ones
    f.push_back({"efc_J", "f64", reinterpret_cast<uintptr_t>(data_.efc_J.data()),
                 static_cast<int>(data_.efc_J.rows()), static_cast<int>(data_.efc_J.cols()),
                 reinterpret_cast<uintptr_t>(&data_.nefc)});
    for (const lever::FieldView& v : lever::data_fields(model_.model(), data_)) {
      JsField js = js_field(v);
      if (v.info->rows == lever::Size::kNefc)
        js.live_rows = reinterpret_cast<uintptr_t>(&data_.nefc);
      f.push_back(js);
    }
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

  /// data.contact: its first element's address (the array holds nconmax, data.ncon are current)
  /// and the distance between two elements, for the views contact_layout() describes.
  uintptr_t contact_address() const { return reinterpret_cast<uintptr_t>(data_.contact.data()); }
  int contact_capacity() const { return static_cast<int>(data_.contact.size()); }
  int contact_stride() const { return static_cast<int>(sizeof(lever::Contact)); }

  /// lever::contact_force (MuJoCo's mj_contactForce) of contact `id` into the 6 numbers at
  /// contact_force_address(); "" or the error (an id outside [0, ncon)).
  std::string contact_force(int id) {
    return guarded(
        [this, id] { contact_force_ = lever::contact_force(model_.model(), data_, id); });
  }
  uintptr_t contact_force_address() const {
    return reinterpret_cast<uintptr_t>(contact_force_.data());
  }

  /// lever::reset_keyframe (MuJoCo's mj_resetDataKeyframe); "" or the error (no such keyframe).
  std::string reset_keyframe(int key) {
    return guarded([this, key] { lever::reset_keyframe(model_.model(), data_, key); });
  }

  /// lever::jac_site (MuJoCo's mj_jacSite) at data's current kinematics, into the 6 x nv buffer at
  /// jac_address(): jacp's 3 rows then jacr's, row-major. "" or the error (a site out of range).
  std::string jac_site(int site) {
    const int nv = model_.model().nv;
    jacp_.resize(3, nv);
    jacr_.resize(3, nv);
    jac_.resize(6, nv);
    return guarded([this, site] {
      lever::jac_site(model_.model(), data_, site, jacp_, jacr_);
      jac_ << jacp_, jacr_;
    });
  }
  uintptr_t jac_address() const { return reinterpret_cast<uintptr_t>(jac_.data()); }

  // The lean calls from qpos (lever/kinematics.hpp), for a controller that needs less than
  // forward; "" or the error.
  /// lever::body_poses: each body's xpos, xquat and xmat.
  std::string body_poses() {
    return guarded([this] { lever::body_poses(model_.model(), data_); });
  }
  /// lever::body_kinematics: kinematics() without the geom and site frames.
  std::string body_kinematics() {
    return guarded([this] { lever::body_kinematics(model_.model(), data_); });
  }
  /// lever::jac_site_from_q: the site's frame and Jacobians from qpos alone, into the buffer at
  /// jac_address() as jac_site() fills it.
  std::string jac_site_from_q(int site) {
    const int nv = model_.model().nv;
    jacp_.resize(3, nv);
    jacr_.resize(3, nv);
    jac_.resize(6, nv);
    return guarded([this, site] {
      lever::jac_site_from_q(model_.model(), data_, site, jacp_, jacr_);
      jac_ << jacp_, jacr_;
    });
  }

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
  // row-major, so that JavaScript reads jacp and jacr as two flat 3 x nv arrays, as MuJoCo's are
  Eigen::Matrix<double, 6, Eigen::Dynamic, Eigen::RowMajor> jac_;
  Eigen::MatrixXd jacp_, jacr_;  // lever::jac_site's (column-major) outputs
  Eigen::Matrix<double, 6, 1> contact_force_ = Eigen::Matrix<double, 6, 1>::Zero();
};

/// `lever check` on MJCF text: lesson 5.1's six checks, lesson 5.2's two and lesson 5.3's contacts,
/// as the command prints them (text) or as its JSON; section (4) loads the same text again with
/// every mass inferred from the geoms, as check_file() does with the file. A model that cannot be
/// loaded gives its diagnostic instead.
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
    const lever::check::Report report = lever::check::run_check(
        {model, inferred ? &*inferred : nullptr, inferred_error, /*key=*/""});
    return json ? lever::check::to_json(report) : lever::check::to_text(report);
  } catch (const std::exception& e) {
    return std::string("error: ") + e.what();
  }
}

}  // namespace

EMSCRIPTEN_BINDINGS(lever) {
  using namespace emscripten;
  function("check_model_text", &check_model_text);
  value_object<JsField>("JsField")
      .field("name", &JsField::name)
      .field("type", &JsField::type)
      .field("address", &JsField::address)
      .field("rows", &JsField::rows)
      .field("cols", &JsField::cols)
      .field("live_rows", &JsField::live_rows);
  register_vector<JsField>("JsFields");
  value_object<JsMember>("JsMember")
      .field("name", &JsMember::name)
      .field("type", &JsMember::type)
      .field("offset", &JsMember::offset)
      .field("count", &JsMember::count);
  register_vector<JsMember>("JsMembers");
  function("contact_layout", &contact_layout);
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
      .function("warnings", &WasmData::warnings)
      .function("contact_address", &WasmData::contact_address)
      .function("contact_capacity", &WasmData::contact_capacity)
      .function("contact_stride", &WasmData::contact_stride)
      .function("contact_force", &WasmData::contact_force)
      .function("contact_force_address", &WasmData::contact_force_address)
      .function("reset_keyframe", &WasmData::reset_keyframe)
      .function("jac_site", &WasmData::jac_site)
      .function("jac_address", &WasmData::jac_address)
      .function("body_poses", &WasmData::body_poses)
      .function("body_kinematics", &WasmData::body_kinematics)
      .function("jac_site_from_q", &WasmData::jac_site_from_q);
  constant("version", std::string(lever::version_string()));
}
