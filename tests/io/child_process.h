// Test helper: start a program (argv, PATH lookup), optionally capturing its stdout, wait for it
// with a deadline through a pidfd (no sleeps), and stop it by its pid if it outlives the test.
#pragma once

#include <sys/types.h>

#include <chrono>
#include <optional>
#include <string>
#include <vector>

namespace swum::test {

class ChildProcess {
 public:
  // Throws std::runtime_error naming the program when it cannot be started.
  ChildProcess(std::vector<std::string> argv, bool capture_stdout);
  ~ChildProcess();  // SIGKILLs and reaps the child if still running
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  pid_t pid() const { return pid_; }
  // Exit status (WEXITSTATUS, or 128+signal), nullopt on timeout.
  std::optional<int> wait(std::chrono::milliseconds timeout);
  // Reads stdout until EOF or timeout; returns what was read.
  std::string read_stdout(std::chrono::milliseconds timeout);
  std::string command() const;

 private:
  std::vector<std::string> argv_;
  pid_t pid_ = -1;
  int pidfd_ = -1;
  int out_fd_ = -1;
  bool reaped_ = false;
};

// Runs a program to completion (stdout discarded); returns its exit status, nullopt on timeout.
std::optional<int> run(std::vector<std::string> argv, std::chrono::milliseconds timeout);

// Waits until `ready()` holds or the deadline passes, checking it at a 1 ms pace. For readiness
// that only shows as kernel state (e.g. a socket appearing in /proc/net/can/rcvlist_*).
template <class Pred>
bool wait_until(Pred ready, std::chrono::milliseconds timeout);

}  // namespace swum::test

#include <poll.h>

namespace swum::test {
template <class Pred>
bool wait_until(Pred ready, std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (!ready()) {
    if (std::chrono::steady_clock::now() >= deadline) return false;
    ::poll(nullptr, 0, 1);
  }
  return true;
}
}  // namespace swum::test
