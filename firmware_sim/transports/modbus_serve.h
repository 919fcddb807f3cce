// The request handling both Modbus servers share (TCP: modbus_tcp_server.cpp, RTU:
// modbus_rtu_server.cpp): one framed request is checked by protocol/modbus_codec (pure),
// accepted writes go to the command queue, reads are served from the latest telemetry snapshot,
// a lockstep step waits for its ticks, and a scenario's communication faults withhold or delay
// the reply. The framing, the deadlines and the connections are each server's own.
#pragma once

#include <modbus.h>

#include <cstdint>
#include <functional>
#include <string>

#include "core/amplifier.h"
#include "core/monotonic_clock.h"
#include "core/shared_state.h"
#include "transports/modbus_server.h"

namespace swum::emu {

// "call: strerror(e)", for the servers' one-line messages.
std::string errno_text(const char* call, int e);

// The servers' deadlines are unsigned nanoseconds on the shared monotonic clock.
inline std::uint64_t now_ns() { return static_cast<std::uint64_t>(monotonic_ns()); }
inline std::uint64_t ms_to_ns(int ms) { return static_cast<std::uint64_t>(ms) * 1'000'000ULL; }

// `stepping(true)` before a lockstep step waits for the loop, `stepping(false)` after it (the TCP
// server suspends the connection's deadlines meanwhile); false: the connection is being closed.
using SteppingHook = std::function<bool(bool)>;

// One request: validate, queue writes, serve reads. False when the connection should close.
// `adu` holds `length` bytes: the header (MBAP or unit id), the PDU, `checksum_length` bytes of
// CRC (RTU: 2, TCP: 0); `map` is the server's libmodbus mapping the reply is built in.
// `surplus`: the MBAP length counted bytes after what the function code frames; a supported
// function code with them is malformed (exception 03, wrong length), an unsupported one is
// refused as such (01).
bool serve(modbus_t* ctx, const std::uint8_t* adu, int length, int checksum_length, modbus_mapping_t* map,
           SharedState& shared, const AmplifierLimits& limits, ModbusStats& stats, bool surplus = false,
           const SteppingHook& stepping = {});

}  // namespace swum::emu
