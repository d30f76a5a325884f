// Run a program the way a shell would, without a shell: its stdout and stderr captured apart,
// its exit status or the signal that ended it, its wall time and its peak memory, and a time
// limit after which it is killed.
#pragma once

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace lever::test {

struct Process {
  std::string out, err;  ///< what it printed on stdout and stderr
  int status = -1;       ///< exit status; -1 if it did not exit normally
  int signal = 0;        ///< the signal that ended it, 0 if none
  bool timed_out = false;
  double seconds = 0;   ///< wall time
  long max_rss_kb = 0;  ///< peak resident memory
};

inline std::string slurp(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// Run argv[0] with the arguments argv[1..]; kill it after `limit_seconds`.
inline Process run_process(const std::vector<std::string>& argv, double limit_seconds) {
  Process p;
  static int counter = 0;
  const std::filesystem::path dir = std::filesystem::temp_directory_path();
  const std::string stem =
      "lever-hostile-" + std::to_string(getpid()) + "-" + std::to_string(++counter);
  const std::filesystem::path out = dir / (stem + ".out"), err = dir / (stem + ".err");

  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 1, out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
  posix_spawn_file_actions_addopen(&actions, 2, err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
  std::vector<char*> args;
  args.reserve(argv.size() + 1);
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);

  const auto start = std::chrono::steady_clock::now();
  pid_t pid = 0;
  const int spawned = posix_spawn(&pid, args[0], &actions, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (spawned != 0) {
    p.err = "cannot start " + argv[0];
    return p;
  }
  int raw = 0;
  rusage usage{};
  while (true) {
    const pid_t done = wait4(pid, &raw, WNOHANG, &usage);
    if (done == pid) break;
    const double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (elapsed > limit_seconds && !p.timed_out) {
      p.timed_out = true;
      kill(pid, SIGKILL);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  p.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  p.max_rss_kb = usage.ru_maxrss;
  if (WIFEXITED(raw)) p.status = WEXITSTATUS(raw);
  if (WIFSIGNALED(raw)) p.signal = WTERMSIG(raw);
  p.out = slurp(out);
  p.err = slurp(err);
  std::filesystem::remove(out);
  std::filesystem::remove(err);
  return p;
}

}  // namespace lever::test
