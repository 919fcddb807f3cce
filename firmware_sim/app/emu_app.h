// swum-emu's run: the parts wired from the options (core, transports, loop), signals, the
// ready line, and the exit report (docs/emulator.md, "Readiness" and "Exit").
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "app/emu_options.h"
#include "core/loop_statistics.h"
#include "http/http_api.h"

namespace swum::emu {

// Runs the emulator until SIGINT/SIGTERM or the end of --duration-s, then prints the exit report
// to stdout and returns 0. Start-up failures (config file, option values, a port in use, no such
// CAN interface or GPIO chip) throw with one line of text; nothing has been printed to stdout
// then. Blocks SIGINT/SIGTERM in the calling thread: call it before starting any thread.
int run_emulator(const EmuOptions& options);

// What the exit report shows, taken after the loop and the transports stopped. The transport
// counters are those of the transports that ran (nullptr: not configured).
struct ExitStatistics {
  bool stopped_by_signal = false;  // otherwise --duration-s ran out
  double emulated_s = 0.0;
  double wall_s = 0.0;
  AmpState state = AmpState::disabled;
  FaultCode fault = FaultCode::none;
  double tick_hz = 0.0;
  LoopStatsSummary loop;
  std::optional<std::uint64_t> lockstep_ticks;  // --clock external: ticks stepped (no loop timing then)
  std::uint64_t resyncs = 0;
  std::uint64_t commands_applied = 0;
  std::uint64_t commands_rejected = 0;  // by the transports and the amplifier (the reject log)
  std::uint64_t queue_full = 0;
  const ModbusStats* modbus_tcp = nullptr;
  const ModbusStats* modbus_rtu = nullptr;
  const CanStats* can = nullptr;
  const HttpStats* http = nullptr;             // --http
  const Histogram* can_receive_age = nullptr;  // with `can`: bus timestamp -> read (none: empty)
  std::uint64_t can_kernel_drops = 0;          // with `can`: SO_RXQ_OVFL of the receive socket
};

// The exit report, every line ending in '\n'.
std::string format_exit_report(const ExitStatistics& s);

}  // namespace swum::emu
