// Child processes for end-to-end tests: start a binary, capture its output, stop it.
#pragma once

#include <sys/types.h>

#include <chrono>
#include <string>
#include <vector>

namespace mesh4d::testing {

struct RunResult {
  int exit_code = -1;  // -1 when killed by a signal or timed out
  std::string output;  // stdout and stderr together
};

/// Runs `argv` to completion (killed after `timeout`) and returns its exit code and output.
RunResult run_command(const std::vector<std::string>& argv,
                      std::chrono::milliseconds timeout = std::chrono::seconds(30));

/// A background process, killed (SIGKILL) on destruction if still running.
class ChildProcess {
 public:
  ChildProcess(const std::vector<std::string>& argv, const std::string& log_path);
  ~ChildProcess();
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  pid_t pid() const { return pid_; }
  /// Sends `signal` and waits up to `timeout`; returns the exit code, or -1 if it did not exit.
  int stop(int signal, std::chrono::milliseconds timeout = std::chrono::seconds(10));

 private:
  pid_t pid_ = -1;
};

/// Waits until `path` exists and is non-empty, or `timeout` passes; returns its contents or "".
std::string wait_for_file(const std::string& path, std::chrono::milliseconds timeout);

/// A fresh directory under the system's temporary folder, removed with its contents when the
/// program ends (or at remove_temp_dirs()) unless the predicate of keep_temp_dirs_if() says to
/// keep them.
std::string make_temp_dir(const std::string& prefix);
/// The tests keep them when a test failed (e2e_main.cpp).
void keep_temp_dirs_if(bool (*keep)());
/// Removes the folders made so far, unless the predicate says to keep them.
void remove_temp_dirs();

}  // namespace mesh4d::testing
