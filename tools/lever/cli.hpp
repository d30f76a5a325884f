// Shared pieces of the `lever` command: argument parsing, number lists, JSON output.
#pragma once

#include <Eigen/Core>

#include <cstdio>
#include <map>
#include <string>
#include <vector>

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
  double get_double(const std::string& name, double fallback) const;
  long get_long(const std::string& name, long fallback) const;
  /// A comma-separated list of n numbers ("0.6,-1.2"); `what` names it in errors.
  Eigen::VectorXd get_vector(const std::string& name, int n, const Eigen::VectorXd& fallback) const;

 private:
  std::vector<std::string> positional_;
  std::map<std::string, std::string> values_;
};

/// A minimal streaming JSON writer: numbers in full double precision (%.17g), non-finite
/// numbers as null, keys in the order written.
class Json {
 public:
  explicit Json(std::FILE* out) : out_(out) {}
  Json& begin_object();
  Json& end_object();
  Json& begin_array();
  Json& end_array();
  Json& key(const std::string& k);
  Json& value(double x);
  Json& value(int x);
  Json& value(long x);
  Json& value(bool x);
  Json& value(const std::string& s);
  Json& value(const char* s) { return value(std::string(s)); }
  Json& values(const Eigen::Ref<const Eigen::VectorXd>& v);  ///< as one flat array
  void newline();

 private:
  void separator();
  std::FILE* out_;
  std::vector<bool> first_;  // one per open container: nothing written in it yet
  bool after_key_ = false;
};

/// JSON string escaping.
std::string json_escape(const std::string& s);

}  // namespace lever::cli
