// Run the built `lever` executable and capture what it prints and its exit status.
#pragma once

#include <sys/wait.h>

#include <unistd.h>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

namespace lever::test {

struct Run {
  std::string out;  ///< stdout (stderr too when asked)
  int status = -1;  ///< exit status; -1 if it did not exit normally (a crash)
};

/// `lever <arguments>`; stderr is discarded unless `with_stderr`.
inline Run run_lever(const std::string& arguments, bool with_stderr = false) {
  const std::string command =
      std::string("'") + LEVER_EXE + "' " + arguments + (with_stderr ? " 2>&1" : " 2>/dev/null");
  Run run;
  std::FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return run;
  std::array<char, 4096> buffer{};
  size_t n = 0;
  while ((n = std::fread(buffer.data(), 1, buffer.size(), pipe)) > 0)
    run.out.append(buffer.data(), n);
  const int raw = pclose(pipe);
  run.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  return run;
}

/// Quote a path for the shell.
inline std::string quoted(const std::string& path) { return "'" + path + "'"; }

/// Write text to a file in the temporary directory and return its path.
inline std::string temporary_file(const std::string& name, const std::string& text) {
  // one per process: ctest runs the test cases of one executable side by side
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() / (std::to_string(::getpid()) + "-" + name);
  std::ofstream(path) << text;
  return path.string();
}

/// printf-style formatting of one number, as the check prints it.
inline std::string format(const char* spec, double x) {
  char buf[64];
  std::snprintf(buf, sizeof buf, spec, x);
  return buf;
}

}  // namespace lever::test
