// lever simulate: not written yet.
#include <cstdio>

#include "cli.hpp"
#include "commands.hpp"

namespace lever::cli {

int cmd_simulate(const std::vector<std::string>&) {
  std::fprintf(stderr, "lever simulate: not available yet\n");
  return kBadInput;
}

}  // namespace lever::cli
