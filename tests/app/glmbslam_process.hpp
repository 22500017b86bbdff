#pragma once
// Runs the glmbslam executable from a test as a child process: start it (optionally with a file-size limit,
// which makes every write beyond it fail like a full disk), signal it, wait for it.
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <string>
#include <vector>

#include "support/test_data.hpp"

namespace glmbslam::test {

/// Starts `glmbslam args...` with stdout and stderr sent to `log`; `max_file_bytes` > 0 limits the size of
/// every file the process writes (RLIMIT_FSIZE; SIGXFSZ ignored, so writes fail with EFBIG). Returns the pid.
inline pid_t start_glmbslam(const std::vector<std::string>& args, const std::filesystem::path& log,
                            rlim_t max_file_bytes = 0) {
  std::vector<std::string> all = {glmbslam_binary().string()};
  all.insert(all.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& a : all) argv.push_back(a.data());
  argv.push_back(nullptr);
  const std::string log_path = log.string();
  const pid_t pid = fork();
  if (pid == 0) {
    if (freopen(log_path.c_str(), "w", stdout) == nullptr || dup2(fileno(stdout), STDERR_FILENO) < 0)
      _exit(127);
    if (max_file_bytes > 0) {
      signal(SIGXFSZ, SIG_IGN);
      const rlimit limit{max_file_bytes, max_file_bytes};
      setrlimit(RLIMIT_FSIZE, &limit);
    }
    execv(argv[0], argv.data());
    _exit(127);
  }
  return pid;
}

/// Waits for `pid`; returns its wait status.
inline int wait_for(pid_t pid) {
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
  }
  return status;
}

/// Runs `glmbslam args...` to the end; returns its exit code (128 + signal if killed by one).
inline int run_glmbslam(const std::vector<std::string>& args, const std::filesystem::path& log,
                        rlim_t max_file_bytes = 0) {
  const int status = wait_for(start_glmbslam(args, log, max_file_bytes));
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

}  // namespace glmbslam::test
