// lever/error.hpp: the exceptions lever throws. what() is always a complete sentence.
#pragma once

#include <stdexcept>
#include <string>
#include <utility>

namespace lever {

/// Base of every lever exception.
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& what) : std::runtime_error(what) {}
};

/// A model whose parameters are inconsistent or non-physical (sizes, tree order, mass, inertia).
/// When one object is at fault, `object()` names its kind ("body", "joint", "site", "actuator")
/// and `index()` its id, so that a loader can point at the element it came from.
class ModelError : public Error {
 public:
  explicit ModelError(const std::string& what) : Error(what) {}
  ModelError(const std::string& what, std::string object, int index)
      : Error(what), object_(std::move(object)), index_(index) {}

  const std::string& object() const { return object_; }  ///< "" when no single object is at fault
  int index() const { return index_; }                   ///< -1 when no single object is at fault

 private:
  std::string object_;
  int index_ = -1;
};

/// A state or argument that cannot be evaluated (wrong size, unknown name).
class StateError : public Error {
 public:
  using Error::Error;
};

}  // namespace lever
