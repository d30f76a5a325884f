// lever model: not written yet.
#include <cstdio>

#include "cli.hpp"
#include "commands.hpp"

namespace lever::cli {

int cmd_model(const std::vector<std::string>&) {
  std::fprintf(stderr, "lever model: not available yet\n");
  return kBadInput;
}

}  // namespace lever::cli
