#include <lever/io/serialize.hpp>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <vector>

#include <lever/contact_force.hpp>
#include <lever/error.hpp>
#include <lever/fields.hpp>

namespace lever {

namespace {

void write_array(json::Writer& json, const FieldView& v) {
  json.key(v.info->name).begin_array();
  for (long i = 0; i < v.size(); ++i) {
    switch (v.info->scalar) {
      case Scalar::kDouble: json.value(static_cast<const double*>(v.data)[i]); break;
      case Scalar::kInt: json.value(static_cast<const int*>(v.data)[i]); break;
      case Scalar::kByte:
        json.value(static_cast<int>(static_cast<const uint8_t*>(v.data)[i]));
        break;
    }
  }
  json.end_array();
}

void write_names(json::Writer& json, const char* key, const std::vector<std::string>& names) {
  json.key(key).begin_array();
  for (const std::string& n : names) json.value(n);
  json.end_array();
}

// ---- CSV -------------------------------------------------------------------------------------

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string out = "\"";
  for (const char ch : s) out += ch == '"' ? std::string("\"\"") : std::string(1, ch);
  return out + "\"";
}

std::string name_or_index(const std::vector<std::string>& names, int i) {
  return names[i].empty() ? std::string(1, '#').append(std::to_string(i)) : names[i];
}

// A joint's name, with the component a row stands for where the joint has several: a free
// joint's x y z qw qx qy qz (qpos) and vx vy vz wx wy wz (qvel), a ball's qw qx qy qz and wx wy wz.
std::string joint_component(const Model& model, int j, int offset, bool coordinate) {
  static const char* const kFreeQ[] = {"x", "y", "z", "qw", "qx", "qy", "qz"};
  static const char* const kFreeV[] = {"vx", "vy", "vz", "wx", "wy", "wz"};
  const std::string name = name_or_index(model.jnt_name, j);
  switch (model.jnt_type[j]) {
    case JointType::kFree: return name + "." + (coordinate ? kFreeQ : kFreeV)[offset];
    case JointType::kBall:
      return name + "." + (coordinate ? kFreeQ[3 + offset] : kFreeV[3 + offset]);
    default: return name;
  }
}

// The sensor whose numbers include sensordata[i].
int sensor_of(const Model& model, int i) {
  int s = model.nsensor - 1;
  while (s > 0 && model.sensor_adr[s] > i) --s;
  return s;
}

// The object row i of an array counted in `rows` stands for.
std::string row_name(const Model& model, Size rows, int i) {
  switch (rows) {
    case Size::kNq:
      for (int j = model.njnt - 1; j >= 0; --j) {
        if (model.jnt_qposadr[j] <= i)
          return joint_component(model, j, i - model.jnt_qposadr[j], true);
      }
      break;
    case Size::kNv: {
      const int j = model.dof_jntid[i];
      return joint_component(model, j, i - model.jnt_dofadr[j], false);
    }
    case Size::kNjnt: return name_or_index(model.jnt_name, i);
    case Size::kNu: return name_or_index(model.actuator_name, i);
    case Size::kNbody: return name_or_index(model.body_name, i);
    case Size::kNsite: return name_or_index(model.site_name, i);
    case Size::kNgeom: return name_or_index(model.geom_name, i);
    case Size::kNsensor: return name_or_index(model.sensor_name, i);
    case Size::kNsensordata: {
      // a named sensor's numbers: name[k], k from 0 within the sensor; an unnamed one's: i
      const int s = sensor_of(model, i);
      if (model.sensor_name[s].empty()) break;
      return model.sensor_name[s] + "[" + std::to_string(i - model.sensor_adr[s]) + "]";
    }
    case Size::kNeq: return name_or_index(model.eq_name, i);
    case Size::kNtendon: return name_or_index(model.tendon_name, i);
    case Size::kOne:
    case Size::kNefc:
    case Size::kNpair:  // pairs and exclusions have no names in lever: their index
    case Size::kNexclude:
    case Size::kNmesh:  // meshes, their vertices and graphs: by index
    case Size::kNmeshvert:
    case Size::kNmeshgraph:
    case Size::kNmeshface: break;
    case Size::kNmocap: break;
    case Size::kNwrap: break;  // a path's objects: by index
    case Size::kNa: return name_or_index(model.actuator_name, i + model.nu - model.na);
    case Size::kNuserBody:  // the user numbers' widths count columns, never rows
    case Size::kNuserJnt:
    case Size::kNuserGeom:
    case Size::kNuserSite:
    case Size::kNuserTendon:
    case Size::kNuserActuator:
    case Size::kNuserSensor: break;
  }
  return std::to_string(i);
}

void append_number(std::string& line, double x) {
  line += ',';
  if (!std::isfinite(x)) return;
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", x + 0.0);  // + 0.0: no "-0"
  line += buf;
}

double element(const FieldView& v, long i) {
  switch (v.info->scalar) {
    case Scalar::kDouble: return static_cast<const double*>(v.data)[i];
    case Scalar::kInt: return static_cast<const int*>(v.data)[i];
    case Scalar::kByte: return static_cast<const uint8_t*>(v.data)[i];
  }
  return 0.0;
}

}  // namespace

CsvWriter::CsvWriter(const Model& model, std::vector<std::string> arrays) : model_(&model) {
  const std::vector<FieldInfo>& table = data_field_table();
  for (const std::string& name : arrays) {
    size_t k = 0;
    while (k < table.size() && name != table[k].name) ++k;
    if (k == table.size()) throw StateError("CSV: Data has no array called '" + name + "'.");
    if (table[k].rows == Size::kNefc) {
      // the live rows change from line to line: a CSV needs fixed columns
      throw StateError("CSV: " + name + " has one row per live limit row; it cannot be a column.");
    }
    columns_.push_back(k);
  }
}

std::string CsvWriter::header() const {
  const Data data(*model_);
  const std::vector<FieldView> views = data_fields(*model_, data);
  std::string line = "time";
  for (const size_t k : columns_) {
    const FieldView& v = views[k];
    for (int r = 0; r < v.rows; ++r) {
      // a sensor's numbers by its own name, `imu_acc[0]`: sensordata[k] only if it has none
      const bool named_sensor = v.info->rows == Size::kNsensordata &&
                                !model_->sensor_name[sensor_of(*model_, r)].empty();
      const std::string object =
          named_sensor ? row_name(*model_, v.info->rows, r)
                       : std::string(v.info->name) + "[" + row_name(*model_, v.info->rows, r) + "]";
      for (int c = 0; c < v.cols; ++c) {
        line += ',';
        line += csv_field(v.cols == 1 ? object : object + "[" + std::to_string(c) + "]");
      }
    }
  }
  return line + "\n";
}

std::string CsvWriter::row(const Data& data) const {
  check_fit(*model_, data, "lever::CsvWriter::row");
  const std::vector<FieldView> views = data_fields(*model_, data);
  std::string line;
  append_number(line, data.time);
  line.erase(0, 1);  // the first field has no comma before it
  for (const size_t k : columns_) {
    const FieldView& v = views[k];
    for (long i = 0; i < v.size(); ++i) append_number(line, element(v, i));
  }
  return line + "\n";
}

const std::vector<std::string>& simulate_csv_arrays() {
  static const std::vector<std::string> arrays = {
      "qpos", "qvel", "qacc", "qfrc_bias", "ctrl", "actuator_force", "qfrc_constraint",
      "sensordata"};
  return arrays;
}

void write_model_sizes(json::Writer& json, const Model& model) {
  for (Size s :
       {Size::kNq, Size::kNv, Size::kNu, Size::kNbody, Size::kNjnt, Size::kNgeom, Size::kNsite}) {
    json.key(size_name(s)).value(size_of(model, s));
  }
}

void write_model_fields(json::Writer& json, const Model& model) {
  json.key("model").value(model.name);
  json.key("source").value(model.source);
  write_model_sizes(json, model);
  json.key("opt_timestep").value(model.opt.timestep);
  json.key("opt_gravity").values(model.opt.gravity);
  json.key("opt_integrator").value(static_cast<int>(model.opt.integrator));
  json.key("opt_disableflags").value(model.opt.disableflags);
  json.key("opt_enableflags").value(model.opt.enableflags);
  json.key("opt_o_margin").value(model.opt.o_margin);
  json.key("opt_o_solref").values(Eigen::Map<const Eigen::VectorXd>(model.opt.o_solref.data(), 2));
  json.key("opt_o_solimp").values(Eigen::Map<const Eigen::VectorXd>(model.opt.o_solimp.data(), 5));
  write_names(json, "body_name", model.body_name);
  write_names(json, "jnt_name", model.jnt_name);
  write_names(json, "geom_name", model.geom_name);
  write_names(json, "site_name", model.site_name);
  write_names(json, "actuator_name", model.actuator_name);
  json.key("nsensor").value(model.nsensor);
  json.key("nsensordata").value(model.nsensordata);
  write_names(json, "sensor_name", model.sensor_name);
  for (const FieldView& v : model_fields(model)) write_array(json, v);
}

void write_data_fields(json::Writer& json, const Model& model, const Data& data) {
  json.key("time").value(data.time);
  json.key("nefc").value(data.nefc);
  for (const FieldView& v : data_fields(model, data)) write_array(json, v);
  // efc_J's live rows, nefc x nv row-major (the table has no nefc x nv shape)
  json.key("efc_J").begin_array();
  for (int r = 0; r < data.nefc; ++r) {
    for (int c = 0; c < model.nv; ++c) json.value(data.efc_J(r, c));
  }
  json.end_array();
  write_contacts(json, model, data);
}

void write_contacts(json::Writer& json, const Model& model, const Data& data) {
  check_fit(model, data, "lever::write_contacts");
  json.key("ncon").value(data.ncon);
  json.key("contact").begin_array();
  const auto numbers = [&json](const char* key, const double* x, int n) {
    json.key(key).begin_array();
    for (int k = 0; k < n; ++k) json.value(x[k]);
    json.end_array();
  };
  for (int i = 0; i < data.ncon; ++i) {
    const Contact& c = data.contact[static_cast<size_t>(i)];
    json.begin_object();
    for (const ContactField& f : contact_field_table()) {  // frame row-major: the normal first
      if (f.scalar == Scalar::kInt) {
        const int* x = static_cast<const int*>(f.in(c));
        if (f.count == 1) {
          json.key(f.name).value(*x);
        } else {
          json.key(f.name).begin_array();
          for (int k = 0; k < f.count; ++k) json.value(x[k]);
          json.end_array();
        }
      } else if (f.count == 1) {
        json.key(f.name).value(*static_cast<const double*>(f.in(c)));
      } else {
        numbers(f.name, static_cast<const double*>(f.in(c)), f.count);
      }
    }
    json.key("geom1_name").value(model.geom_name[static_cast<size_t>(c.geom1)]);
    json.key("geom2_name").value(model.geom_name[static_cast<size_t>(c.geom2)]);
    const Eigen::Matrix<double, 6, 1> force = contact_force(model, data, i);
    numbers("force", force.data(), 6);
    json.end_object();
  }
  json.end_array();
}

void write_data_arrays(json::Writer& json, const Model& model, const Data& data,
                       const std::vector<std::string>& names) {
  const std::vector<FieldView> views = data_fields(model, data);
  for (const std::string& name : names) {
    const FieldView* found = nullptr;
    for (const FieldView& v : views) {
      if (name == v.info->name) found = &v;
    }
    if (found == nullptr) throw StateError("JSON: Data has no array called '" + name + "'.");
    write_array(json, *found);
  }
}

std::string model_to_json(const Model& model) {
  std::string text;
  json::Writer json(&text);
  json.begin_object();
  write_model_fields(json, model);
  json.end_object();
  return text;
}

std::string data_to_json(const Model& model, const Data& data) {
  std::string text;
  json::Writer json(&text);
  json.begin_object();
  write_data_fields(json, model, data);
  json.end_object();
  return text;
}

}  // namespace lever
