// <sensor>: its elements as a schema table (the rows schema.cpp adds to its own), read into
// SensorSpec records (parse.cpp calls read_sensors), and compiled into the model's sensor_ arrays
// as MuJoCo 2.2.2's compiler sets them (mjCSensor::Compile; compiler.cpp calls compile_sensors
// once every object has its id).
#pragma once

#include <string>
#include <vector>

#include <lever/model.hpp>

#include "problem.hpp"
#include "user.hpp"

namespace lever::mjcf::detail {

struct ElementRule;
struct Element;

/// One sensor element as written.
struct SensorSpec {
  Place at;
  SensorType type = SensorType::kTouch;
  ObjectType objtype = ObjectType::kUnknown;  ///< what `object` names
  std::string object;                         ///< its name ("" for the clock)
  std::string object_attribute;               ///< the attribute that names it ("site", "objname")
  Place object_at;                            ///< where that attribute is
  ObjectType reftype = ObjectType::kUnknown;  ///< a frame sensor's reference frame, if any
  std::string ref;
  Place ref_at;
  double cutoff = 0, noise = 0;
  UserData user;
  /// a user sensor's own layout (<user dim datatype needstage>); other types take their type's
  SensorLayout layout{0, SensorDataType::kReal, SensorStage::kNone, ObjectType::kUnknown};
};

/// The schema rows of <sensor> and of each sensor element (schema.cpp appends them).
std::vector<ElementRule> sensor_rules();

/// Every sensor of the model's <sensor> sections, in document order. Refuses, naming them, a
/// negative cutoff or noise, and a user sensor's dim that does not fit its datatype.
std::vector<SensorSpec> read_sensors(const Element& root);

/// The sensor_ arrays, nsensor and nsensordata of a model whose other objects are compiled (their
/// names are looked up): a sensor on an object that does not exist, or of a kind it cannot
/// read, is a Problem at the attribute that names it.
void compile_sensors(const std::vector<SensorSpec>& sensors, Model& model);

}  // namespace lever::mjcf::detail
