// ModelSpec -> lever::Model, as MuJoCo 2.2.2's compiler (mjCModel::Compile) does it for the
// subset: bodies numbered depth-first, frames and orientation forms, inertia from <inertial> or
// from geoms, bounds, joint limits in radians, dof tree, motors, checks; then set_const().
#pragma once

#include <lever/mjcf.hpp>
#include <lever/model.hpp>
#include <string>
#include <vector>

#include "spec.hpp"

namespace lever::mjcf::detail {

/// Where each compiled object was written, by its id in the Model: lets a ModelError from
/// set_const() be reported at the element it came from.
struct Locations {
  std::vector<Place> body, joint, site, actuator;
  /// per body, its <inertial> element (Place::element -1 where it has none)
  std::vector<Place> inertial;
  /// the files the model file includes (<include>), in the order read
  std::vector<std::string> included_files;
};

/// Compile a parsed model; throws Problem for bad input. set_const() is not called here.
/// `where`, if given, receives each object's element.
Model compile(const ModelSpec& spec, Locations* where = nullptr);

/// load_string() that also gives each object's element (mjcf.cpp), for write.cpp.
Model load_located(const std::string& xml, const std::string& filename, const LoadOptions& options,
                   Locations* where);

/// A model file's text, with load_file()'s checks (exists, regular, size limit); throws ParseError.
std::string read_model_file(const std::string& path);

}  // namespace lever::mjcf::detail
