// The random trees of tests/support/random_tree_mjcf.hpp (hinges, slides, ball joints, free
// roots, branches and welds) against MuJoCo 2.2.2: every quantity both compute, M, qfrc_bias and
// qacc among them, on random states, through lever's loader and through MuJoCo's compiled model.
#include <unistd.h>
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <lever/diff/runs.hpp>

#include <lever/harness/models.hpp>
#include "diff_checks.hpp"
#include "random_tree_mjcf.hpp"

namespace lever::test {

TEST_CASE("diff: random trees with ball and free joints agree with MuJoCo", "[diff][trees]") {
  REQUIRE(mj_version() == 222);
  constexpr int kTrees = 20, kStates = 200;
  const std::uint64_t first = seed_for("random_tree_mjcf");  // the property tests' trees
  for (int t = 0; t < kTrees; ++t) {
    const std::uint64_t seed = first + static_cast<std::uint64_t>(t);
    // Twin reads files: the tree written to one named for its seed and this process
    const std::filesystem::path file =
        std::filesystem::temp_directory_path() /
        ("lever_random_tree_" + std::to_string(seed) + "_" + std::to_string(::getpid()) + ".xml");
    {
      std::ofstream out(file);
      out << random_tree_mjcf(seed);
    }
    for (const diff::Path path : paths_to_compare()) {
      INFO("random_tree_mjcf(" << seed << "), " << diff::path_name(path) << " path");
      diff::Twin twin(file.string(), path);
      const diff::Report report = diff::random_states(twin, kStates, seed);
      check_within_bound(report);
      for (const char* quantity : {"M", "qfrc_bias", "qacc"}) {
        INFO(quantity);
        const diff::Extreme* e = report.find(quantity);
        REQUIRE(e != nullptr);
        CHECK(e->compared > 0);
      }
    }
    std::filesystem::remove(file);
  }
}

}  // namespace lever::test
