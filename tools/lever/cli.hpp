// Shared pieces of the `lever` command: the command line as CLI11 parsed it, the checks its
// options are declared with, and the preamble of the commands that read a model.
//
// Each command declares its positionals and options on its own CLI11 subcommand (declare_<name>
// in cmd_<name>.cpp: name, help text, type name, check); main() parses the whole command line
// with CLI11, which answers --help and refuses what is not declared, and hands the command an
// Args to read its values by name.
#pragma once

#include <Eigen/Core>

#include <cstddef>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include <lever/io/json.hpp>
#include <lever/mjcf.hpp>
#include <lever/model.hpp>

namespace lever::cli {

/// Exit statuses of every command.
enum Exit : int { kOk = 0, kFindings = 1, kBadInput = 2 };

/// An error in the command line found after parsing (a list of the wrong length, two options that
/// exclude each other); main() prints it after the command's name and exits with kBadInput.
struct UsageError {
  std::string message;
};

// ---- declaring a command's options (CLI11) -------------------------------------------------

/// The checks an option's value is declared with. Each refuses text that is not what the option
/// takes, with the message the user sees after the option's name ("--qpos: 'x' is not a number").
/// A finite double.
const CLI::Validator& number_check();
/// A whole number (a C long).
const CLI::Validator& whole_number_check();
/// Comma-separated finite doubles; how many the model needs is checked by Args::get_vector.
const CLI::Validator& number_list_check();
/// Not empty (a file or keyframe name).
const CLI::Validator& not_empty_check();

/// A `--name VALUE` option: shown in --help as `--name TYPE` with `help`; given twice, the last
/// value counts.
CLI::Option* add_value(CLI::App& command, const std::string& name, const std::string& type,
                       const std::string& help);
/// A `--name` switch, which takes no value.
CLI::Option* add_switch(CLI::App& command, const std::string& name, const std::string& help);

/// --key, --qpos, --qvel and --ctrl with their help (forward_state.hpp reads them).
struct StateHelp {
  const char* key;
  const char* qpos;
  const char* qvel;
  const char* ctrl;
};
void add_state_options(CLI::App& command, const StateHelp& help);

// ---- reading them ----------------------------------------------------------------------------

/// One command's positionals and options as CLI11 parsed them; options are named without their
/// dashes ("qpos" for --qpos).
class Args {
 public:
  explicit Args(const CLI::App& command);

  /// Every positional's values, in the order they are declared.
  const std::vector<std::string>& positional() const { return positional_; }
  bool has(const std::string& name) const;
  std::string get(const std::string& name, const std::string& fallback = "") const;
  /// Every value a repeatable option was given, in order (get() returns the last).
  std::vector<std::string> get_all(const std::string& name) const;
  double get_double(const std::string& name, double fallback) const;
  long get_long(const std::string& name, long fallback) const;
  /// A comma-separated list of n numbers ("0.6,-1.2").
  Eigen::VectorXd get_vector(const std::string& name, int n, const Eigen::VectorXd& fallback) const;

 private:
  const CLI::Option& option(const std::string& name) const;
  const CLI::App* command_;
  std::vector<std::string> positional_;
};

/// The JSON writer the commands share (lever/io/json.hpp).
using Json = json::Writer;

/// The model file loaded by lever::mjcf::load_file, with what the loader noticed (geom pairs that
/// can collide and that lever cannot compute) written to stderr as warnings naming
/// `command`: never a silent difference from MuJoCo.
Model load_model(const std::string& command, const std::string& path,
                 const mjcf::LoadOptions& options = {});

// ---- the preamble of the commands that read a model (forward, derivatives, identify, simulate)

/// A command line read and its model loaded.
struct Invocation {
  Args args;
  std::string path;  ///< the model file, the first positional
  Model model;
};

/// What such a command does first, after CLI11 has parsed and checked each option: run the
/// command's own checks of its options together (`check`, before anything is read), and load the
/// first positional as the model, its warnings on stderr (load_model).
Invocation begin(const char* command, const Args& args,
                 const std::function<void(const Args&)>& check = {});

}  // namespace lever::cli
