// lever: run a model's checks, evaluate and simulate it, and compare it with MuJoCo 2.2.2.
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include <lever/error.hpp>
#include <lever/version.hpp>

#include "cli.hpp"
#include "commands.hpp"

namespace {

struct Command {
  const char* name;
  int (*run)(const std::vector<std::string>&);
  const char* summary;
};

const Command kCommands[] = {
    {"model", lever::cli::cmd_model, "print what the compiled model contains (--json: its arrays)"},
    {"check", lever::cli::cmd_check, "check every claim the model makes (lesson 5.1's six checks)"},
    {"forward", lever::cli::cmd_forward, "evaluate the model at one state"},
    {"simulate", lever::cli::cmd_simulate, "step the model and print or save the trajectory"},
    {"diff", lever::cli::cmd_diff, "compare lever with MuJoCo 2.2.2 on random states"},
    {"derivatives", lever::cli::cmd_derivatives,
     "the step's Jacobians A, B and the dynamics' derivatives at one state"},
    {"identify", lever::cli::cmd_identify,
     "identify the base inertial parameters from a trajectory (CSV)"},
};

void usage(std::FILE* out) {
  std::fprintf(out, "usage: lever <command> MODEL [options]\n\ncommands:\n");
  for (const Command& c : kCommands) std::fprintf(out, "  %-11s %s\n", c.name, c.summary);
  std::fprintf(
      out, "\n`lever <command> --help` for a command's options; docs/cli.md for all of them.\n");
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || !std::strcmp(argv[1], "--help") || !std::strcmp(argv[1], "-h")) {
    usage(argc < 2 ? stderr : stdout);
    return argc < 2 ? lever::cli::kBadInput : lever::cli::kOk;
  }
  if (!std::strcmp(argv[1], "--version")) {
    std::printf("lever %s\n", lever::version_string());
    return lever::cli::kOk;
  }
  const std::vector<std::string> args(argv + 2, argv + argc);
  for (const Command& c : kCommands) {
    if (std::strcmp(argv[1], c.name) != 0) continue;
    try {
      return c.run(args);
    } catch (const lever::cli::UsageError& e) {
      std::fprintf(stderr, "lever %s: %s\n", c.name, e.message.c_str());
      return lever::cli::kBadInput;
    } catch (const lever::Error& e) {
      std::fprintf(stderr, "%s\n", e.what());
      return lever::cli::kBadInput;
    } catch (const std::exception& e) {
      std::fprintf(stderr, "lever %s: %s\n", c.name, e.what());
      return lever::cli::kBadInput;
    }
  }
  std::fprintf(stderr, "lever: unknown command '%s'\n\n", argv[1]);
  usage(stderr);
  return lever::cli::kBadInput;
}
