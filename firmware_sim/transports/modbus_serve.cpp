#include "transports/modbus_serve.h"

#include "core/lockstep_clock.h"

#include <time.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstring>

#include "modbus_codec.h"

namespace swum::emu {

std::string errno_text(const char* call, int e) { return std::string(call) + ": " + std::strerror(e); }

namespace {

// A scenario's communication faults, after the request was processed: false when its reply is
// withheld (modbus_drop: the next N requests; telemetry_silence: FC04 reads); a modbus_delay
// holds the reply back by delay_ms of emulated time (lockstep: the motor runs on that many ticks
// while the controller waits; wall time: delay_ms / speedup).
bool reply_allowed(SharedState& shared, std::uint8_t function, ModbusStats& stats, const SteppingHook& stepping) {
  if (shared.modbus_faults.take_drop()) {
    stats.withheld_replies.fetch_add(1, std::memory_order_relaxed);
    return false;
  }
  if (function == protocol::modbus::kReadInputRegisters && shared.telemetry_silent.load(std::memory_order_relaxed)) {
    stats.withheld_replies.fetch_add(1, std::memory_order_relaxed);
    return false;
  }
  const double delay_ms = shared.modbus_faults.delay_ms();
  if (delay_ms > 0.0) {
    stats.delayed_replies.fetch_add(1, std::memory_order_relaxed);
    if (stepping && !stepping(true)) return false;  // the delay is the device's: no deadline on it
    if (shared.lockstep != nullptr) {
      const auto ticks = static_cast<std::uint64_t>(std::llround(delay_ms * 1e-3 * shared.tick_hz));
      if (ticks > 0) shared.lockstep->advance(ticks);
    } else if (shared.speedup > 0.0) {
      const auto ns = static_cast<long long>(delay_ms * 1e6 / shared.speedup);
      timespec pause = to_timespec(ns);
      while (nanosleep(&pause, &pause) != 0 && errno == EINTR) {
      }
    }
    if (stepping && !stepping(false)) return false;
  }
  return true;
}

}  // namespace

bool serve(modbus_t* ctx, const std::uint8_t* adu, int length, int checksum_length, modbus_mapping_t* map,
           SharedState& shared, const AmplifierLimits& limits, ModbusStats& stats, bool surplus,
           const SteppingHook& stepping) {
  stats.requests.fetch_add(1, std::memory_order_relaxed);
  const int header = modbus_get_header_length(ctx);
  const int pdu_length = length - header - checksum_length;
  if (pdu_length < 1) return true;
  const std::span<const std::uint8_t> pdu(adu + header, static_cast<std::size_t>(pdu_length));

  protocol::modbus::Request request;
  Reason reason = Reason::none;
  std::uint8_t exception = protocol::modbus::parse_request(pdu, request, &reason);
  if (surplus && exception == protocol::modbus::kNoException) {
    exception = protocol::modbus::kIllegalDataValue;
    reason = Reason::wrong_length;
  }
  protocol::modbus::Decision decision;
  if (exception == protocol::modbus::kNoException) {
    decision = protocol::modbus::decide(request, limits);
    exception = decision.exception;
    reason = decision.reason;
    if (exception == protocol::modbus::kNoException && decision.advance_ticks != 0 && shared.lockstep == nullptr) {
      exception = protocol::modbus::kIllegalDataValue;  // nothing of the request is applied
      reason = Reason::clock_not_external;
    }
  }
  if (exception == protocol::modbus::kNoException && decision.has_command) {
    decision.command.accepted_ns = now_ns();
    if (shared.submit(decision.command) != Reason::none) exception = protocol::modbus::kServerDeviceBusy;
  }
  if (exception == protocol::modbus::kNoException && decision.advance_ticks != 0) {
    // The command above is queued first, so the first of these ticks applies it.
    if (stepping && !stepping(true)) return false;
    const bool ran = shared.lockstep->advance(decision.advance_ticks);
    if (stepping && !stepping(false)) return false;
    if (!ran) exception = protocol::modbus::kServerDeviceFailure;  // the emulator stopped first
  }
  if (!reply_allowed(shared, pdu[0], stats, stepping)) return true;  // a scenario's communication fault
  if (exception != protocol::modbus::kNoException) {
    stats.exceptions.fetch_add(1, std::memory_order_relaxed);
    if (exception != protocol::modbus::kServerDeviceBusy && exception != protocol::modbus::kServerDeviceFailure)
      shared.rejects.record(reason, CommandSource::modbus);
    if (pdu[0] & 0x80) {
      // libmodbus answers function + 0x80 in one byte: a code that has the top bit already
      // (128-255, those of exception replies) would come back as function - 128, e.g. 0x84 as
      // "04 01", a malformed FC04 reply. With the bit cleared in the request it gives function | 0x80.
      std::array<std::uint8_t, 8> head{};  // the MBAP header (7) or the RTU unit id (1), then the code
      if (header + 1 > static_cast<int>(head.size())) return false;
      std::copy_n(adu, header + 1, head.begin());
      head[static_cast<std::size_t>(header)] &= 0x7F;
      return modbus_reply_exception(ctx, head.data(), exception) != -1;
    }
    return modbus_reply_exception(ctx, adu, exception) != -1;
  }
  const Telemetry t = shared.telemetry.load();
  if (request.function == protocol::modbus::kReadInputRegisters) {
    const RejectSnapshot rejects{static_cast<Reason>(shared.rejects.last_reason.load(std::memory_order_relaxed)),
                                 shared.rejects.count.load(std::memory_order_acquire)};
    protocol::modbus::fill_input(t, rejects,
                                 std::span<std::uint16_t, protocol::modbus::input::kCount>(
                                     map->tab_input_registers, protocol::modbus::input::kCount));
  } else {
    protocol::modbus::fill_holding(t, std::span<std::uint16_t, protocol::modbus::holding::kCount>(
                                          map->tab_registers, protocol::modbus::holding::kCount));
  }
  return modbus_reply(ctx, adu, length, map) != -1;
}

}  // namespace swum::emu
