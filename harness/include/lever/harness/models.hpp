// Where the models are, for tests: every *.xml under models/ and tests/models/.
#pragma once

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <cstdlib>
#include <string>
#include <vector>

namespace lever::test {

inline std::string source_dir() { return LEVER_SOURCE_DIR; }

inline std::string model_path(const std::string& relative) { return source_dir() + "/" + relative; }

/// The shared robot files: MuJoCo 2.2.2's sample models and the Menagerie of 2022, read in place
/// from $LEVER_ROBOTS_DIR when it is set, else from CMake's LEVER_ROBOTS_DIR (../shared/robots
/// beside the checkout).
inline std::string robots_dir() {
  // set but empty counts as unset (as a shell's `LEVER_ROBOTS_DIR= make test` means "no override")
  if (const char* dir = std::getenv("LEVER_ROBOTS_DIR"); dir != nullptr && *dir != '\0') return dir;
  return LEVER_ROBOTS_DIR;
}

/// Every model file of the repository (models/ and tests/models/), sorted, as absolute paths.
inline std::vector<std::string> all_model_files() {
  std::vector<std::string> files;
  for (const char* dir : {"models", "tests/models"}) {
    const std::filesystem::path p = std::filesystem::path(source_dir()) / dir;
    if (!std::filesystem::exists(p)) continue;
    for (const auto& entry : std::filesystem::directory_iterator(p)) {
      if (entry.path().extension() == ".xml") files.push_back(entry.path().string());
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

/// The whole text of a file ("" if it cannot be read).
inline std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

/// Seed derived from a name, so every model gets its own reproducible random states.
inline unsigned long long seed_for(const std::string& name) {
  unsigned long long h = 1469598103934665603ull;  // FNV-1a
  for (const unsigned char ch : std::filesystem::path(name).filename().string()) {
    h = (h ^ ch) * 1099511628211ull;
  }
  return h;
}

}  // namespace lever::test
