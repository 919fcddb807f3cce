// `swum log`: timestamped telemetry of a live device to CSV, as a passive observer (it sends
// no commands, so the controller under test keeps the drive). Rows are written as they arrive,
// so a crash or Ctrl-C loses nothing already received; gaps are counted.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <thread>

#include "commands/command_error.h"
#include "commands/commands.h"
#include "device/device_options.h"
#include "device/stop_signal.h"
#include "output/log_table.h"
#include "output/partial_file.h"
#include "output/reports/device/log_report.h"

namespace swum::host {
namespace {

struct LogOptions {
  DeviceOptions device;
  double tick_hz = 10000.0;  // --tick-hz: lockstep (--canopen --sync-ticks)
  double duration_s = 10.0;
  double rate_hz = 100.0;
  std::string out_path;
};

void run_log(const LogOptions& o) {
  if (!(o.duration_s > 0.0)) throw std::invalid_argument("--duration-s: must be > 0");
  if (!(o.duration_s <= 1e7)) throw std::invalid_argument("--duration-s: must be <= 1e7 s");
  if (!(o.rate_hz >= 0.01 && o.rate_hz <= 10000.0))
    throw std::invalid_argument("--rate-hz: must be within 0.01..10000");
  StopSignal stop;
  const auto device = o.device.open(o.tick_hz);
  // Each row is written as it arrives (one write(2) each) to OUT.partial, renamed to OUT when
  // the log ends (--duration-s or Ctrl-C); a killed run or a device error leaves OUT.partial.
  PartialFile out(o.out_path, kLogCsvHeader);
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  const auto period = std::chrono::duration<double>(1.0 / o.rate_hz);
  // Polled protocols (Modbus): one read per period; a period without a sample is a gap.
  // Streamed protocols (CAN): every telemetry set; a jump of the device's counter is a gap.
  std::size_t samples = 0, gaps = 0, missing = 0;
  std::optional<std::uint32_t> last_counter;
  auto next = start;
  const auto end = start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(o.duration_s));
  std::string stop_reason;
  while (Clock::now() - start < std::chrono::duration<double>(o.duration_s)) {
    if (StopSignal::requested()) {
      stop_reason = "interrupted";
      break;
    }
    DeviceTelemetry t;
    try {
      t = device->read();
    } catch (const DeviceError& e) {
      if (StopSignal::requested()) continue;
      std::fprintf(stderr, "swum: the %zu samples received before the error are in %s\n", samples,
                   out.partial().c_str());
      throw;
    }
    const double host_s = std::chrono::duration<double>(t.received - start).count();
    if (t.sample_counter) {
      if (last_counter) {
        const std::uint32_t m = t.sample_counter_modulus;
        const std::uint32_t step = (*t.sample_counter + m - *last_counter) % m;
        if (step != 1) {
          ++gaps;
          missing += step == 0 ? m - 1 : step - 1;
        }
      }
      last_counter = t.sample_counter;
    }
    out.append(format_log_row(host_s, t));
    ++samples;
    if (!t.sample_counter) {
      next += std::chrono::duration_cast<Clock::duration>(period);
      const auto now = Clock::now();
      if (now > next + std::chrono::duration_cast<Clock::duration>(period)) {
        // Fell behind by whole periods: those samples are missing, not silently skipped.
        const auto behind = static_cast<std::size_t>((now - next) /
                                                     std::chrono::duration_cast<Clock::duration>(period));
        ++gaps;
        missing += behind;
        next += behind * std::chrono::duration_cast<Clock::duration>(period);
      }
      // Wait for the next poll in short naps: Ctrl-C and the end of --duration-s end it at once.
      while (Clock::now() < next && Clock::now() < end && !StopSignal::requested()) {
        std::this_thread::sleep_for(std::min<Clock::duration>(next - Clock::now(), std::chrono::milliseconds(20)));
      }
    }
  }
  out.commit();
  const double elapsed = std::chrono::duration<double>(Clock::now() - start).count();
  std::fputs(log_run_summary({samples, gaps, missing, elapsed}, device->name(), o.out_path).c_str(), stdout);
  if (!stop_reason.empty())
    throw CommandError("interrupted: " + o.out_path + " holds every sample received", kExitInterrupted);
}

}  // namespace

void add_log_command(CLI::App& app) {
  auto o = std::make_shared<LogOptions>();
  CLI::App* sub = app.add_subcommand("log", "Log a live device's telemetry to CSV (passive: sends no commands)");
  add_device_options(*sub, o->device, &o->tick_hz);
  sub->add_option("--duration-s", o->duration_s, "how long to log (s)")->capture_default_str();
  sub->add_option("--rate-hz", o->rate_hz, "poll rate for polled protocols (Modbus); CAN logs every frame set")
      ->capture_default_str();
  sub->add_option("--out", o->out_path, "output CSV")->required();
  sub->callback([o] { run_log(*o); });
}

}  // namespace swum::host
