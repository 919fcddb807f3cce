// The invariants of one Modbus request PDU as swum-emu serves it (firmware_sim/transports/modbus_serve.cpp:
// parse_request, then decide), shared by the PDU target and the RTU framing target.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "fuzz_check.h"
#include "modbus_codec.h"

namespace swum::fuzz {

namespace modbus = protocol::modbus;

// The PDU a client sends for `request` (function, address, quantity, byte count, values, all
// big-endian): the inverse of parse_request.
inline std::vector<std::uint8_t> serialise(const modbus::Request& r) {
  auto u16 = [](std::vector<std::uint8_t>& out, std::uint16_t v) {
    out.push_back(static_cast<std::uint8_t>(v >> 8));
    out.push_back(static_cast<std::uint8_t>(v & 0xFFU));
  };
  std::vector<std::uint8_t> pdu{r.function};
  u16(pdu, r.address);
  if (r.function == modbus::kWriteSingleRegister) {
    u16(pdu, r.values[0]);
    return pdu;
  }
  u16(pdu, r.quantity);
  if (r.function == modbus::kWriteMultipleRegisters) {
    pdu.push_back(static_cast<std::uint8_t>(2 * r.quantity));
    for (std::size_t i = 0; i < r.quantity; ++i) u16(pdu, r.values[i]);
  }
  return pdu;
}

// A write the device accepted, encoded again the way the host tool encodes set-points
// (encode_drive_write / encode_slew_write), gives back the registers the client wrote.
inline void check_controller_encodes_same_registers(const modbus::Request& r, const protocol::Command& c) {
  const unsigned first = r.address;
  const unsigned end = first + r.quantity;
  auto written = [&](unsigned a) { return r.values[a - first]; };
  auto covers = [&](unsigned a) { return a >= first && a < end; };
  std::array<std::uint16_t, modbus::kDriveWriteCount> drive{};
  const std::string drive_error = modbus::encode_drive_write(c.frequency_hz, c.amplitude_v, c.phase_deg, c.load_n,
                                                             drive);
  FUZZ_CHECK(drive_error.empty(), "accepted set-points do not encode: %s", drive_error.c_str());
  for (unsigned a = modbus::holding::kFrequency; a <= modbus::holding::kLoad; ++a) {
    if (!covers(a)) continue;
    FUZZ_CHECK(drive[a - modbus::holding::kFrequency] == written(a), "holding %u: written 0x%04X, re-encoded 0x%04X", a,
               written(a), drive[a - modbus::holding::kFrequency]);
  }
  std::array<std::uint16_t, modbus::kSlewWriteCount> slew{};
  const std::string slew_error = modbus::encode_slew_write(c.frequency_slew_hz_per_s, c.amplitude_slew_v_per_s, slew);
  FUZZ_CHECK(slew_error.empty(), "accepted slew limits do not encode: %s", slew_error.c_str());
  for (unsigned a = modbus::holding::kFrequencySlew; a < modbus::holding::kFrequencySlew + modbus::kSlewWriteCount;
       ++a) {
    if (!covers(a)) continue;
    FUZZ_CHECK(slew[a - modbus::holding::kFrequencySlew] == written(a), "holding %u: written 0x%04X, re-encoded 0x%04X",
               a, written(a), slew[a - modbus::holding::kFrequencySlew]);
  }
  if (covers(modbus::holding::kCommand)) {
    FUZZ_CHECK(modbus::command_code(c.action) == written(modbus::holding::kCommand),
               "command register %u became action %u", written(modbus::holding::kCommand),
               modbus::command_code(c.action));
  }
}

// parse_request + decide on one PDU, with every invariant checked.
inline void check_pdu(std::span<const std::uint8_t> pdu) {
  const protocol::AmplifierLimits limits{};
  modbus::Request request;
  protocol::Reason reason = protocol::Reason::none;
  const std::uint8_t exception = modbus::parse_request(pdu, request, &reason);
  if (exception != modbus::kNoException) {
    FUZZ_CHECK(exception == modbus::kIllegalFunction || exception == modbus::kIllegalDataValue,
               "parse_request answered exception %u", exception);
    FUZZ_CHECK(reason != protocol::Reason::none, "refused (exception %u) without a reason", exception);
    return;
  }
  FUZZ_CHECK(reason == protocol::Reason::none, "accepted with reason %u", static_cast<unsigned>(reason));
  const std::vector<std::uint8_t> again = serialise(request);
  FUZZ_CHECK(again.size() == pdu.size() && std::equal(again.begin(), again.end(), pdu.begin()),
             "accepted PDU of %zu bytes re-serialises to %zu different bytes", pdu.size(), again.size());

  const modbus::Decision d = modbus::decide(request, limits);
  const bool is_write = request.function == modbus::kWriteSingleRegister ||
                        request.function == modbus::kWriteMultipleRegisters;
  if (d.exception != modbus::kNoException) {
    // A refused request changes nothing: no command reaches the queue.
    FUZZ_CHECK(!d.has_command, "exception %u with a command", d.exception);
    FUZZ_CHECK(d.reason != protocol::Reason::none, "exception %u without a reason", d.exception);
    FUZZ_CHECK(d.exception == modbus::kIllegalDataAddress || d.exception == modbus::kIllegalDataValue,
               "decide answered exception %u", d.exception);
    return;
  }
  // An accepted read lies within its table: input registers 0..44 (the electrical port 36..44
  // included), holding 0..10; the emulator's image of that many registers answers it.
  if (!is_write) {
    const unsigned table = request.function == modbus::kReadInputRegisters ? modbus::input::kCount
                                                                           : modbus::holding::kCount;
    FUZZ_CHECK(request.address + request.quantity <= table, "function %u: read of %u..%u accepted (table of %u)",
               request.function, request.address, request.address + request.quantity - 1, table);
  }
  // A write carries a command unless it covers only the lockstep advance register (a step alone).
  const bool advance_only = is_write && request.address == modbus::holding::kAdvance;
  FUZZ_CHECK(d.has_command == (is_write && !advance_only), "function %u: has_command %d", request.function,
             d.has_command);
  FUZZ_CHECK(d.advance_ticks == 0 || (is_write && request.address + request.quantity > modbus::holding::kAdvance),
             "advance %u without a write of register %u", d.advance_ticks, modbus::holding::kAdvance);
  if (!d.has_command) return;
  FUZZ_CHECK(protocol::validate(d.command, limits) == protocol::Reason::none,
             "an accepted command fails validate(): %s", protocol::to_string(protocol::validate(d.command, limits)));
  FUZZ_CHECK(d.command.fields != 0, "an accepted write changes no field");
  FUZZ_CHECK(d.command.source == protocol::CommandSource::modbus, "command source %u",
             static_cast<unsigned>(d.command.source));
  check_controller_encodes_same_registers(request, d.command);
}

}  // namespace swum::fuzz
