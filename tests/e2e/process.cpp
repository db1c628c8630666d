#include "process.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <thread>

extern char** environ;

namespace mesh4d::testing {
namespace {

pid_t spawn(const std::vector<std::string>& argv, const std::string& out_path) {
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, out_path.c_str(),
                                   O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  pid_t pid = -1;
  const int rc = posix_spawn(&pid, args[0], &actions, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (rc != 0) throw std::runtime_error("cannot start " + argv[0]);
  return pid;
}

// Polls waitpid until the child exits or the timeout passes; returns the exit code, -1 otherwise.
int wait_exit(pid_t pid, std::chrono::milliseconds timeout, bool* exited) {
  const auto end = std::chrono::steady_clock::now() + timeout;
  int status = 0;
  while (true) {
    const pid_t r = waitpid(pid, &status, WNOHANG);
    if (r == pid) {
      *exited = true;
      return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    }
    if (std::chrono::steady_clock::now() > end) {
      *exited = false;
      return -1;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
}

std::string read_file(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace

RunResult run_command(const std::vector<std::string>& argv, std::chrono::milliseconds timeout) {
  const std::string out = make_temp_dir("mesh4d-run") + "/output.txt";
  const pid_t pid = spawn(argv, out);
  bool exited = false;
  RunResult result;
  result.exit_code = wait_exit(pid, timeout, &exited);
  if (!exited) {
    kill(pid, SIGKILL);
    waitpid(pid, nullptr, 0);
  }
  result.output = read_file(out);
  return result;
}

ChildProcess::ChildProcess(const std::vector<std::string>& argv, const std::string& log_path)
    : pid_(spawn(argv, log_path)) {}

ChildProcess::~ChildProcess() {
  if (pid_ > 0) stop(SIGKILL, std::chrono::seconds(5));
}

int ChildProcess::stop(int signal, std::chrono::milliseconds timeout) {
  if (pid_ <= 0) return -1;
  kill(pid_, signal);
  bool exited = false;
  const int code = wait_exit(pid_, timeout, &exited);
  if (exited) pid_ = -1;
  return code;
}

std::string wait_for_file(const std::string& path, std::chrono::milliseconds timeout) {
  const auto end = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < end) {
    std::error_code ec;
    if (std::filesystem::file_size(path, ec) > 0 && !ec) return read_file(path);
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return "";
}

namespace {
bool (*g_keep_temp_dirs)() = nullptr;
}  // namespace

void keep_temp_dirs_if(bool (*keep)()) {
  g_keep_temp_dirs = keep;
}

namespace {

// The folders made so far, removed when the program ends (or before: remove_temp_dirs).
struct TempDirs {
  std::mutex mutex;
  std::vector<std::string> dirs;
  void remove() {
    std::lock_guard lock(mutex);
    if (!(g_keep_temp_dirs && g_keep_temp_dirs()))
      for (const auto& dir : dirs) {
        std::error_code ec;
        std::filesystem::remove_all(dir, ec);
      }
    dirs.clear();
  }
  ~TempDirs() { remove(); }
};

TempDirs& temp_dirs() {
  static TempDirs dirs;
  return dirs;
}

}  // namespace

std::string make_temp_dir(const std::string& prefix) {
  // Each holds a server's job store and meshes, and left behind they fill /tmp (75 GB once).
  std::string pattern = (std::filesystem::temp_directory_path() / (prefix + "-XXXXXX")).string();
  if (mkdtemp(pattern.data()) == nullptr) throw std::runtime_error("mkdtemp failed");
  TempDirs& made = temp_dirs();
  std::lock_guard lock(made.mutex);
  made.dirs.push_back(pattern);
  return pattern;
}

void remove_temp_dirs() {
  temp_dirs().remove();
}

}  // namespace mesh4d::testing
