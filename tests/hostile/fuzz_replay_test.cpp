// Every input the fuzzers ever found a problem with (tests/hostile/fuzz/<target>/), replayed
// through the fuzz targets' own checks (fuzz/checks.cpp) without libFuzzer: each must now be
// handled correctly. Runs in every build, the sanitizer build included.
#include <catch2/catch.hpp>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "checks.hpp"
#include "run_process.hpp"
#include <lever/harness/models.hpp>

namespace {

std::vector<std::filesystem::path> inputs(const char* target) {
  std::vector<std::filesystem::path> files;
  const std::filesystem::path d =
      std::filesystem::path(lever::test::source_dir()) / "tests/hostile/fuzz" / target;
  if (!std::filesystem::exists(d)) return files;
  for (const auto& entry : std::filesystem::directory_iterator(d)) {
    if (entry.is_regular_file()) files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

std::string bytes_of(const std::filesystem::path& p) { return lever::test::slurp(p); }

const std::uint8_t* data_of(const std::string& s) {
  return reinterpret_cast<const std::uint8_t*>(s.data());
}

}  // namespace

TEST_CASE("fuzz_mjcf regressions are handled", "[hostile][fuzz]") {
  const auto files = inputs("fuzz_mjcf");
  for (const auto& f : files) {
    {
      INFO(f.filename().string());
      const std::string bytes = bytes_of(f);
      CHECK(lever::fuzz::check_mjcf(data_of(bytes), bytes.size()).empty());
    }
  }
}

TEST_CASE("fuzz_engine regressions are handled", "[hostile][fuzz]") {
  REQUIRE(lever::fuzz::engine_model_count(lever::test::source_dir()) > 0);
  for (const auto& f : inputs("fuzz_engine")) {
    {
      INFO(f.filename().string());
      const std::string bytes = bytes_of(f);
      CHECK(lever::fuzz::check_engine(data_of(bytes), bytes.size(), lever::test::source_dir())
                .empty());
    }
  }
}

TEST_CASE("the fuzz checks catch what they are meant to", "[hostile][fuzz]") {
  // a model that loads passes; junk is refused cleanly (not a finding)
  const std::string arm2 = lever::test::slurp(lever::test::model_path("models/arm2.xml"));
  CHECK(lever::fuzz::check_mjcf(data_of(arm2), arm2.size()).empty());
  const std::string junk = "\x01\x02<mujoco";
  CHECK(lever::fuzz::check_mjcf(data_of(junk), junk.size()).empty());
  // every model, NaN everywhere, both integrators, several steps: handled
  for (int m = 0; m < lever::fuzz::engine_model_count(lever::test::source_dir()); ++m) {
    for (const std::uint8_t flags : {0, 1, 3, 0x4f}) {
      const std::string nan_state =
          std::string{static_cast<char>(m), static_cast<char>(flags)} + std::string(64, '\0');
      CHECK(
          lever::fuzz::check_engine(data_of(nan_state), nan_state.size(), lever::test::source_dir())
              .empty());
    }
  }
}
