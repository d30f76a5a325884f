// lever/serialize.hpp: Model and Data as JSON, every array of the field table (lever/fields.hpp)
// under its own name, flattened row by row. Shared by `lever model --json`, `lever forward
// --json`, the Python package and the browser build.
#pragma once

#include <string>

#include <lever/data.hpp>
#include <lever/json.hpp>
#include <lever/model.hpp>

namespace lever {

/// The model's sizes, names and every array of the table, as members of the open JSON object.
void write_model_fields(json::Writer& json, const Model& model);

/// time, nefc and every array of the table (efc arrays: the live rows), as members of the open
/// JSON object.
void write_data_fields(json::Writer& json, const Model& model, const Data& data);

/// The same, each as one JSON object.
std::string model_to_json(const Model& model);
std::string data_to_json(const Model& model, const Data& data);

}  // namespace lever
