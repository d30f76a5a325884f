#include "cli.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <utility>

namespace lever::cli {

namespace {
bool contains(const std::vector<std::string>& list, const std::string& s) {
  for (const auto& x : list) {
    if (x == s) return true;
  }
  return false;
}

double parse_double(const std::string& text, const std::string& what) {
  errno = 0;
  char* end = nullptr;
  const double x = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size()) {
    throw UsageError{what + ": '" + text + "' is not a number"};
  }
  // ERANGE: an overflow is refused; an underflow to a denormal or zero is a number (4.9e-324)
  if (errno == ERANGE && std::isinf(x)) {
    throw UsageError{what + ": '" + text + "' is too large for a double"};
  }
  if (!std::isfinite(x)) throw UsageError{what + ": '" + text + "' is not a finite number"};
  return x;
}
}  // namespace

Args::Args(const std::vector<std::string>& argv, const std::vector<std::string>& valued,
           const std::vector<std::string>& switches) {
  for (size_t i = 0; i < argv.size(); ++i) {
    const std::string& a = argv[i];
    if (a.rfind("--", 0) == 0 && a.size() > 2) {
      std::string name = a.substr(2), value;
      const size_t eq = name.find('=');
      const bool inline_value = eq != std::string::npos;
      if (inline_value) {
        value = name.substr(eq + 1);
        name.resize(eq);
      }
      if (contains(valued, name)) {
        if (!inline_value) {
          if (i + 1 >= argv.size()) throw UsageError{"option --" + name + " needs a value"};
          value = argv[++i];
        }
        values_[name] = value;
        all_values_[name].push_back(value);
      } else if (contains(switches, name)) {
        if (inline_value) throw UsageError{"option --" + name + " takes no value"};
        values_[name] = "";
      } else {
        throw UsageError{"unknown option --" + name};
      }
    } else {
      positional_.push_back(a);
    }
  }
}

bool Args::has(const std::string& name) const { return values_.count(name) > 0; }

std::vector<std::string> Args::get_all(const std::string& name) const {
  const auto it = all_values_.find(name);
  return it == all_values_.end() ? std::vector<std::string>{} : it->second;
}

std::string Args::get(const std::string& name, const std::string& fallback) const {
  const auto it = values_.find(name);
  return it == values_.end() ? fallback : it->second;
}

double Args::get_double(const std::string& name, double fallback) const {
  return has(name) ? parse_double(get(name), "--" + name) : fallback;
}

long Args::get_long(const std::string& name, long fallback) const {
  if (!has(name)) return fallback;
  const std::string text = get(name);
  char* end = nullptr;
  errno = 0;
  const long x = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || end != text.c_str() + text.size() || errno == ERANGE) {
    throw UsageError{"--" + name + ": '" + text + "' is not a whole number"};
  }
  return x;
}

Eigen::VectorXd Args::get_vector(const std::string& name, int n,
                                 const Eigen::VectorXd& fallback) const {
  if (!has(name)) return fallback;
  std::vector<double> xs;
  std::stringstream ss(get(name));
  std::string item;
  while (std::getline(ss, item, ',')) xs.push_back(parse_double(item, "--" + name));
  if (static_cast<int>(xs.size()) != n) {
    throw UsageError{"--" + name + " needs " + std::to_string(n) +
                     " comma-separated numbers, got " + std::to_string(xs.size())};
  }
  return Eigen::Map<Eigen::VectorXd>(xs.data(), n);
}

Model load_model(const std::string& command, const std::string& path,
                 const mjcf::LoadOptions& options) {
  Model model = mjcf::load_file(path, options);
  for (const std::string& w : model.warnings) {
    std::fprintf(stderr, "lever %s: warning: %s: %s\n", command.c_str(), path.c_str(), w.c_str());
  }
  return model;
}

std::optional<Invocation> begin(const char* command, const std::vector<std::string>& argv,
                                const char* usage, const std::vector<std::string>& valued,
                                std::vector<std::string> switches, std::size_t positionals,
                                const char* expected,
                                const std::function<void(const Args&)>& check) {
  switches.push_back("help");
  Args args(argv, valued, switches);
  if (args.has("help")) {
    std::fputs(usage, stdout);
    return std::nullopt;
  }
  if (args.positional().size() != positionals) {
    throw UsageError{std::string("expects ") + expected + "\n" + usage};
  }
  if (check) check(args);
  std::string path = args.positional()[0];
  Model model = load_model(command, path);
  return Invocation{std::move(args), std::move(path), std::move(model)};
}

}  // namespace lever::cli
