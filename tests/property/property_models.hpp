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

#include <lever/harness/models.hpp>
#include <lever/harness/random_state.hpp>
#include "random_tree.hpp"
#include "random_tree_mjcf.hpp"
#include "sampling.hpp"

namespace lever::test {

/// Random states per model and property: enough to visit every limit row and pose region of
/// these small models, few enough to keep the whole kind under a couple of seconds.
constexpr int kStatesPerModel = samples(200);

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

/// Random trees per property, besides the model files.
constexpr int kRandomTrees = 20;

/// kRandomTrees random trees (tests/support/random_tree.hpp), each named by the seed that
/// rebuilds it: random_tree(seed).
inline std::vector<ModelCase> random_trees() {
  std::vector<ModelCase> cases;
  const std::uint64_t first = seed_for("random_tree");
  for (int t = 0; t < kRandomTrees; ++t) {
    const std::uint64_t seed = first + static_cast<std::uint64_t>(t);
    cases.push_back({"random_tree(" + std::to_string(seed) + ")", seed, random_tree(seed)});
  }
  return cases;
}

/// Random trees written as MJCF (tests/support/random_tree_mjcf.hpp: ball joints, free roots),
/// per property.
constexpr int kRandomMjcfTrees = 20;

/// kRandomMjcfTrees trees of random_tree_mjcf(seed), compiled by lever::mjcf::load_string.
inline std::vector<ModelCase> random_mjcf_trees() {
  std::vector<ModelCase> cases;
  const std::uint64_t first = seed_for("random_tree_mjcf");
  for (int t = 0; t < kRandomMjcfTrees; ++t) {
    const std::uint64_t seed = first + static_cast<std::uint64_t>(t);
    const std::string name = "random_tree_mjcf(" + std::to_string(seed) + ")";
    cases.push_back({name, seed, mjcf::load_string(random_tree_mjcf(seed), name)});
  }
  return cases;
}

/// Every model file, then the random trees (built in memory, then written as MJCF).
inline std::vector<ModelCase> every_model_and_random_trees() {
  std::vector<ModelCase> cases = every_model();
  for (ModelCase& c : random_trees()) cases.push_back(std::move(c));
  for (ModelCase& c : random_mjcf_trees()) cases.push_back(std::move(c));
  return cases;
}

/// Whether every joint is a hinge or a slide (no quaternion coordinates): what lever's analytic
/// derivatives and identification cover so far (they refuse the others, tests/derivatives).
inline bool hinges_and_slides(const Model& model) { return model.nq == model.nv; }

/// The cases of `cases` whose joints are all hinges and slides.
inline std::vector<ModelCase> hinge_and_slide_models(std::vector<ModelCase> cases) {
  std::erase_if(cases, [](const ModelCase& c) { return !hinges_and_slides(c.model); });
  return cases;
}

/// How many of `states` the expensive properties (those differencing or integrating every dof)
/// run on a case: all on a model file, a fifth on a random tree, whose dofs are many and whose
/// number makes up for the states.
inline int states_for(const ModelCase& c, int states) {
  return c.model.source.empty() ? std::max(1, states / 5) : states;
}

/// Largest |x_i|.
inline double max_abs(const Eigen::Ref<const Eigen::VectorXd>& x) {
  return x.size() ? x.cwiseAbs().maxCoeff() : 0.0;
}

}  // namespace lever::test
