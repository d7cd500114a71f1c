#pragma once
// Child processes for tests that must fail, not hang: a program (or this test program again, for
// one hidden test case) started with posix_spawn, waited for with a deadline and killed past it.

#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

extern char** environ;

namespace igi::testing {

/// How a child process ended.
struct ChildExit {
  bool exited = false;  ///< It called exit (else a signal ended it).
  int code = 0;         ///< Exit status if `exited`, else the signal number.
  /// "exit status N" or "signal N", for messages.
  std::string describe() const {
    return (exited ? "exit status " : "signal ") + std::to_string(code);
  }
};

/// One running child process; killed with SIGKILL and reaped on destruction if still running.
class ChildProcess {
 public:
  /// Starts `program` with `arguments` (argv[1...]) and the environment of this process plus
  /// `environment` ("NAME=value" entries, which win over inherited ones).
  ChildProcess(const std::string& program, const std::vector<std::string>& arguments,
               const std::vector<std::string>& environment = {}) {
    std::vector<std::string> argv_strings{program};
    argv_strings.insert(argv_strings.end(), arguments.begin(), arguments.end());
    std::vector<char*> argv;
    for (std::string& a : argv_strings) argv.push_back(a.data());
    argv.push_back(nullptr);
    std::vector<std::string> env_strings = environment;
    for (char** e = environ; *e != nullptr; ++e) {
      const std::string entry = *e;
      const std::string name = entry.substr(0, entry.find('='));
      bool overridden = false;
      for (const std::string& mine : environment) overridden |= mine.substr(0, mine.find('=')) == name;
      if (!overridden) env_strings.push_back(entry);
    }
    std::vector<char*> envp;
    for (std::string& e : env_strings) envp.push_back(e.data());
    envp.push_back(nullptr);
    if (const int error = ::posix_spawn(&pid_, program.c_str(), nullptr, nullptr, argv.data(), envp.data()); error != 0)
      throw std::runtime_error("posix_spawn " + program + " failed with error " + std::to_string(error));
  }
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;
  ~ChildProcess() {
    if (!exit_) {
      ::kill(pid_, SIGKILL);
      int status = 0;
      ::waitpid(pid_, &status, 0);
    }
  }

  /// The child's process id.
  pid_t pid() const noexcept { return pid_; }

  /// Sends `signal` to the child.
  void send(int signal) const { ::kill(pid_, signal); }

  /// Waits until the child ends or `deadline` passes; its exit, or nothing if still running.
  std::optional<ChildExit> wait_for(std::chrono::milliseconds deadline) {
    const auto end = std::chrono::steady_clock::now() + deadline;
    while (!exit_) {
      int status = 0;
      const pid_t done = ::waitpid(pid_, &status, WNOHANG);
      if (done == pid_) {
        exit_ = ChildExit{WIFEXITED(status), WIFEXITED(status) ? WEXITSTATUS(status) : WTERMSIG(status)};
        break;
      }
      if (std::chrono::steady_clock::now() >= end) break;
      // 5 ms between polls: fine enough for the one-second limits these tests check.
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return exit_;
  }

 private:
  pid_t pid_ = 0;
  std::optional<ChildExit> exit_;
};

/// This test program's own path, to run one of its hidden test cases as a child.
inline std::string this_program() {
  std::vector<char> path(4096);
  const ssize_t length = ::readlink("/proc/self/exe", path.data(), path.size() - 1);
  if (length <= 0) throw std::runtime_error("cannot read /proc/self/exe");
  return std::string(path.data(), std::size_t(length));
}

}  // namespace igi::testing
