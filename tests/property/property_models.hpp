// Shared by the property tests: every model, loaded by lever's own loader, with its seed.
#pragma once

#include <algorithm>
#include <catch2/catch.hpp>
#include <cstdint>
#include <filesystem>
#include <lever/lever.hpp>
#include <lever/mjcf.hpp>
#include <string>
#include <vector>

#include <lever/harness/random_state.hpp>
#include <lever/harness/models.hpp>

namespace lever::test {

/// Random states per model and property: enough to visit every limit row and pose region of
/// these small models, few enough to keep the whole kind under a couple of seconds.
constexpr int kStatesPerModel = 200;

struct ModelCase {
  std::string name;  ///< file name, for messages
  std::uint64_t seed;
  Model model;
};

/// Every model of the repository, compiled by lever::mjcf::load_file.
inline std::vector<ModelCase> every_model() {
  std::vector<ModelCase> cases;
  for (const std::string& file : all_model_files()) {
    cases.push_back(
        {std::filesystem::path(file).filename().string(), seed_for(file), mjcf::load_file(file)});
  }
  return cases;
}

/// Largest |x_i|.
inline double max_abs(const Eigen::Ref<const Eigen::VectorXd>& x) {
  return x.size() ? x.cwiseAbs().maxCoeff() : 0.0;
}

}  // namespace lever::test
