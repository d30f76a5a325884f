// lever forward: not written yet.
#include <cstdio>

#include "cli.hpp"
#include "commands.hpp"

namespace lever::cli {

int cmd_forward(const std::vector<std::string>&) {
  std::fprintf(stderr, "lever forward: not available yet\n");
  return kBadInput;
}

}  // namespace lever::cli
