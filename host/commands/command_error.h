// Errors a subcommand reports to the user: one line on stderr and a chosen exit code.
#pragma once

#include <stdexcept>
#include <string>

namespace swum::host {

enum ExitCode : int {
  kExitOk = 0,
  kExitFailure = 1,        // bad input file, I/O error, anything the user must fix
  kExitUsage = 2,          // bad command-line arguments
  kExitDiverged = 3,       // the simulation blew up; nothing was printed as a number
  kExitInterrupted = 130,  // Ctrl-C / SIGTERM on a live command: drive off, files flushed
};

class CommandError : public std::runtime_error {
 public:
  CommandError(const std::string& message, int exit_code = kExitFailure)
      : std::runtime_error(message), exit_code_(exit_code) {}
  int exit_code() const { return exit_code_; }

 private:
  int exit_code_;
};

// A failure already reported on stderr by another process of the same run (a rank of
// `mpirun ... swum population`): main exits with the code and prints nothing.
class ReportedFailure : public CommandError {
 public:
  explicit ReportedFailure(int exit_code) : CommandError("", exit_code) {}
};

}  // namespace swum::host
