// For tests that read the shared robot files (../shared/robots, or $LEVER_ROBOTS_DIR): on a machine
// without them such a test says so and returns, rather than failing on a missing file.
#pragma once

#include <catch2/catch.hpp>

#include <filesystem>
#include <string>

#include "lever/harness/models.hpp"

namespace lever::test {

/// True if `path` (a robot file or their folder) is on this machine; else a warning that the test
/// is skipped. Use: `if (!robots_present(file)) return;`
inline bool robots_present(const std::string& path) {
  if (std::filesystem::exists(path)) return true;
  WARN("no real model files at " << path << ": skipped");
  return false;
}

}  // namespace lever::test
