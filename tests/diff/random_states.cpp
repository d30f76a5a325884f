// Every quantity lever shares with MuJoCo 2.2.2, on 1000 random states per model.
#include <catch2/catch.hpp>
#include <lever/diff/runs.hpp>
#include <lever/fields.hpp>

#include <lever/harness/models.hpp>
#include "diff_checks.hpp"
#include "sampling.hpp"

namespace lever::test {

namespace {

constexpr int kStates = samples(1000);

void compare_every_model_on(diff::Path path) {
  REQUIRE(mj_version() == 222);
  for (const std::string& file : all_model_files()) {
    const std::uint64_t seed = diff::default_seed(file);
    const std::string where = context(file, path, seed);
    INFO(where);
    diff::Twin twin(file, path);
    const diff::Report report = diff::random_states(twin, kStates, seed);
    check_within_bound(report);
    // the states must reach the stops, or the limit rows were never compared
    if (has_limits(twin.model)) CHECK(report.find("efc_force")->compared >= kStates / 10);
    // every array of Data's field table that MuJoCo has and forward() writes was compared (the
    // comparison is driven by the table: an array it skipped would be a hole in the proof)
    for (const FieldInfo& info : data_field_table()) {
      const bool forward_output = info.stage != Stage::kInverse && info.stage != Stage::kEnergy &&
                                  info.stage != Stage::kStep;
      if (!info.in_mujoco || !forward_output) continue;
      INFO(info.name);
      const diff::Extreme* e = report.find(info.name);
      REQUIRE(e != nullptr);
      if (info.rows == Size::kNefc) {
        if (has_limits(twin.model)) CHECK(e->compared > 0);
      } else if (size_of(twin.model, info.rows) > 0) {
        CHECK(e->compared == static_cast<long>(kStates) * size_of(twin.model, info.rows) *
                                 (info.cols < 0 ? twin.model.nv : info.cols));
      }
    }
  }
}

}  // namespace

TEST_CASE("diff: every quantity agrees with MuJoCo on random states, lever's loader",
          "[diff][loader]") {
  compare_every_model_on(diff::Path::kLoader);
}

TEST_CASE("diff: every quantity agrees with MuJoCo on random states, MuJoCo's compiled model",
          "[diff][engine]") {
  compare_every_model_on(diff::Path::kEngine);
}

}  // namespace lever::test
