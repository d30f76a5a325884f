// lever diff: not written yet.
#include <cstdio>

#include "cli.hpp"
#include "commands.hpp"

namespace lever::cli {

int cmd_diff(const std::vector<std::string>&) {
  std::fprintf(stderr, "lever diff: not available yet\n");
  return kBadInput;
}

}  // namespace lever::cli
