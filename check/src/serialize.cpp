#include <lever/serialize.hpp>

#include <cstdint>
#include <vector>

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

}  // namespace

void write_model_fields(json::Writer& json, const Model& model) {
  json.key("model").value(model.name);
  json.key("source").value(model.source);
  for (Size s :
       {Size::kNq, Size::kNv, Size::kNu, Size::kNbody, Size::kNjnt, Size::kNgeom, Size::kNsite}) {
    json.key(size_name(s)).value(size_of(model, s));
  }
  json.key("opt_timestep").value(model.opt.timestep);
  json.key("opt_gravity").values(model.opt.gravity);
  json.key("opt_integrator").value(static_cast<int>(model.opt.integrator));
  write_names(json, "body_name", model.body_name);
  write_names(json, "jnt_name", model.jnt_name);
  write_names(json, "geom_name", model.geom_name);
  write_names(json, "site_name", model.site_name);
  write_names(json, "actuator_name", model.actuator_name);
  for (const FieldView& v : model_fields(model)) write_array(json, v);
}

void write_data_fields(json::Writer& json, const Model& model, const Data& data) {
  json.key("time").value(data.time);
  json.key("nefc").value(data.nefc);
  for (const FieldView& v : data_fields(model, data)) write_array(json, v);
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
