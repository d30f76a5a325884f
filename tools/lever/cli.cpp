#include "cli.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <utility>

namespace lever::cli {

namespace {

// "" when text is a finite double, else why not (the option's name goes before it).
std::string number_error(const std::string& text) {
  errno = 0;
  char* end = nullptr;
  const double x = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size()) return "'" + text + "' is not a number";
  // ERANGE: an overflow is refused; an underflow to a denormal or zero is a number (4.9e-324)
  if (errno == ERANGE && std::isinf(x)) return "'" + text + "' is too large for a double";
  if (!std::isfinite(x)) return "'" + text + "' is not a finite number";
  return "";
}

std::string whole_number_error(const std::string& text) {
  char* end = nullptr;
  errno = 0;
  std::strtol(text.c_str(), &end, 10);
  if (text.empty() || end != text.c_str() + text.size() || errno == ERANGE) {
    return "'" + text + "' is not a whole number";
  }
  return "";
}

std::vector<std::string> split_list(const std::string& text) {
  std::vector<std::string> items;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) items.push_back(item);
  return items;
}

std::string number_list_error(const std::string& text) {
  for (const std::string& item : split_list(text)) {
    std::string error = number_error(item);
    if (!error.empty()) return error;
  }
  return "";
}

// A check with no description of its own: --help shows the option's type name alone.
CLI::Validator check_of(std::string (*error)(const std::string&)) {
  return CLI::Validator([error](std::string& text) { return error(text); }, "");
}

// An option's value is checked when it is parsed, so a value read here is well formed.
[[noreturn]] void unchecked(const std::string& name, const std::string& error) {
  throw UsageError{"--" + name + ": " + error};
}

}  // namespace

const CLI::Validator& number_check() {
  static const CLI::Validator check = check_of(number_error);
  return check;
}
const CLI::Validator& whole_number_check() {
  static const CLI::Validator check = check_of(whole_number_error);
  return check;
}
const CLI::Validator& number_list_check() {
  static const CLI::Validator check = check_of(number_list_error);
  return check;
}
const CLI::Validator& not_empty_check() {
  static const CLI::Validator check = check_of(
      [](const std::string& text) { return text.empty() ? std::string("needs a name") : ""; });
  return check;
}

CLI::Option* add_value(CLI::App& command, const std::string& name, const std::string& type,
                       const std::string& help) {
  return command.add_option("--" + name, help)
      ->type_name(type)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
}

CLI::Option* add_switch(CLI::App& command, const std::string& name, const std::string& help) {
  return command.add_flag("--" + name, help)->disable_flag_override();
}

void add_state_options(CLI::App& command, const StateHelp& help) {
  add_value(command, "key", "NAME", help.key)->check(not_empty_check());
  add_value(command, "qpos", "LIST", help.qpos)->check(number_list_check());
  add_value(command, "qvel", "LIST", help.qvel)->check(number_list_check());
  add_value(command, "ctrl", "LIST", help.ctrl)->check(number_list_check());
}

Args::Args(const CLI::App& command) : command_(&command) {
  for (const CLI::Option* o : command.get_options()) {
    if (!o->get_positional()) continue;
    for (const std::string& value : o->results()) positional_.push_back(value);
  }
}

const CLI::Option& Args::option(const std::string& name) const {
  return *command_->get_option("--" + name);  // throws CLI::OptionNotFound: a name not declared
}

bool Args::has(const std::string& name) const { return option(name).count() > 0; }

std::vector<std::string> Args::get_all(const std::string& name) const {
  return option(name).results();
}

std::string Args::get(const std::string& name, const std::string& fallback) const {
  const std::vector<std::string>& values = option(name).results();
  return values.empty() ? fallback : values.back();
}

double Args::get_double(const std::string& name, double fallback) const {
  if (!has(name)) return fallback;
  const std::string text = get(name);
  const std::string error = number_error(text);
  if (!error.empty()) unchecked(name, error);
  return std::strtod(text.c_str(), nullptr);
}

long Args::get_long(const std::string& name, long fallback) const {
  if (!has(name)) return fallback;
  const std::string text = get(name);
  const std::string error = whole_number_error(text);
  if (!error.empty()) unchecked(name, error);
  return std::strtol(text.c_str(), nullptr, 10);
}

Eigen::VectorXd Args::get_vector(const std::string& name, int n,
                                 const Eigen::VectorXd& fallback) const {
  if (!has(name)) return fallback;
  std::vector<double> xs;
  for (const std::string& item : split_list(get(name))) {
    const std::string error = number_error(item);
    if (!error.empty()) unchecked(name, error);
    xs.push_back(std::strtod(item.c_str(), nullptr));
  }
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

Invocation begin(const char* command, const Args& args,
                 const std::function<void(const Args&)>& check) {
  if (check) check(args);
  std::string path = args.positional().at(0);
  Model model = load_model(command, path);
  return Invocation{args, std::move(path), std::move(model)};
}

}  // namespace lever::cli
