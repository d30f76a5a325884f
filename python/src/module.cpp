// lever._lever: the C++ library seen from Python.
//
// Model and Data are exposed with every array of the field table (lever/fields.hpp) as a numpy
// array that is a zero-copy view of lever's own memory: writing into `data.qpos[:]` writes the
// state lever evaluates, and writing into `model.body_mass[2]` changes the model (call
// set_const afterwards, as after any parameter edit). A view keeps its Model or Data alive.
// Functions take (model, data) as the C++ ones do; every one checks that the two belong together.
// Errors come back as exceptions: lever.ParseError (file, line, element, attribute), ModelError,
// StateError.
#include <pybind11/eigen.h>
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <lever/batch.hpp>
#include <lever/check.hpp>
#include <lever/derivatives.hpp>
#include <lever/fields.hpp>
#include <lever/identify.hpp>
#include <lever/io/serialize.hpp>
#include <lever/lab/lab.hpp>
#include <lever/lever.hpp>
#include <lever/mjcf.hpp>
#include <lever/regressor.hpp>

#include "state.hpp"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace py = pybind11;

namespace {

// A Data with the model it was built for, so that Python can never pair them wrongly by accident
// and the model outlives every Data made from it.
struct PyData {
  std::shared_ptr<lever::Model> model;
  lever::Data data;
  explicit PyData(std::shared_ptr<lever::Model> m) : model(std::move(m)), data(*model) {}
  PyData(std::shared_ptr<lever::Model> m, const lever::Data& d) : model(std::move(m)), data(d) {}
};

using ModelPtr = std::shared_ptr<lever::Model>;
using DataPtr = std::shared_ptr<PyData>;

// The Data a pipeline call (lever.forward, lever.step, ...) is evaluating on this thread, so that
// a Python sensor callback is handed the lever.Data it fills.
thread_local const DataPtr* evaluating_data = nullptr;

struct Evaluating {
  const DataPtr* previous;
  explicit Evaluating(const DataPtr& d) : previous(evaluating_data) { evaluating_data = &d; }
  ~Evaluating() { evaluating_data = previous; }
};

// Model::sensor_callback calling a Python function fn(model, data, stage) (MuJoCo's mjcb_sensor;
// stage 1, 2, 3: position, velocity, acceleration).
lever::SensorCallback python_sensor_callback(py::object fn, std::weak_ptr<lever::Model> model) {
  return [fn = std::move(fn), model](const lever::Model&, lever::Data& data,
                                     lever::SensorStage stage) {
    py::gil_scoped_acquire gil;
    if (evaluating_data == nullptr || &(*evaluating_data)->data != &data) {
      throw lever::StateError(
          "lever: a Python sensor callback runs in lever.forward, step, step1, step2 and "
          "inverse on a lever.Data, not in a batch.");
    }
    fn(model.lock(), *evaluating_data, static_cast<int>(stage));
  };
}

// A Model actuator callback calling a Python function fn(model, data, id) -> float (MuJoCo's
// mjcb_act_gain, mjcb_act_bias, mjcb_act_dyn).
lever::ActuatorCallback python_actuator_callback(py::object fn, std::weak_ptr<lever::Model> model) {
  return [fn = std::move(fn), model](const lever::Model&, const lever::Data& data, int id) {
    py::gil_scoped_acquire gil;
    if (evaluating_data == nullptr || &(*evaluating_data)->data != &data) {
      throw lever::StateError(
          "lever: a Python actuator callback runs in lever.forward, step, step1, step2 and "
          "inverse on a lever.Data, not in a batch.");
    }
    return fn(model.lock(), *evaluating_data, id).cast<double>();
  };
}

// A keyframe array (nkey x n, row-major) as a writable (nkey, n) numpy view.
py::array key_view(lever::ArenaRowMatrix& a, py::handle owner) {
  const auto item = static_cast<py::ssize_t>(sizeof(double));
  return py::array_t<double>(
      {static_cast<py::ssize_t>(a.rows()), static_cast<py::ssize_t>(a.cols())},
      {item * static_cast<py::ssize_t>(a.cols()), item}, a.data(), owner);
}

// The numpy shape of a field: (rows,) when the table gives one column, else (rows, cols); one row
// (energy) is a flat array of its columns. MuJoCo's Python bindings use the same shapes.
std::vector<py::ssize_t> field_shape(const lever::FieldView& v) {
  std::vector<py::ssize_t> shape;
  if (v.info->rows != lever::Size::kOne) shape.push_back(v.rows);
  if (v.cols != 1 || v.info->rows == lever::Size::kOne) shape.push_back(v.cols);
  return shape;
}

py::dtype field_dtype(const lever::FieldInfo& info) {
  switch (info.scalar) {
    case lever::Scalar::kDouble: return py::dtype::of<double>();
    case lever::Scalar::kInt: return py::dtype::of<int32_t>();
    case lever::Scalar::kByte: return py::dtype::of<uint8_t>();
  }
  return py::dtype::of<double>();
}

// A numpy view of one field; `owner` keeps the memory alive.
py::array view(const lever::FieldView& v, py::handle owner, bool writable) {
  const py::dtype dtype = field_dtype(*v.info);
  const auto item = static_cast<py::ssize_t>(dtype.itemsize());
  const std::vector<py::ssize_t> shape = field_shape(v);
  std::vector<py::ssize_t> strides(shape.size(), item);  // row-major
  if (shape.size() == 2) strides[0] = item * v.cols;
  py::array a(dtype, shape, strides, v.data, owner);
  if (!writable) {
    py::detail::array_proxy(a.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  }
  return a;
}

lever::Model& model_of(const ModelPtr& m) {
  if (!m) throw lever::StateError("the model is None.");
  return *m;
}

// The pairing check Python adds on top of the C++ one: a Data is used with the model it was
// built from (the C++ check compares sizes only).
lever::Data& data_for(const ModelPtr& model, const DataPtr& data) {
  if (!data) throw lever::StateError("the data is None.");
  if (data->model != model) {
    throw lever::StateError(
        "this Data was made from another Model: make it with lever.Data(model) from the model "
        "you pass with it.");
  }
  return data->data;
}

// ---- contacts ----------------------------------------------------------------------------------
// data.contact is an array of structs (lever::Contact, MuJoCo's mjContact); each member is shown
// as a strided numpy view over the first ncon contacts, so that it is live as the other arrays.
using lever_python::contact_members;
using lever_python::ContactMember;
using lever_python::is_int;

py::array contact_view(lever::Data& data, const ContactMember& m, py::handle owner) {
  const auto stride = static_cast<py::ssize_t>(sizeof(lever::Contact));
  const auto item = static_cast<py::ssize_t>(is_int(m) ? sizeof(int32_t) : sizeof(double));
  std::vector<py::ssize_t> shape{data.ncon}, strides{stride};
  if (m.count > 1) {
    shape.push_back(m.count);
    strides.push_back(item);
  }
  char* base = reinterpret_cast<char*>(data.contact.data()) + m.offset;
  const py::dtype dtype = is_int(m) ? py::dtype::of<int32_t>() : py::dtype::of<double>();
  return py::array(dtype, shape, strides, base, owner);
}

// ---- batches (lever/batch.hpp) ------------------------------------------------------------------
// A C-contiguous (n, nq) float64 array holds state k's nq numbers contiguously in row k: that is
// exactly the nq x n column-major matrix BatchRunner takes (state k its column k), so the array
// is mapped, not copied.

// lever::BatchRunner with the model it runs, kept alive, and a lock: the GIL is released while a
// batch runs, and a second Python thread calling the same runner waits for the first batch
// instead of sharing its Data.
struct PyBatchRunner {
  ModelPtr model;
  lever::BatchRunner runner;
  std::mutex busy;
  PyBatchRunner(ModelPtr m, int threads) : model(std::move(m)), runner(*model, threads) {}
};

using StateRows = py::array_t<double, py::array::c_style>;
using ConstStates = Eigen::Map<const Eigen::MatrixXd>;

std::string shape_text(const py::array& a) {
  std::string text = "(";
  for (py::ssize_t i = 0; i < a.ndim(); ++i) {
    text += (i ? ", " : "") + std::to_string(a.shape(i));
  }
  return text + (a.ndim() == 1 ? ",)" : ")");
}

// `what` as n states of `count` numbers, one per row: the array itself when it is a C-contiguous
// float64 array, else a C-contiguous float64 copy (np.ascontiguousarray). `n` is -1 for the first
// argument, which sets it.
StateRows state_rows(const py::handle& values, const char* where, const char* what,
                     const char* count_name, int count, py::ssize_t n) {
  StateRows rows = StateRows::ensure(values);
  if (!rows) {
    PyErr_Clear();
    throw lever::StateError(std::string(where) + ": " + what +
                            " is not an array of numbers (float64).");
  }
  if (rows.ndim() != 2 || rows.shape(1) != count || (n >= 0 && rows.shape(0) != n)) {
    throw lever::StateError(std::string(where) + ": " + what + " has shape " + shape_text(rows) +
                            "; it needs (n, " + count_name + ") = (" +
                            (n < 0 ? std::string("n") : std::to_string(n)) + ", " +
                            std::to_string(count) + "): one state per row.");
  }
  return rows;
}

ConstStates as_columns(const StateRows& rows) {
  return ConstStates(rows.data(), rows.shape(1), rows.shape(0));
}

// The states of one call: qpos (n, nq), qvel (n, nv), ctrl (n, nu) or None, checked.
struct BatchStates {
  StateRows qpos, qvel, ctrl;
  bool zero_controls;  // ctrl was None
  py::ssize_t n;

  BatchStates(const lever::Model& model, const py::object& q, const py::object& v,
              const py::object& u, const char* where)
      : qpos(state_rows(q, where, "qpos", "nq", model.nq, -1)),
        qvel(state_rows(v, where, "qvel", "nv", model.nv, qpos.shape(0))),
        zero_controls(u.is_none()),
        n(qpos.shape(0)) {
    if (!zero_controls) ctrl = state_rows(u, where, "ctrl", "nu", model.nu, n);
  }
  // no columns when ctrl was None: BatchRunner's "every control zero"
  ConstStates ctrl_columns(int nu) const {
    return zero_controls ? ConstStates(nullptr, nu, 0) : as_columns(ctrl);
  }
};

// One requested Data field of a batch: the output array, (n,) + the field's shape, whose row k
// receives state k's numbers, and where those numbers are in each thread's Data.
struct BatchField {
  std::string name;
  py::array out;
  char* rows = nullptr;             // out's numbers: row k at rows + k * bytes
  std::size_t bytes = 0;            // one state's
  std::vector<const char*> source;  // source[t]: the field in runner.data(t)
};

// The field `name` with its output array, refused (naming it) unless forward() computes it and
// its size is the model's alone. Its sources are located later, under the runner's lock.
BatchField batch_field(const lever::Model& model, const std::string& name, py::ssize_t n) {
  const char* where = "lever.BatchRunner.forward";
  const lever::FieldInfo* info = nullptr;
  for (const lever::FieldInfo& f : lever::data_field_table()) {
    if (name == f.name) info = &f;
  }
  if (info == nullptr) {
    if (name.rfind("contact", 0) == 0 || name.rfind("efc_", 0) == 0 || name == "ncon" ||
        name == "nefc") {
      throw lever::StateError(std::string(where) + ": field '" + name +
                              "' is sized by the state's contacts or constraint rows, which "
                              "vary from state to state: run lever.forward on a Data for it.");
    }
    throw lever::StateError(std::string(where) + ": Data has no field '" + name +
                            "' (lever.data_field_table() lists them).");
  }
  if (info->rows == lever::Size::kNefc) {
    throw lever::StateError(std::string(where) + ": field '" + name +
                            "' has one row per live constraint row (nefc), which varies from "
                            "state to state: run lever.forward on a Data for it.");
  }
  if (info->stage == lever::Stage::kInverse || info->stage == lever::Stage::kEnergy ||
      info->stage == lever::Stage::kStep) {
    const char* writer = info->stage == lever::Stage::kInverse  ? "lever.inverse"
                         : info->stage == lever::Stage::kEnergy ? "lever.compute_energy"
                                                                : "lever.step with fwdinv";
    throw lever::StateError(std::string(where) + ": field '" + name +
                            "' is not computed by forward() (" + writer + " writes it).");
  }
  lever::FieldView one_state;  // the field's shape in any Data of this model
  one_state.info = info;
  one_state.rows = lever::size_of(model, info->rows);
  one_state.cols = info->cols < 0 ? model.nv : info->cols;  // -1: nv columns
  std::vector<py::ssize_t> shape = field_shape(one_state);
  shape.insert(shape.begin(), n);
  BatchField field;
  field.name = name;
  field.out = py::array(field_dtype(*info), shape);
  field.rows = static_cast<char*>(field.out.mutable_data());
  field.bytes =
      static_cast<std::size_t>(one_state.size()) * static_cast<std::size_t>(field.out.itemsize());
  return field;
}

// Python exception classes, made once in the module
py::object g_parse_error, g_model_error, g_state_error, g_error;

}  // namespace

PYBIND11_MODULE(_lever, m) {
  m.doc() = "lever: rigid-body dynamics for robot arms, proven against MuJoCo 2.2.2";
  m.attr("__version__") = lever::version_string();

  // ---- exceptions ------------------------------------------------------------------------------
  g_error = py::reinterpret_borrow<py::object>(
      py::exception<lever::Error>(m, "Error", PyExc_RuntimeError));
  g_model_error = py::reinterpret_borrow<py::object>(
      py::exception<lever::ModelError>(m, "ModelError", PyExc_ValueError));
  g_state_error = py::reinterpret_borrow<py::object>(
      py::exception<lever::StateError>(m, "StateError", PyExc_ValueError));
  g_parse_error = py::reinterpret_borrow<py::object>(
      py::exception<lever::mjcf::ParseError>(m, "ParseError", PyExc_ValueError));
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const lever::mjcf::ParseError& e) {
      py::object err = g_parse_error(e.what());
      err.attr("file") = e.file();
      err.attr("line") = e.line();
      err.attr("element") = e.element();
      err.attr("attribute") = e.attribute();
      err.attr("problem") = e.problem();
      PyErr_SetObject(g_parse_error.ptr(), err.ptr());
    } catch (const lever::ModelError& e) {
      PyErr_SetString(g_model_error.ptr(), e.what());
    } catch (const lever::StateError& e) {
      PyErr_SetString(g_state_error.ptr(), e.what());
    } catch (const lever::Error& e) {
      PyErr_SetString(g_error.ptr(), e.what());
    }
  });

  // ---- the field table -------------------------------------------------------------------------
  auto table = [](const std::vector<lever::FieldInfo>& rows, bool data) {
    py::list out;
    for (const lever::FieldInfo& f : rows) {
      py::dict d;
      d["name"] = f.name;
      d["dtype"] = lever::scalar_name(f.scalar);
      d["rows"] = lever::size_name(f.rows);
      d["cols"] = f.cols < 0 ? py::object(py::str(lever::size_name(f.cols_size))) : py::int_(f.cols);
      if (data) d["stage"] = lever::stage_name(f.stage);
      d["mujoco"] = f.in_mujoco;
      out.append(d);
    }
    return out;
  };
  m.def(
      "model_field_table", [table] { return table(lever::model_field_table(), false); },
      "Every array of Model: name, dtype, rows, cols, and whether MuJoCo has it.");
  m.def(
      "data_field_table", [table] { return table(lever::data_field_table(), true); },
      "Every array of Data: name, dtype, rows, cols, stage, and whether MuJoCo has it.");

  // ---- Model -----------------------------------------------------------------------------------
  py::class_<lever::Model, ModelPtr> model_class(m, "Model", "A compiled model (lever::Model).");
  model_class.def_property_readonly("name", [](const lever::Model& x) { return x.name; })
      .def_property_readonly("source", [](const lever::Model& x) { return x.source; })
      .def_property_readonly("nq", [](const lever::Model& x) { return x.nq; })
      .def_property_readonly("nv", [](const lever::Model& x) { return x.nv; })
      .def_property_readonly("nu", [](const lever::Model& x) { return x.nu; })
      .def_property_readonly("nbody", [](const lever::Model& x) { return x.nbody; })
      .def_property_readonly("njnt", [](const lever::Model& x) { return x.njnt; })
      .def_property_readonly("ngeom", [](const lever::Model& x) { return x.ngeom; })
      .def_property_readonly("nsite", [](const lever::Model& x) { return x.nsite; })
      .def_property_readonly("npair", [](const lever::Model& x) { return x.npair; })
      .def_property_readonly("nexclude", [](const lever::Model& x) { return x.nexclude; })
      .def_property_readonly("nsensor", [](const lever::Model& x) { return x.nsensor; })
      .def_property_readonly("nsensordata", [](const lever::Model& x) { return x.nsensordata; })
      .def_property_readonly("neq", [](const lever::Model& x) { return x.neq; })
      .def_property_readonly("nmocap", [](const lever::Model& x) { return x.nmocap; })
      .def_property_readonly("na", [](const lever::Model& x) { return x.na; })
      .def_property_readonly("ntendon", [](const lever::Model& x) { return x.ntendon; })
      .def_property_readonly("nwrap", [](const lever::Model& x) { return x.nwrap; })
      .def_property_readonly("nuser_body", [](const lever::Model& x) { return x.nuser_body; })
      .def_property_readonly("nuser_jnt", [](const lever::Model& x) { return x.nuser_jnt; })
      .def_property_readonly("nuser_geom", [](const lever::Model& x) { return x.nuser_geom; })
      .def_property_readonly("nuser_site", [](const lever::Model& x) { return x.nuser_site; })
      .def_property_readonly("nuser_tendon", [](const lever::Model& x) { return x.nuser_tendon; })
      .def_property_readonly("nuser_actuator", [](const lever::Model& x) { return x.nuser_actuator; })
      .def_property_readonly("nuser_sensor", [](const lever::Model& x) { return x.nuser_sensor; })
      .def_property_readonly("nmesh", [](const lever::Model& x) { return x.nmesh; })
      .def_property_readonly("nmeshvert", [](const lever::Model& x) { return x.nmeshvert; })
      .def_property_readonly("nmeshgraph", [](const lever::Model& x) { return x.nmeshgraph; })
      .def_property_readonly("nmeshface", [](const lever::Model& x) { return x.nmeshface; })
      .def_property_readonly("nconmax", [](const lever::Model& x) { return x.nconmax; })
      .def_property_readonly("njmax", [](const lever::Model& x) { return x.njmax; })
      .def_property(
          "timestep", [](const lever::Model& x) { return x.opt.timestep; },
          [](lever::Model& x, double h) { x.opt.timestep = h; })
      .def_property(
          "gravity",
          [](py::object self) {
            auto& x = self.cast<lever::Model&>();
            return py::array_t<double>({3}, {sizeof(double)}, x.opt.gravity.data(), self);
          },
          nullptr)
      // <option><flag>: MuJoCo's mjtDisableBit and mjtEnableBit bits, and the contact override
      .def_property(
          "disableflags", [](const lever::Model& x) { return x.opt.disableflags; },
          [](lever::Model& x, int bits) { x.opt.disableflags = bits; })
      .def_property(
          "enableflags", [](const lever::Model& x) { return x.opt.enableflags; },
          [](lever::Model& x, int bits) { x.opt.enableflags = bits; })
      .def_property(
          "o_margin", [](const lever::Model& x) { return x.opt.o_margin; },
          [](lever::Model& x, double margin) { x.opt.o_margin = margin; })
      .def_property_readonly("o_solref",
                             [](py::object self) {
                               auto& x = self.cast<lever::Model&>();
                               return py::array_t<double>({2}, {sizeof(double)},
                                                          x.opt.o_solref.data(), self);
                             })
      .def_property_readonly("o_solimp",
                             [](py::object self) {
                               auto& x = self.cast<lever::Model&>();
                               return py::array_t<double>({5}, {sizeof(double)},
                                                          x.opt.o_solimp.data(), self);
                             })
      .def(
          "set_sensor_callback",
          [](const ModelPtr& x, py::object fn) {
            if (fn.is_none()) {
              x->sensor_callback = nullptr;
            } else {
              x->sensor_callback = python_sensor_callback(std::move(fn), x);
            }
          },
          py::arg("callback"),
          "fn(model, data, stage) writes the user sensors' numbers into data.sensordata after "
          "each stage (1 position, 2 velocity, 3 acceleration) that has user sensors (MuJoCo's "
          "mjcb_sensor); None removes it, and the user sensors then stay as they are.")
      .def(
          "set_actuator_callbacks",
          [](const ModelPtr& x, py::object gain, py::object bias, py::object dyn) {
            const auto wrap = [&x](py::object fn) {
              return fn.is_none() ? lever::ActuatorCallback{}
                                  : python_actuator_callback(std::move(fn), x);
            };
            x->actuator_gain_callback = wrap(std::move(gain));
            x->actuator_bias_callback = wrap(std::move(bias));
            x->actuator_dyn_callback = wrap(std::move(dyn));
          },
          py::arg("gain") = py::none(), py::arg("bias") = py::none(), py::arg("dyn") = py::none(),
          "fn(model, data, id) -> float for the actuators whose gaintype, biastype or dyntype is "
          "user (MuJoCo's mjcb_act_gain, mjcb_act_bias, mjcb_act_dyn): the gain, the bias, "
          "act_dot; None (the default) leaves MuJoCo's values, gain 1, bias 0, act_dot 0.")
      .def_property(
          "integrator", [](const lever::Model& x) { return static_cast<int>(x.opt.integrator); },
          [](lever::Model& x, int i) {
            if (i != 0 && i != 1 && i != 2 && i != 3) {
              throw lever::StateError(
                  "integrator " + std::to_string(i) +
                  " is not one lever has (0 Euler, 1 RK4, 2 implicit, 3 implicitfast).");
            }
            x.opt.integrator = static_cast<lever::Integrator>(i);
          })
      // the constraint solver (mjtSolver's values) and CG's stopping rule
      .def_property(
          "solver", [](const lever::Model& x) { return static_cast<int>(x.opt.solver); },
          [](lever::Model& x, int s) {
            if (s < 0 || s > 2) {
              throw lever::StateError("solver " + std::to_string(s) +
                                      " is not one lever has (0 PGS, 1 CG, 2 Newton).");
            }
            x.opt.solver = static_cast<lever::Solver>(s);
          })
      .def_property(
          "iterations", [](const lever::Model& x) { return x.opt.iterations; },
          [](lever::Model& x, int n) {
            if (n < 0) throw lever::StateError("iterations must not be negative.");
            x.opt.iterations = n;
          })
      .def_property(
          "tolerance", [](const lever::Model& x) { return x.opt.tolerance; },
          [](lever::Model& x, double t) {
            if (!(t >= 0)) throw lever::StateError("tolerance must not be negative.");
            x.opt.tolerance = t;
          })
      .def_property_readonly("body_name", [](const lever::Model& x) { return x.body_name; })
      .def_property_readonly("jnt_name", [](const lever::Model& x) { return x.jnt_name; })
      .def_property_readonly("geom_name", [](const lever::Model& x) { return x.geom_name; })
      .def_property_readonly("site_name", [](const lever::Model& x) { return x.site_name; })
      .def_property_readonly("actuator_name", [](const lever::Model& x) { return x.actuator_name; })
      .def_property_readonly("sensor_name", [](const lever::Model& x) { return x.sensor_name; })
      .def_property_readonly("eq_name", [](const lever::Model& x) { return x.eq_name; })
      .def_property_readonly("tendon_name", [](const lever::Model& x) { return x.tendon_name; })
      // keyframes (not in the field table: their rows are keyframes): writable row-major views
      .def_property_readonly("nkey", [](const lever::Model& x) { return x.nkey; })
      .def_property_readonly("key_name", [](const lever::Model& x) { return x.key_name; })
      .def_property_readonly("key_time",
                             [](py::object self) {
                               auto& x = self.cast<lever::Model&>();
                               return py::array_t<double>({x.nkey}, {sizeof(double)},
                                                          x.key_time.data(), self);
                             })
      .def_property_readonly("key_qpos",
                             [](py::object self) {
                               auto& x = self.cast<lever::Model&>();
                               return key_view(x.key_qpos, self);
                             })
      .def_property_readonly("key_qvel",
                             [](py::object self) {
                               auto& x = self.cast<lever::Model&>();
                               return key_view(x.key_qvel, self);
                             })
      .def_property_readonly("key_ctrl",
                             [](py::object self) {
                               auto& x = self.cast<lever::Model&>();
                               return key_view(x.key_ctrl, self);
                             })
      .def_property_readonly("key_mpos",
                             [](py::object self) {
                               auto& x = self.cast<lever::Model&>();
                               return key_view(x.key_mpos, self);
                             })
      .def_property_readonly("key_mquat",
                             [](py::object self) {
                               auto& x = self.cast<lever::Model&>();
                               return key_view(x.key_mquat, self);
                             })
      .def(
          "field",
          [](py::object self, const std::string& name) {
            const auto& x = self.cast<const lever::Model&>();
            return view(lever::model_field(x, name), self, true);
          },
          py::arg("name"), "One array of the field table, as a writable numpy view.")
      .def("to_json", [](const lever::Model& x) { return lever::model_to_json(x); })
      // pickle: every array of the field table, the names, keyframes and options (state.hpp);
      // copies: the whole C++ object, derived arrays included
      .def(py::pickle([](const lever::Model& x) { return lever_python::model_state(x); },
                      [](const py::dict& state) { return lever_python::model_from_state(state); }))
      .def("__copy__", [](const lever::Model& x) { return std::make_shared<lever::Model>(x); })
      .def(
          "__deepcopy__",
          [](const lever::Model& x, const py::dict&) { return std::make_shared<lever::Model>(x); },
          py::arg("memo"))
      .def("__repr__", [](const lever::Model& x) {
        return "<lever.Model '" + x.name + "' nq=" + std::to_string(x.nq) +
               " nu=" + std::to_string(x.nu) + " nbody=" + std::to_string(x.nbody) + ">";
      });
  for (const lever::FieldInfo& f : lever::model_field_table()) {
    const std::string name = f.name;
    model_class.def_property_readonly(f.name, [name](py::object self) {
      const auto& x = self.cast<const lever::Model&>();
      return view(lever::model_field(x, name), self, true);
    });
  }

  m.def(
      "load",
      [](const std::string& path, bool infer_inertia_from_geoms) {
        return std::make_shared<lever::Model>(
            lever::mjcf::load_file(path, {.infer_inertia_from_geoms = infer_inertia_from_geoms}));
      },
      py::arg("path"), py::arg("infer_inertia_from_geoms") = false,
      "Load and compile an MJCF file (raises lever.ParseError with file and line).");
  m.def(
      "load_string",
      [](const std::string& xml, const std::string& filename, bool infer) {
        return std::make_shared<lever::Model>(
            lever::mjcf::load_string(xml, filename, {.infer_inertia_from_geoms = infer}));
      },
      py::arg("xml"), py::arg("filename") = "<string>", py::arg("infer_inertia_from_geoms") = false,
      "Load and compile MJCF text.");
  m.def(
      "set_const", [](const ModelPtr& x) { lever::set_const(model_of(x)); }, py::arg("model"),
      "Recompute the model's derived constants after editing a parameter (MuJoCo's mj_setConst).");
  m.def(
      "copy_model", [](const ModelPtr& x) { return std::make_shared<lever::Model>(model_of(x)); },
      py::arg("model"), "An independent copy of the model.");

  // ---- Data ------------------------------------------------------------------------------------
  py::class_<PyData, DataPtr> data_class(m, "Data",
                                         "The state, outputs and workspace (lever::Data).");
  data_class
      .def(py::init([](const ModelPtr& x) {
             model_of(x);
             return std::make_shared<PyData>(x);
           }),
           py::arg("model"))
      .def_property_readonly("model", [](const PyData& d) { return d.model; })
      .def_property(
          "time", [](const PyData& d) { return d.data.time; },
          [](PyData& d, double t) { d.data.time = t; })
      .def_property_readonly("nefc", [](const PyData& d) { return d.data.nefc; })
      .def_property_readonly("ne", [](const PyData& d) { return d.data.ne; })
      .def_property_readonly("nf", [](const PyData& d) { return d.data.nf; })
      // contacts: ncon, each member of data.contact as a view over the first ncon,
      // and efc_J's live rows (the field table has no (nefc, nv) shape)
      .def_property_readonly("ncon", [](const PyData& d) { return d.data.ncon; })
      .def_property_readonly("solver_iter", [](const PyData& d) { return d.data.solver_iter; })
      .def(
          "contact_field",
          [](py::object self, const std::string& name) {
            auto& d = self.cast<PyData&>();
            for (const ContactMember& member : contact_members()) {
              if (name == member.name) return contact_view(d.data, member, self);
            }
            throw lever::StateError("a contact has no member called '" + name + "'.");
          },
          py::arg("name"), "One member of data.contact for the first ncon contacts, as a view.")
      .def_property_readonly("efc_J",
                             [](py::object self) {
                               auto& d = self.cast<PyData&>();
                               const auto item = static_cast<py::ssize_t>(sizeof(double));
                               const auto nv = static_cast<py::ssize_t>(d.data.efc_J.cols());
                               return py::array_t<double>(
                                   {static_cast<py::ssize_t>(d.data.nefc), nv}, {item * nv, item},
                                   d.data.efc_J.data(), self);
                             })
      .def_property_readonly("warnings",
                             [](const PyData& d) { return lever::warning_text(d.data); })
      .def_property_readonly("warning_count",
                             [](const PyData& d) { return lever::warning_count(d.data); })
      .def(
          "field",
          [](py::object self, const std::string& name) {
            const auto& d = self.cast<const PyData&>();
            return view(lever::data_field(*d.model, d.data, name), self, true);
          },
          py::arg("name"))
      .def("to_json", [](const PyData& d) { return lever::data_to_json(*d.model, d.data); })
      // pickle: (the model, the state): pickled together, a Data and its Model stay paired
      .def(py::pickle(
          [](const PyData& d) {
            return py::make_tuple(d.model, lever_python::data_state(*d.model, d.data));
          },
          [](const py::tuple& t) {
            if (t.size() != 2) throw lever::StateError("lever: cannot unpickle a Data from this.");
            auto d = std::make_shared<PyData>(t[0].cast<ModelPtr>());
            lever_python::restore_data(*d->model, d->data, t[1].cast<py::dict>());
            return d;
          }))
      // copy.copy: the state copied, the model shared; copy.deepcopy: the model copied too, once
      // per deepcopy call (deepcopy((model, data)) gives a pair that belongs together)
      .def("__copy__", [](const PyData& d) { return std::make_shared<PyData>(d.model, d.data); })
      .def(
          "__deepcopy__",
          [](const PyData& d, const py::dict& memo) {
            const py::object model =
                py::module_::import("copy").attr("deepcopy")(py::cast(d.model), memo);
            return std::make_shared<PyData>(model.cast<ModelPtr>(), d.data);
          },
          py::arg("memo"))
      .def(
          "_adopt_model",
          [](PyData& d, const ModelPtr& x) {
            lever::check_fit(model_of(x), d.data, "lever.Data");
            if (d.data.contact.size() != static_cast<std::size_t>(x->nconmax)) {
              throw lever::StateError("lever.Data: this Data holds " +
                                      std::to_string(d.data.contact.size()) +
                                      " contacts; the model's nconmax is " +
                                      std::to_string(x->nconmax) + ".");
            }
            d.model = x;
          },
          py::arg("model"),
          "Pair this Data with another model of the same sizes (lever.mujoco: MuJoCo's "
          "functions use the model they are given).");
  for (const lever::FieldInfo& f : lever::data_field_table()) {
    const std::string name = f.name;
    data_class.def_property_readonly(f.name, [name](py::object self) {
      const auto& d = self.cast<const PyData&>();
      return view(lever::data_field(*d.model, d.data, name), self, true);
    });
  }

  // ---- the engine ------------------------------------------------------------------------------
  auto pipeline = [&m](const char* name, void (*fn)(const lever::Model&, lever::Data&),
                       const char* doc) {
    m.def(
        name,
        [fn](const ModelPtr& x, const DataPtr& d) {
          lever::Data& data = data_for(x, d);
          const Evaluating evaluating(d);
          fn(*x, data);
        },
        py::arg("model"), py::arg("data"), doc);
  };
  pipeline("forward", lever::forward, "Everything at the current state (mj_forward).");
  pipeline("step", lever::step, "One step of the model's integrator (mj_step).");
  pipeline("step_all", lever::step_all,
           "step() with every output forward() computes, xquat and the geom frames included, as "
           "mj_step leaves them.");
  pipeline("step1", lever::step1, "Position and velocity stages of a split step (mj_step1).");
  pipeline("step2", lever::step2, "Motors, accelerations, the limit solve and Euler (mj_step2).");
  pipeline("inverse", lever::inverse, "Inverse dynamics into qfrc_inverse (mj_inverse).");
  pipeline("kinematics", lever::kinematics, "Poses and com-frame quantities (mj_kinematics).");
  pipeline("body_kinematics", lever::body_kinematics,
           "kinematics() without the geom and site frames: what crba, bias and rnea read.");
  pipeline("crba", lever::crba, "M(q) into data.M, armature included (mj_crb).");
  pipeline("factor_mass", lever::factor_mass, "Factor M (mj_factorM).");
  pipeline("bias", lever::bias, "qfrc_bias (mj_rne with flg_acc = 0).");
  pipeline("passive", lever::passive, "qfrc_passive (mj_passive).");
  pipeline("transmission", lever::transmission, "actuator_length (mj_transmission).");
  pipeline("actuation", lever::actuation, "actuator_force and qfrc_actuator (mj_fwdActuation).");
  pipeline("compute_energy", lever::compute_energy, "data.energy: potential, kinetic.");
  pipeline("reset", lever::reset, "qpos = qpos0, the rest of the state zero (mj_resetData).");
  m.def(
      "rnea",
      [](const ModelPtr& x, const DataPtr& d, const Eigen::VectorXd& qacc) {
        lever::Data& data = data_for(x, d);
        Eigen::VectorXd tau(x->nv);
        lever::rnea(*x, data, qacc, tau);
        return tau;
      },
      py::arg("model"), py::arg("data"), py::arg("qacc"),
      "M(q) qacc + qfrc_bias by recursive Newton-Euler (armature included).");
  m.def(
      "solve_mass",
      [](const ModelPtr& x, const DataPtr& d, Eigen::VectorXd v) {
        lever::solve_mass(*x, data_for(x, d), v);
        return v;
      },
      py::arg("model"), py::arg("data"), py::arg("vec"), "M^-1 vec with the current factor.");
  m.def(
      "contact_members",
      [] {
        py::list names;
        for (const ContactMember& member : contact_members()) names.append(member.name);
        return names;
      },
      "The members of a contact Data.contact_field shows (MuJoCo's mjContact names).");
  m.def(
      "contact_force",
      [](const ModelPtr& x, const DataPtr& d, int id) {
        const Eigen::Matrix<double, 6, 1> f = lever::contact_force(*x, data_for(x, d), id);
        return Eigen::VectorXd(f);
      },
      py::arg("model"), py::arg("data"), py::arg("id"),
      "Contact id's force in its frame: normal, two tangents, torsion, two rolls (entries past "
      "dim zero), as mj_contactForce; raises lever.StateError for an id outside [0, ncon).");
  m.def(
      "jac_site",
      [](const ModelPtr& x, const DataPtr& d, int site) {
        Eigen::MatrixXd jacp(3, x->nv), jacr(3, x->nv);
        lever::jac_site(*x, data_for(x, d), site, jacp, jacr);
        return py::make_tuple(jacp, jacr);
      },
      py::arg("model"), py::arg("data"), py::arg("site"), "(jacp, jacr), each 3 x nv.");
  m.def(
      "jac_site_from_q",
      [](const ModelPtr& x, const DataPtr& d, int site) {
        Eigen::MatrixXd jacp(3, x->nv), jacr(3, x->nv);
        lever::jac_site_from_q(*x, data_for(x, d), site, jacp, jacr);
        return py::make_tuple(jacp, jacr);
      },
      py::arg("model"), py::arg("data"), py::arg("site"),
      "(jacp, jacr), each 3 x nv, from data.qpos: jac_site() without the rest of kinematics() "
      "(the site's tree and the site placed), bit for bit kinematics() then jac_site().");
  m.def(
      "jac_point",
      [](const ModelPtr& x, const DataPtr& d, int body, const Eigen::Vector3d& point) {
        Eigen::MatrixXd jacp(3, x->nv), jacr(3, x->nv);
        lever::jac_point(*x, data_for(x, d), body, point, jacp, jacr);
        return py::make_tuple(jacp, jacr);
      },
      py::arg("model"), py::arg("data"), py::arg("body"), py::arg("point"),
      "(jacp, jacr) of a world point fixed to a body.");

  m.def(
      "integrate_pos",
      [](const ModelPtr& x, Eigen::VectorXd qpos, const Eigen::VectorXd& qvel, double h) {
        lever::integrate_pos(model_of(x), qpos, qvel, h);
        return qpos;
      },
      py::arg("model"), py::arg("qpos"), py::arg("qvel"), py::arg("h"),
      "qpos advanced by qvel for time h (quaternions turned about body axes and normalized), "
      "as mj_integratePos; returns a new array.");
  m.def(
      "differentiate_pos",
      [](const ModelPtr& x, double h, const Eigen::VectorXd& qpos1, const Eigen::VectorXd& qpos2) {
        Eigen::VectorXd qvel(model_of(x).nv);
        lever::differentiate_pos(model_of(x), qvel, h, qpos1, qpos2);
        return qvel;
      },
      py::arg("model"), py::arg("h"), py::arg("qpos1"), py::arg("qpos2"),
      "The velocity (nv) taking qpos1 to qpos2 in time h, as mj_differentiatePos.");

  // ---- batches (lever/batch.hpp) ----------------------------------------------------------------
  py::class_<PyBatchRunner, std::shared_ptr<PyBatchRunner>>(
      m, "BatchRunner",
      "forward() or step() over many states on several threads, one Data per thread "
      "(lever::BatchRunner). States are rows: qpos (n, nq), qvel (n, nv), ctrl (n, nu).")
      .def(py::init([](const ModelPtr& x, int threads) {
             model_of(x);
             return std::make_shared<PyBatchRunner>(x, threads);
           }),
           py::arg("model"), py::arg("threads") = 1,
           "One Data per thread and threads - 1 worker threads, kept until the runner goes (keep "
           "it and give each call many states); the runner keeps the model alive. Edit the model "
           "between batches only. Raises lever.StateError if threads < 1.")
      .def_property_readonly("threads",
                             [](const PyBatchRunner& self) { return self.runner.threads(); })
      .def_property_readonly("model", [](const PyBatchRunner& self) { return self.model; })
      .def(
          "forward",
          [](PyBatchRunner& self, const py::object& qpos, const py::object& qvel,
             const py::object& ctrl, const py::object& fields) {
            const lever::Model& model = *self.model;
            const BatchStates states(model, qpos, qvel, ctrl, "lever.BatchRunner.forward");
            // a str is one name, not a sequence of one-letter names
            const py::list names = py::isinstance<py::str>(fields)
                                       ? py::list(py::make_tuple(fields))
                                       : py::list(fields);
            std::vector<BatchField> outputs;
            for (const py::handle& name : names) {
              const std::string text = py::str(name);
              const auto same = [&text](const BatchField& f) { return f.name == text; };
              if (std::none_of(outputs.begin(), outputs.end(), same)) {
                outputs.push_back(batch_field(model, text, states.n));
              }
            }
            {
              py::gil_scoped_release release;
              std::lock_guard<std::mutex> lock(self.busy);
              // each field located once per thread's Data, not per state
              for (BatchField& f : outputs) {
                for (int t = 0; t < self.runner.threads(); ++t) {
                  const lever::FieldView v = lever::data_field(model, self.runner.data(t), f.name);
                  f.source.push_back(static_cast<const char*>(v.data));
                }
              }
              // runs on every thread, concurrently for different states: raw buffers only
              const auto collect = [&outputs](const lever::Data&, Eigen::Index k, int t) {
                for (const BatchField& f : outputs) {
                  std::memcpy(f.rows + static_cast<std::size_t>(k) * f.bytes,
                              f.source[static_cast<std::size_t>(t)], f.bytes);
                }
              };
              self.runner.forward_each(as_columns(states.qpos), as_columns(states.qvel),
                                       states.ctrl_columns(model.nu), collect);
            }
            py::dict out;
            for (const BatchField& f : outputs) out[py::str(f.name)] = f.out;
            return out;
          },
          py::arg("qpos"), py::arg("qvel"), py::arg("ctrl") = py::none(),
          py::arg("fields") = py::make_tuple("qacc"),
          "forward() at every state (row k of qpos (n, nq), qvel (n, nv), ctrl (n, nu); ctrl None: "
          "zero controls). Returns a dict: each name of `fields` (Data fields whose size is the "
          "model's: qacc, qfrc_bias, M, site_xpos, ...) -> an array (n,) + that field's shape, "
          "row k state k's. C-contiguous float64 inputs are read in place, others copied once; "
          "none is modified. The GIL is released while the states run.")
      .def(
          "step",
          [](PyBatchRunner& self, const py::object& qpos, const py::object& qvel,
             const py::object& ctrl, int nstep) {
            const lever::Model& model = *self.model;
            const BatchStates states(model, qpos, qvel, ctrl, "lever.BatchRunner.step");
            // the new states, stepped in place in fresh arrays: the inputs are left as they were
            StateRows new_qpos({states.n, static_cast<py::ssize_t>(model.nq)});
            StateRows new_qvel({states.n, static_cast<py::ssize_t>(model.nv)});
            std::copy_n(states.qpos.data(), states.qpos.size(), new_qpos.mutable_data());
            std::copy_n(states.qvel.data(), states.qvel.size(), new_qvel.mutable_data());
            Eigen::Map<Eigen::MatrixXd> qpos_columns(new_qpos.mutable_data(), model.nq, states.n);
            Eigen::Map<Eigen::MatrixXd> qvel_columns(new_qvel.mutable_data(), model.nv, states.n);
            {
              py::gil_scoped_release release;
              std::lock_guard<std::mutex> lock(self.busy);
              self.runner.step(qpos_columns, qvel_columns, states.ctrl_columns(model.nu), nstep);
            }
            return py::make_tuple(new_qpos, new_qvel);
          },
          py::arg("qpos"), py::arg("qvel"), py::arg("ctrl") = py::none(), py::arg("nstep") = 1,
          "Every state (rows, as forward's) advanced by nstep steps of the model's integrator, "
          "controls held: returns (qpos, qvel), new arrays; the inputs are not modified. A state "
          "step() resets (NaN or huge values) comes back reset. The GIL is released while the "
          "states run.")
      .def("__repr__", [](const PyBatchRunner& self) {
        return "<lever.BatchRunner '" + self.model->name +
               "' threads=" + std::to_string(self.runner.threads()) + ">";
      });

  // ---- derivatives and the regressor (docs/derivatives.md)
  // ----------------------------------------
  m.def(
      "step_derivatives",
      [](const ModelPtr& x, const DataPtr& d) {
        lever::Data& data = data_for(x, d);
        lever::Derivatives deriv(*x);
        lever::step_derivatives(*x, data, deriv);
        return py::make_tuple(deriv.A, deriv.B);
      },
      py::arg("model"), py::arg("data"),
      "(A, B): the step's transition Jacobians at data's state, in mjd_transitionFD's layout "
      "(x = [qpos; qvel]); data's state is left as it was.");
  m.def(
      "derivatives",
      [](const ModelPtr& x, const DataPtr& d) {
        lever::Data& data = data_for(x, d);
        lever::Derivatives deriv(*x);
        lever::step_derivatives(*x, data, deriv);
        py::dict out;
        out["A"] = deriv.A;
        out["B"] = deriv.B;
        out["active_set_changes"] = deriv.active_set_changes;
        // Euler and implicit leave forward_derivatives() of the state itself; RK4 its last stage's
        if (x->opt.integrator == lever::Integrator::kRK4) {
          const Eigen::VectorXd qpos = data.qpos;  // forward() normalizes its quaternions
          lever::forward_derivatives(*x, data, deriv);
          data.qpos = qpos;
        }
        lever::applied_force_derivatives(*x, data, deriv);
        out["dqacc_dq"] = deriv.dqacc_dq;
        out["dqacc_dv"] = deriv.dqacc_dv;
        out["dqacc_du"] = deriv.dqacc_du;
        out["dqacc_dact"] = deriv.dqacc_dact;
        out["dqacc_dapplied"] = deriv.dqacc_dapplied;
        out["nefc"] = data.nefc;
        return out;
      },
      py::arg("model"), py::arg("data"),
      "step_derivatives(), forward_derivatives() and applied_force_derivatives() at data's state "
      "(lever.derivatives documents the keys).");
  m.def(
      "forward_derivatives",
      [](const ModelPtr& x, const DataPtr& d) {
        lever::Data& data = data_for(x, d);
        lever::Derivatives deriv(*x);
        lever::forward_derivatives(*x, data, deriv);
        py::dict out;
        out["dqacc_dq"] = deriv.dqacc_dq;
        out["dqacc_dv"] = deriv.dqacc_dv;
        out["dqacc_du"] = deriv.dqacc_du;
        out["dtau_dq"] = deriv.dtau_dq;
        out["dtau_dv"] = deriv.dtau_dv;
        return out;
      },
      py::arg("model"), py::arg("data"),
      "forward() at data's state, then d qacc / d (qpos, qvel, ctrl) and d rnea / d (qpos, qvel).");
  m.def(
      "regressor",
      [](const ModelPtr& x, const DataPtr& d, const Eigen::VectorXd& qacc) {
        lever::Data& data = data_for(x, d);
        lever::check_fit(*x, data, "lever.regressor");
        if (qacc.size() != x->nv) throw lever::StateError("lever.regressor: qacc needs nv values.");
        Eigen::MatrixXd Y(x->nv, lever::regressor_columns(*x));
        lever::kinematics(*x, data);
        lever::regressor(*x, data, qacc, Y);
        return Y;
      },
      py::arg("model"), py::arg("data"), py::arg("qacc"),
      "Y (nv x columns) at data's qpos, qvel and ctrl: Y pi = rnea(qacc) + damping qvel - the "
      "actuators' torque through their gain columns (gear gain basis; see docs/derivatives.md).");
  m.def(
      "regressor_names", [](const ModelPtr& x) { return lever::regressor_names(model_of(x)); },
      py::arg("model"), "What each column of the regressor (each entry of pi) is.");
  m.def(
      "model_parameters", [](const ModelPtr& x) { return lever::model_parameters(model_of(x)); },
      py::arg("model"), "The model's own parameter vector pi.");

  // ---- identification (docs/derivatives.md) ---------------------------------------------------
  m.def(
      "identify",
      [](const ModelPtr& x, const py::object& trajectory, const std::string& gains,
         const std::vector<std::string>& known_masses, const std::string& write_to) {
        const lever::Model& prior = model_of(x);
        namespace id = lever::identify;
        id::Trajectory t;
        if (py::isinstance<py::str>(trajectory)) {
          t = id::read_csv(prior, trajectory.cast<std::string>());
        } else {
          // arrays of N rows, as a log holds them: one row per sample
          const py::dict d = trajectory.cast<py::dict>();
          const auto rows = [&](const char* key, Eigen::Index cols, bool required) {
            if (!d.contains(key)) {
              if (required) {
                throw lever::Error(std::string("lever.identify: the trajectory has no '") + key +
                                   "'.");
              }
              return Eigen::MatrixXd();
            }
            Eigen::MatrixXd a = d[key].cast<Eigen::MatrixXd>();
            if (a.cols() == 1 && cols > 1 && a.rows() == cols) a.transposeInPlace();  // one row
            if (a.cols() != cols) {
              throw lever::Error(std::string("lever.identify: '") + key + "' needs " +
                                 std::to_string(cols) + " columns.");
            }
            return Eigen::MatrixXd(a.transpose());
          };
          const Eigen::MatrixXd time = rows("time", 1, true);
          t.time = time.row(0).transpose();
          t.qpos = rows("qpos", prior.nq, true);
          t.qvel = rows("qvel", prior.nv, true);
          t.qacc = rows("qacc", prior.nv, true);
          t.ctrl = rows("ctrl", prior.nu, false);
          t.actuator_force = rows("actuator_force", prior.nu, false);
          const bool joint_force = d.contains("qfrc");
          if (joint_force) {
            t.force = rows("qfrc", prior.nv, true);
          } else if (t.actuator_force.size() > 0) {
            lever::require_simple_actuators(prior, "lever.identify");
            t.force = Eigen::MatrixXd::Zero(prior.nv, t.actuator_force.cols());
            for (int a = 0; a < prior.nu; ++a) {
              const int dof = lever::actuator_scalar_dof(prior, a);  // checked above
              t.force.row(dof) += prior.actuator_gear[a][0] * t.actuator_force.row(a);
            }
            const Eigen::MatrixXd stops = rows("qfrc_constraint", prior.nv, false);
            if (stops.size() > 0) t.force += stops;
          } else {
            throw lever::Error(
                "lever.identify: the trajectory needs 'qfrc' (the joint force of motors and "
                "stops) or 'actuator_force'.");
          }
          // without them, estimating a gain is refused by identify() with the reason
          if (t.ctrl.size() == 0) t.ctrl.resize(0, t.time.size());
          if (t.actuator_force.size() == 0) t.actuator_force.resize(0, t.time.size());
          t.qacc_source = "the trajectory's qacc";
          t.force_source = joint_force ? "the trajectory's qfrc" : "actuator_force times gear";
        }
        id::Options options;
        if (!gains.empty()) options.gains = id::gain_actuators_named(prior, gains);
        for (const std::string& k : known_masses) {
          options.known_masses.push_back(id::known_mass_named(prior, k));
        }
        const id::Result r = id::identify(prior, t, options);
        py::dict out;
        out["names"] = r.base.names;
        out["prior"] = r.prior;
        out["estimate"] = r.estimate;
        out["standard_error"] = r.standard_error;
        out["physical_estimate"] = r.physical_estimate;
        out["estimate_physical"] = r.estimate_physical;
        out["residual_rms"] = r.residual_rms;
        out["physical_residual_rms"] = r.physical_residual_rms;
        out["samples"] = r.samples;
        out["equations"] = r.equations;
        out["dropped"] = r.dropped;
        out["unexcited"] = r.unexcited;
        out["parameters"] = r.parameters;
        py::dict distance;
        for (int b = 1; b < prior.nbody; ++b) {
          const std::string name = prior.body_name[b].empty()
                                       ? std::string("#").append(std::to_string(b))
                                       : prior.body_name[b];
          distance[py::str(name)] = r.distance_to_prior[static_cast<std::size_t>(b)];
        }
        out["distance_to_prior"] = distance;
        out["not_physical"] =
            r.not_physical.empty() ? py::object(py::none()) : py::object(py::str(r.not_physical));
        out["model"] = py::none();
        out["written"] = py::none();
        if (r.not_physical.empty()) {
          auto identified = std::make_shared<lever::Model>(id::identified_model(prior, r));
          if (!write_to.empty()) {
            if (prior.source.empty()) {
              throw lever::Error(
                  "lever.identify: writing a model needs a prior loaded from a file.");
            }
            id::write_model(prior.source, *identified, write_to);
            out["written"] = write_to;
          }
          out["model"] = ModelPtr(identified);
        }
        return out;
      },
      py::arg("prior"), py::arg("trajectory"), py::arg("gains"), py::arg("known_masses"),
      py::arg("write_model"), "lever.identify's C++ side (see lever/__init__.py).");

  // ---- the checks and the lab ------------------------------------------------------------------
  m.def(
      "check_json",
      [](const ModelPtr& x, const std::string& key) {
        const lever::check::Report r = lever::check::check_model(model_of(x), key);
        return lever::check::to_json(r);
      },
      py::arg("model"), py::arg("key") = "",
      "Lesson 5.1's six checks, lesson 5.2's two (singular poses, stability of the step) and "
      "lesson 5.3's contacts "
      "of a model, as the JSON `lever check` prints; `key`: sections 7 and 8 at that keyframe "
      "only.");
  m.def(
      "check_text",
      [](const ModelPtr& x, const std::string& key) {
        return lever::check::to_text(lever::check::check_model(model_of(x), key));
      },
      py::arg("model"), py::arg("key") = "", "The same checks as the text `lever check` prints.");
  m.def(
      "reset_keyframe",
      [](const ModelPtr& x, const DataPtr& d, const py::object& key) {
        lever::Data& data = data_for(x, d);
        if (py::isinstance<py::str>(key)) {
          lever::reset_keyframe(*x, data, key.cast<std::string>());
        } else {
          lever::reset_keyframe(*x, data, key.cast<int>());
        }
      },
      py::arg("model"), py::arg("data"), py::arg("key"),
      "Reset to a keyframe, by index or name (mj_resetDataKeyframe); an unknown one raises "
      "lever.StateError listing the keyframes.");
  m.def(
      "lab_run",
      [](const ModelPtr& x, const DataPtr& d, const Eigen::VectorXd& torque,
         bool gravity_compensation, long steps, const py::object& on_row) {
        lever::Data& data = data_for(x, d);
        lever::lab::Controller c{torque, gravity_compensation};
        lever::lab::RowCallback callback;
        if (!on_row.is_none()) {
          callback = [&on_row, &d](long row, const lever::Data&) { on_row(row, d); };
        }
        const lever::lab::RunLog log = lever::lab::run(*x, data, c, steps, callback);
        py::dict out;
        out["clamped"] = log.clamped;
        out["warnings"] = log.warnings.lines();
        out["non_finite_rows"] = log.non_finite_rows;
        return out;
      },
      py::arg("model"), py::arg("data"), py::arg("torque"), py::arg("gravity_compensation"),
      py::arg("steps"), py::arg("on_row") = py::none(),
      "Lesson 5.1's lab: constant torque plus optional gravity compensation, `steps` steps.");
}
