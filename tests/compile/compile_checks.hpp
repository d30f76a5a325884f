// Catch2's side of the compile comparison (mujoco_xml.hpp): each difference between lever's and
// MuJoCo 2.2.2's compiled model is one failed check, named by the model.
#pragma once

#include <catch2/catch.hpp>

#include <string>

#include "mujoco_xml.hpp"

namespace lever::test {

inline void check_compiles_as_mujoco(const std::string& name, const std::string& xml) {
  for (const std::string& d : compile_differences(name, xml)) FAIL_CHECK(name << ": " << d);
}

}  // namespace lever::test
