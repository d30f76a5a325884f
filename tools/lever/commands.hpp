// The `lever` subcommands, each in its own cmd_<name>.cpp: declare_<name> declares its
// positionals and options on its CLI11 subcommand (with their help), and cmd_<name> runs it on
// what was parsed and returns an exit status (cli::Exit).
#pragma once

#include "cli.hpp"

namespace lever::cli {

void declare_model(CLI::App& command);
void declare_check(CLI::App& command);
void declare_forward(CLI::App& command);
void declare_simulate(CLI::App& command);
void declare_diff(CLI::App& command);
void declare_derivatives(CLI::App& command);
void declare_identify(CLI::App& command);

int cmd_model(const Args& args);
int cmd_check(const Args& args);
int cmd_forward(const Args& args);
int cmd_simulate(const Args& args);
int cmd_diff(const Args& args);
int cmd_derivatives(const Args& args);
int cmd_identify(const Args& args);

}  // namespace lever::cli
