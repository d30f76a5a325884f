// Shared pieces of the `lever` command: argument parsing, number lists, and the preamble of the
// commands that read a model.
#pragma once

#include <Eigen/Core>

#include <cstddef>
#include <cstdio>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <lever/io/json.hpp>
#include <lever/mjcf.hpp>
#include <lever/model.hpp>

namespace lever::cli {

/// Exit statuses of every command.
enum Exit : int { kOk = 0, kFindings = 1, kBadInput = 2 };

/// An error in the command line; main() prints it with the usage line and exits with kBadInput.
struct UsageError {
  std::string message;
};

/// Command-line arguments: positionals, `--name value` options and `--flag` switches.
class Args {
 public:
  /// `valued` lists the options that take a value; any other `--x` is a switch.
  Args(const std::vector<std::string>& argv, const std::vector<std::string>& valued,
       const std::vector<std::string>& switches);

  const std::vector<std::string>& positional() const { return positional_; }
  bool has(const std::string& name) const;
  std::string get(const std::string& name, const std::string& fallback = "") const;
  /// Every value a repeatable option was given, in order (get() returns the last).
  std::vector<std::string> get_all(const std::string& name) const;
  double get_double(const std::string& name, double fallback) const;
  long get_long(const std::string& name, long fallback) const;
  /// A comma-separated list of n numbers ("0.6,-1.2"); `what` names it in errors.
  Eigen::VectorXd get_vector(const std::string& name, int n, const Eigen::VectorXd& fallback) const;

 private:
  std::vector<std::string> positional_;
  std::map<std::string, std::string> values_;
  std::map<std::string, std::vector<std::string>> all_values_;
};

/// The JSON writer the commands share (lever/io/json.hpp).
using Json = json::Writer;

/// The model file loaded by lever::mjcf::load_file, with what the loader noticed (geom pairs that
/// can collide and that lever cannot compute) written to stderr as warnings naming
/// `command`: never a silent difference from MuJoCo.
Model load_model(const std::string& command, const std::string& path,
                 const mjcf::LoadOptions& options = {});

// ---- the preamble of the commands that read a model (forward, derivatives, identify, simulate)

/// The options that set the state: --key, --qpos, --qvel, --ctrl (forward_state.hpp reads them).
inline const std::vector<std::string> kStateOptions{"key", "qpos", "qvel", "ctrl"};

/// A command line read and its model loaded.
struct Invocation {
  Args args;
  std::string path;  ///< the model file, the first positional
  Model model;
};

/// What such a command does first: parse argv (`valued` options, `switches`, and --help), answer
/// --help by printing `usage` (then it returns nothing: the command exits kOk), require exactly
/// `positionals` positionals (else UsageError "expects <expected>" and the usage), run the
/// command's own checks of its options (`check`, before anything is read), and load the first
/// positional as the model, its warnings on stderr (load_model).
std::optional<Invocation> begin(const char* command, const std::vector<std::string>& argv,
                                const char* usage, const std::vector<std::string>& valued,
                                std::vector<std::string> switches, std::size_t positionals,
                                const char* expected,
                                const std::function<void(const Args&)>& check = {});

}  // namespace lever::cli
