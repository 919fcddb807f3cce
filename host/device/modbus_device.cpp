// The Modbus adapter of host/device.h (libmodbus client, TCP or RTU). Register addresses and
// scaling come from the emulator's register map (firmware_sim/register_map.h), which a test
// keeps in agreement with config/modbus_registers.json: one definition for both ends.
#include "device/modbus_device.h"

#include <modbus.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstring>

#include "modbus_server.h"  // parse_modbus_endpoint
#include "register_map.h"

namespace swum::host {
namespace {

namespace holding = emu::modbus::holding;
namespace input = emu::modbus::input;

std::uint32_t get_u32(const std::uint16_t* r, std::uint16_t address) {
  return (static_cast<std::uint32_t>(r[address]) << 16) | r[address + 1];
}
std::int32_t get_i32(const std::uint16_t* r, std::uint16_t address) {
  return static_cast<std::int32_t>(get_u32(r, address));
}
void put_u32(std::uint16_t* r, std::uint16_t address, std::uint32_t value) {
  r[address] = static_cast<std::uint16_t>(value >> 16);
  r[address + 1] = static_cast<std::uint16_t>(value & 0xFFFFU);
}
std::uint16_t to_register(double value, double lo, double hi, const char* what) {
  if (!std::isfinite(value) || value < lo || value > hi) {
    throw DeviceError(std::string(what) + " " + std::to_string(value) + " does not fit the register (" +
                      std::to_string(lo) + ".." + std::to_string(hi) + ")");
  }
  return static_cast<std::uint16_t>(static_cast<std::int32_t>(std::lround(value)) & 0xFFFF);
}

}  // namespace

ModbusDevice::ModbusDevice(const std::string& endpoint_text, const DeviceTimeouts& timeouts)
    : endpoint_text_(endpoint_text) {
  emu::ModbusEndpoint endpoint;
  const std::string problem = emu::parse_modbus_endpoint(endpoint_text, endpoint);
  if (!problem.empty()) throw std::invalid_argument("--modbus: " + problem);
  if (endpoint.tcp && endpoint.port == 0) throw std::invalid_argument("--modbus: port 0 is not a device address");
  context_ = endpoint.tcp ? modbus_new_tcp(endpoint.host.c_str(), endpoint.port)
                          : modbus_new_rtu(endpoint.device.c_str(), endpoint.baud, 'N', 8, 1);
  if (context_ == nullptr) {
    throw DeviceError("modbus " + endpoint_text + ": cannot create the client: " + std::strerror(errno));
  }
  modbus_set_slave(context_, 1);
  // The connect timeout of a TCP client is libmodbus' response timeout (it waits for the
  // socket to become writable with it), so set the connect timeout first.
  set_timeout(timeouts.connect);
  if (modbus_connect(context_) != 0) {
    const int error = errno;
    modbus_free(context_);
    context_ = nullptr;
    throw DeviceError("modbus " + endpoint_text + ": cannot connect: " + std::strerror(error) +
                      (error == ECONNREFUSED ? " (is swum-emu or the board listening there?)" : ""));
  }
  // Prove the device answers before anyone relies on it: the first answer gets the connect
  // timeout (a device that has just been started may still be busy), later ones the response one.
  (void)read();
  set_timeout(timeouts.response);
}

ModbusDevice::~ModbusDevice() {
  if (context_ != nullptr) {
    modbus_close(context_);
    modbus_free(context_);
  }
}

void ModbusDevice::set_timeout(std::chrono::milliseconds timeout) {
  const auto ms = timeout.count();
  modbus_set_response_timeout(context_, static_cast<std::uint32_t>(ms / 1000),
                              static_cast<std::uint32_t>((ms % 1000) * 1000));
}

std::string ModbusDevice::name() const { return "modbus " + endpoint_text_; }

void ModbusDevice::fail(const std::string& what) const {
  const int error = errno;
  std::string detail = modbus_strerror(error);
  if (error == ETIMEDOUT) detail = "no answer within the response timeout";
  throw DeviceError(name() + ": " + what + " failed: " + detail);
}

void ModbusDevice::write_holding(std::uint16_t address, const std::uint16_t* values, int count,
                                 const std::string& what) {
  if (modbus_write_registers(context_, address, count, values) != count) {
    const int error = errno;
    // An exception answer (e.g. ILLEGAL DATA VALUE): the device keeps the reason.
    if (error == EMBXILVAL || error == EMBXILADD || error == EMBXSBUSY) {
      std::uint16_t reason = 0;
      const bool known = modbus_read_input_registers(context_, input::kLastReject, 1, &reason) == 1;
      throw DeviceError(name() + ": " + what + " rejected: " + modbus_strerror(error) +
                        (known ? " (reason " + reject_reason_name(reason) + ")" : ""));
    }
    errno = error;
    fail(what);
  }
}

void ModbusDevice::set_drive(const DriveSetpoint& s) {
  std::array<std::uint16_t, 5> r{};  // holding 1..5: frequency (2), amplitude, phase, load
  const double frequency_mhz = std::round(s.frequency_hz * 1e3);
  if (!std::isfinite(frequency_mhz) || frequency_mhz < 0.0 || frequency_mhz > 4294967295.0) {
    throw DeviceError("frequency " + std::to_string(s.frequency_hz) + " Hz does not fit the register");
  }
  put_u32(r.data(), 0, static_cast<std::uint32_t>(frequency_mhz));
  r[2] = to_register(s.vpp * 10.0, 0.0, 65535.0, "amplitude (0.1 Vpp)");
  r[3] = to_register(s.phase_deg * 100.0, -32768.0, 32767.0, "phase (0.01 deg)");
  r[4] = to_register(s.load_n * 1000.0, -32768.0, 32767.0, "load (mN)");
  write_holding(holding::kFrequency, r.data(), static_cast<int>(r.size()), "drive setpoint write");
}

void ModbusDevice::set_slew(double frequency_hz_per_s, double vpp_per_s) {
  std::array<std::uint16_t, 4> r{};
  for (double v : {frequency_hz_per_s, vpp_per_s}) {
    if (!std::isfinite(v) || v < 0.0 || v > 4294967295.0) throw DeviceError("slew limit out of range");
  }
  // Rounded down, never to 0 (0 = unlimited): the device must never ramp faster than asked.
  auto units = [](double v) { return v > 0.0 ? std::max<std::uint32_t>(1, static_cast<std::uint32_t>(v)) : 0U; };
  put_u32(r.data(), 0, units(frequency_hz_per_s));
  put_u32(r.data(), 2, units(vpp_per_s));
  write_holding(holding::kFrequencySlew, r.data(), static_cast<int>(r.size()), "slew limit write");
}

void ModbusDevice::command(DeviceAction action) {
  std::uint16_t code = 0;
  switch (action) {
    case DeviceAction::keep_alive: code = 0; break;
    case DeviceAction::enable: code = 1; break;
    case DeviceAction::disable: code = 2; break;
    case DeviceAction::reset_fault: code = 3; break;
  }
  write_holding(holding::kCommand, &code, 1, "command write");
}

DeviceTelemetry ModbusDevice::read() {
  std::array<std::uint16_t, input::kCount> r{};
  if (modbus_read_input_registers(context_, 0, input::kCount, r.data()) != input::kCount) {
    fail("telemetry read");
  }
  DeviceTelemetry t;
  t.received = std::chrono::steady_clock::now();
  t.device_time_s = get_u32(r.data(), input::kSimTime) * 1e-3;
  t.state = r[input::kState];
  t.fault_code = r[input::kFault];
  t.enable_line = (r[input::kStatus] & (1U << 2)) != 0;
  t.drive_on = (r[input::kStatus] & (1U << 3)) != 0;
  t.last_reject = r[input::kLastReject];
  t.reject_count = get_u32(r.data(), input::kRejectCount);
  t.reject_count_modulus = 0;  // full 32 bits
  t.speed_mm_s = get_i32(r.data(), input::kSpeed) * 1e-3;
  t.position_mm = get_i32(r.data(), input::kPosition) * 1e-3;
  t.tip_normal_um = r[input::kTipNormal] * 1e-3;
  t.tip_tangential_um = r[input::kTipTangential] * 1e-3;
  t.frequency_hz = get_u32(r.data(), input::kFrequencyOut) * 1e-3;
  t.vpp = r[input::kAmplitudeOut] * 0.1;
  t.phase_deg = static_cast<std::int16_t>(r[input::kPhaseOut]) * 0.01;
  t.load_n = static_cast<std::int16_t>(r[input::kLoadOut]) * 1e-3;
  t.lateness_p99_us = r[input::kLatenessP99];
  t.lateness_max_us = r[input::kLatenessMax];
  t.overruns = get_u32(r.data(), input::kOverruns);
  return t;
}

}  // namespace swum::host
