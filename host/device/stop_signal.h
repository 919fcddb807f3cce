// Ctrl-C / SIGTERM for the live subcommands: the handler only sets a flag (async-signal-safe);
// the loops check it between device calls, switch the drive off and flush their files. The
// handlers are installed without SA_RESTART so a blocked socket call returns at once (EINTR).
#pragma once

namespace swum::host {

class StopSignal {
 public:
  StopSignal();   // installs the SIGINT and SIGTERM handlers
  ~StopSignal();  // restores the previous handlers
  StopSignal(const StopSignal&) = delete;
  StopSignal& operator=(const StopSignal&) = delete;
  static bool requested();
  static void reset_for_tests();
};

}  // namespace swum::host
