// lever check: not written yet.
#include <cstdio>

#include "cli.hpp"
#include "commands.hpp"

namespace lever::cli {

int cmd_check(const std::vector<std::string>&) {
  std::fprintf(stderr, "lever check: not available yet\n");
  return kBadInput;
}

}  // namespace lever::cli
