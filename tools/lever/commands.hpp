// The `lever` subcommands. Each takes the arguments after its name and returns an exit status
// (cli::Exit); each lives in its own cmd_<name>.cpp.
#pragma once

#include <string>
#include <vector>

namespace lever::cli {

int cmd_model(const std::vector<std::string>& argv);
int cmd_check(const std::vector<std::string>& argv);
int cmd_forward(const std::vector<std::string>& argv);
int cmd_simulate(const std::vector<std::string>& argv);
int cmd_diff(const std::vector<std::string>& argv);
int cmd_derivatives(const std::vector<std::string>& argv);
int cmd_identify(const std::vector<std::string>& argv);

}  // namespace lever::cli
