#include "child_process.h"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

extern char** environ;

namespace swum::test {

ChildProcess::ChildProcess(std::vector<std::string> argv, bool capture_stdout) : argv_(std::move(argv)) {
  if (argv_.empty()) throw std::runtime_error("ChildProcess: empty argv");
  int pipefd[2] = {-1, -1};
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  if (capture_stdout) {
    if (::pipe2(pipefd, O_CLOEXEC) != 0) throw std::runtime_error("pipe2 failed: " + std::string(std::strerror(errno)));
    posix_spawn_file_actions_adddup2(&fa, pipefd[1], STDOUT_FILENO);
  }
  std::vector<char*> args;
  for (auto& a : argv_) args.push_back(a.data());
  args.push_back(nullptr);
  const int rc = posix_spawnp(&pid_, args[0], &fa, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&fa);
  if (capture_stdout) {
    ::close(pipefd[1]);
    out_fd_ = pipefd[0];
  }
  if (rc != 0) {
    if (out_fd_ >= 0) ::close(out_fd_);
    throw std::runtime_error("cannot start '" + argv_[0] + "': " + std::strerror(rc));
  }
  pidfd_ = static_cast<int>(::syscall(SYS_pidfd_open, pid_, 0));
  if (pidfd_ < 0) {
    const int e = errno;
    ::kill(pid_, SIGKILL);
    ::waitpid(pid_, nullptr, 0);
    reaped_ = true;
    throw std::runtime_error("pidfd_open failed: " + std::string(std::strerror(e)));
  }
}

ChildProcess::~ChildProcess() {
  if (!reaped_ && pid_ > 0) {
    ::kill(pid_, SIGKILL);  // only the child we started, by its pid
    ::waitpid(pid_, nullptr, 0);
  }
  if (pidfd_ >= 0) ::close(pidfd_);
  if (out_fd_ >= 0) ::close(out_fd_);
}

std::string ChildProcess::command() const {
  std::string s;
  for (const auto& a : argv_) s += (s.empty() ? "" : " ") + a;
  return s;
}

std::optional<int> ChildProcess::wait(std::chrono::milliseconds timeout) {
  if (reaped_) throw std::logic_error("ChildProcess::wait called twice");
  pollfd pfd{pidfd_, POLLIN, 0};
  int r;
  do {
    r = ::poll(&pfd, 1, static_cast<int>(timeout.count()));
  } while (r < 0 && errno == EINTR);
  if (r == 0) return std::nullopt;
  int status = 0;
  if (::waitpid(pid_, &status, 0) != pid_)
    throw std::runtime_error("waitpid failed: " + std::string(std::strerror(errno)));
  reaped_ = true;
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  return 128 + WTERMSIG(status);
}

std::string ChildProcess::read_stdout(std::chrono::milliseconds timeout) {
  std::string out;
  if (out_fd_ < 0) return out;
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  for (;;) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline -
                                                                            std::chrono::steady_clock::now());
    if (left.count() <= 0) return out;
    pollfd pfd{out_fd_, POLLIN, 0};
    const int r = ::poll(&pfd, 1, static_cast<int>(left.count()));
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0) return out;
    char buf[512];
    const ssize_t n = ::read(out_fd_, buf, sizeof buf);
    if (n <= 0) return out;  // EOF
    out.append(buf, static_cast<std::size_t>(n));
  }
}

std::optional<int> run(std::vector<std::string> argv, std::chrono::milliseconds timeout) {
  ChildProcess p(std::move(argv), false);
  return p.wait(timeout);
}

}  // namespace swum::test
