// lever/io/serialize.hpp: Model and Data as JSON, every array of the field table (lever/fields.hpp)
// under its own name, flattened row by row; and chosen Data arrays as CSV, one line per state.
// Shared by `lever model --json`, `lever forward --json`, `lever simulate --csv`, the Python
// package and the browser build.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include <lever/data.hpp>
#include <lever/io/json.hpp>
#include <lever/model.hpp>

namespace lever {

/// The model's sizes nq, nv, nu, nbody, njnt, ngeom, nsite, as members of the open JSON object.
void write_model_sizes(json::Writer& json, const Model& model);

/// The model's sizes, names and every array of the table, as members of the open JSON object.
void write_model_fields(json::Writer& json, const Model& model);

/// time, nefc and every array of the table (efc arrays: the live rows), efc_J (nefc x nv,
/// row-major), then the contacts (write_contacts), as members of the open JSON object.
void write_data_fields(json::Writer& json, const Model& model, const Data& data);

/// `ncon` and `contact`: an array of the ncon contacts, each an object with MuJoCo's mjContact
/// fields (geom1, geom2, dist, pos, frame as 9 numbers row-major: the normal from geom1 into
/// geom2, then two tangents; dim, friction, solref, solimp, includemargin, exclude, efc_address,
/// mu), the geoms' names (geom1_name, geom2_name; "" for an unnamed geom) and `force`: its force
/// in its frame (lever::contact_force, mj_contactForce: normal, two tangents, torsion, two rolls),
/// as members of the open JSON object. Throws StateError if the data does not fit the model.
void write_contacts(json::Writer& json, const Model& model, const Data& data);

/// Chosen arrays of the table (by name, in the order given), as members of the open JSON object;
/// throws StateError naming an array the table does not have.
void write_data_arrays(json::Writer& json, const Model& model, const Data& data,
                       const std::vector<std::string>& names);

/// The same, each as one JSON object.
std::string model_to_json(const Model& model);
std::string data_to_json(const Model& model, const Data& data);

/// CSV of chosen Data arrays (names of the field table), one line per state: `time`, then each
/// array's elements in the order given, row by row. A column is named after its array and its
/// row's object, `qpos[shoulder]` (joints for nq/nv/njnt arrays, motors for nu, bodies, sites;
/// `#3` for an object without a name), with `[c]` appended for arrays of several columns; a
/// named sensor's numbers are `name[k]` (k counted within the sensor), an unnamed one's
/// `sensordata[i]`.
/// Numbers have 17 significant digits; a number that is not finite is an empty field.
class CsvWriter {
 public:
  /// Throws StateError naming an array the table does not have.
  CsvWriter(const Model& model, std::vector<std::string> arrays);
  /// The header line, with its newline.
  std::string header() const;
  /// One line for the current state of data, with its newline.
  std::string row(const Data& data) const;

 private:
  const Model* model_;
  std::vector<size_t> columns_;  ///< rows of data_field_table()
};

/// The columns of `lever simulate --csv`: joint positions, velocities, accelerations, bias forces,
/// motor commands and forces, limit forces, the sensors' numbers (none for a model without sensors).
const std::vector<std::string>& simulate_csv_arrays();

}  // namespace lever
