// lever/error.hpp: the exceptions lever throws. what() is always a complete sentence.
#pragma once

#include <stdexcept>
#include <string>

namespace lever {

/// Base of every lever exception.
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& what) : std::runtime_error(what) {}
};

/// A model whose parameters are inconsistent or non-physical (sizes, tree order, mass, inertia).
class ModelError : public Error {
 public:
  using Error::Error;
};

/// A state or argument that cannot be evaluated (wrong size, unknown name).
class StateError : public Error {
 public:
  using Error::Error;
};

}  // namespace lever
