// libFuzzer target: mjcf_lite's load_string on arbitrary bytes (see checks.hpp).
#include <cstdio>
#include <cstdlib>

#include "checks.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string finding = lever::fuzz::check_mjcf(data, size);
  if (!finding.empty()) {
    std::fprintf(stderr, "fuzz_mjcf: FINDING: %s\n", finding.c_str());
    std::abort();
  }
  return 0;
}
