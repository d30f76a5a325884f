// libFuzzer target: forward, inverse and step on every repository model at fuzzed states and
// controls (see checks.hpp).
#include <cstdio>
#include <cstdlib>

#include "checks.hpp"

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** /*argv*/) {
  if (lever::fuzz::engine_model_count(LEVER_SOURCE_DIR) == 0) {
    std::fprintf(stderr, "fuzz_engine: no model of %s/models or tests/models loads\n",
                 LEVER_SOURCE_DIR);
    std::abort();
  }
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string finding = lever::fuzz::check_engine(data, size, LEVER_SOURCE_DIR);
  if (!finding.empty()) {
    std::fprintf(stderr, "fuzz_engine: FINDING: %s\n", finding.c_str());
    std::abort();
  }
  return 0;
}
