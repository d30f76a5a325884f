// lever: run a model's checks, evaluate and simulate it, and compare it with MuJoCo 2.2.2.
//
// The command line is parsed by CLI11 (Debian's libcli11-dev): one subcommand per command, each
// declaring its positionals and options with their help, type and check (cmd_<name>.cpp). CLI11
// answers `lever --help` and `lever CMD --help` and refuses an unknown command or option, a
// missing value or positional, and a value its check refuses; the command's own checks that
// need the model (a list of nq numbers) come after the model is loaded.
#include <cstdio>
#include <string>

#include <lever/error.hpp>
#include <lever/version.hpp>

#include "cli.hpp"
#include "commands.hpp"

namespace {

struct Command {
  const char* name;
  const char* summary;
  void (*declare)(CLI::App&);
  int (*run)(const lever::cli::Args&);
};

const Command kCommands[] = {
    {"model", "print what the compiled model contains (--json: its arrays)",
     lever::cli::declare_model, lever::cli::cmd_model},
    {"check", "check every claim the model makes (lesson 5.1's six checks)",
     lever::cli::declare_check, lever::cli::cmd_check},
    {"forward", "evaluate the model at one state", lever::cli::declare_forward,
     lever::cli::cmd_forward},
    {"simulate", "step the model and print or save the trajectory", lever::cli::declare_simulate,
     lever::cli::cmd_simulate},
    {"diff", "compare lever with MuJoCo 2.2.2 on random states", lever::cli::declare_diff,
     lever::cli::cmd_diff},
    {"derivatives", "the step's Jacobians A, B and the dynamics' derivatives at one state",
     lever::cli::declare_derivatives, lever::cli::cmd_derivatives},
    {"identify", "identify the base inertial parameters from a trajectory (CSV)",
     lever::cli::declare_identify, lever::cli::cmd_identify},
};

const Command* command_named(const std::string& name) {
  for (const Command& c : kCommands) {
    if (name == c.name) return &c;
  }
  return nullptr;
}

}  // namespace

int main(int argc, char** argv) {
  using lever::cli::kBadInput;
  using lever::cli::kOk;
  CLI::App app("lever: check, evaluate, simulate and identify robot models (MJCF)", "lever");
  app.footer("`lever <command> --help` for a command's options; docs/cli.md for all of them.");
  app.get_formatter()->column_width(26);
  app.get_formatter()->label("SUBCOMMAND", "COMMAND");
  app.set_help_flag("-h,--help", "print this help and exit");  // the subcommands inherit it
  app.set_version_flag("--version", std::string("lever ") + lever::version_string(),
                       "print lever's version and exit");
  std::vector<std::pair<const Command*, CLI::App*>> commands;
  for (const Command& c : kCommands) {
    CLI::App* sub = app.add_subcommand(c.name, c.summary)->group("Commands");
    c.declare(*sub);
    commands.emplace_back(&c, sub);
  }

  // the command a message is about: the first argument, which names it (or is an option of
  // lever's own, such as --help)
  const std::string first = argc >= 2 ? argv[1] : "";
  if (!first.empty() && first[0] != '-' && command_named(first) == nullptr) {
    std::fprintf(stderr, "lever: unknown command '%s' (lever --help lists them)\n", first.c_str());
    return kBadInput;
  }
  const std::string who = command_named(first) ? "lever " + first : "lever";
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    std::fputs(app.help().c_str(), stdout);  // the command's, when one was named
    return kOk;
  } catch (const CLI::CallForVersion& e) {
    std::printf("%s\n", e.what());
    return kOk;
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "%s: %s\n", who.c_str(), e.what());
    return kBadInput;
  }

  for (const auto& [c, sub] : commands) {
    if (!sub->parsed()) continue;
    try {
      return c->run(lever::cli::Args(*sub));
    } catch (const lever::cli::UsageError& e) {
      std::fprintf(stderr, "%s: %s\n", who.c_str(), e.message.c_str());
      return kBadInput;
    } catch (const lever::Error& e) {
      std::fprintf(stderr, "%s\n", e.what());
      return kBadInput;
    } catch (const std::exception& e) {
      std::fprintf(stderr, "%s: %s\n", who.c_str(), e.what());
      return kBadInput;
    }
  }
  std::fprintf(stderr, "lever: no command given\n\n%s", app.help().c_str());
  return kBadInput;
}
