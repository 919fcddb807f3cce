// The Modbus adapter of host/device/device.h (libmodbus client, TCP or RTU). Register
// addresses, scales and both directions of the encoding come from the protocol library
// (protocol/modbus_codec.h), the same code the emulator's server runs; a test keeps it in
// agreement with config/modbus_registers.json.
#include "device/modbus_device.h"

#include <modbus.h>

#include <array>
#include <cerrno>
#include <cstring>

#include "endpoint.h"
#include "modbus_codec.h"

namespace swum::host {
namespace {

namespace modbus = protocol::modbus;
namespace holding = modbus::holding;
namespace input = modbus::input;

}  // namespace

ModbusDevice::ModbusDevice(const std::string& endpoint_text, const DeviceTimeouts& timeouts)
    : endpoint_text_(endpoint_text) {
  protocol::ModbusEndpoint endpoint;
  const std::string problem = protocol::parse_modbus_endpoint(endpoint_text, endpoint);
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
  // When it does not, the destructor will not run: close the connection here.
  try {
    lockstep_ = read().lockstep;
  } catch (...) {
    modbus_close(context_);
    modbus_free(context_);
    context_ = nullptr;
    throw;
  }
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
  std::array<std::uint16_t, modbus::kDriveWriteCount> r{};
  const std::string problem = modbus::encode_drive_write(s.frequency_hz, s.amplitude_v, s.phase_deg, s.load_n, r);
  if (!problem.empty()) throw DeviceError(problem);
  write_holding(holding::kFrequency, r.data(), static_cast<int>(r.size()), "drive setpoint write");
}

void ModbusDevice::set_slew(double frequency_hz_per_s, double amplitude_v_per_s) {
  std::array<std::uint16_t, modbus::kSlewWriteCount> r{};
  const std::string problem = modbus::encode_slew_write(frequency_hz_per_s, amplitude_v_per_s, r);
  if (!problem.empty()) throw DeviceError(problem);
  write_holding(holding::kFrequencySlew, r.data(), static_cast<int>(r.size()), "slew limit write");
}

void ModbusDevice::command(DeviceAction action) {
  const std::uint16_t value = modbus::command_code(action);
  write_holding(holding::kCommand, &value, 1, "command write");
}

// One request sets and steps (holding 0..10, the reply comes when the ticks are done), one
// reads the state after them.
DeviceTelemetry ModbusDevice::step(const DriveSetpoint& s, const DriveSlew& slew, DeviceAction action,
                                   std::uint32_t ticks) {
  protocol::AmplifierSetpoints setpoints;
  setpoints.frequency_hz = s.frequency_hz;
  setpoints.amplitude_v = s.amplitude_v;
  setpoints.phase_deg = s.phase_deg;
  setpoints.load_n = s.load_n;
  setpoints.frequency_slew_hz_per_s = slew.frequency_hz_per_s;
  setpoints.amplitude_slew_v_per_s = slew.amplitude_v_per_s;
  std::array<std::uint16_t, holding::kCount> r{};
  const std::string problem = modbus::encode_step_write(action, setpoints, ticks, r);
  if (!problem.empty()) throw DeviceError(name() + ": lockstep step: " + problem);
  write_holding(holding::kCommand, r.data(), static_cast<int>(r.size()), "lockstep step");
  return read();
}

DeviceTelemetry ModbusDevice::read() {
  std::array<std::uint16_t, input::kCount> r{};
  // One request for the whole table (51 registers, within a read's 125); a board that stops at
  // register 44 (no amplifier output registers) or 35 (no electrical port) answers it with ILLEGAL
  // DATA ADDRESS: read 0..44, then 0..35, from then on.
  if (input_count_ == 0) input_count_ = input::kCount;
  const int count = input_count_;
  if (modbus_read_input_registers(context_, 0, count, r.data()) != count) {
    if (!(count > input::kCurrentA && errno == EMBXILADD)) fail("telemetry read");
    input_count_ = count == input::kCount ? input::kAmplifierCurrentA : input::kCurrentA;
    electrical_registers_ = input_count_ > input::kCurrentA;
    return read();
  }
  const modbus::InputImage image = modbus::decode_input(r);
  const protocol::Telemetry& d = image.telemetry;
  DeviceTelemetry t;
  t.received = std::chrono::steady_clock::now();
  t.device_time_s = d.sim_time_s;
  t.tick = d.tick;
  t.lockstep = d.external_clock;
  t.state = image.state_code;
  t.fault_code = image.fault_code;
  t.enable_line = d.enable_line;
  t.drive_on = (image.status_bits & protocol::kStatusDriveOn) != 0;
  t.last_reject = image.last_reject_code;
  t.reject_count = static_cast<std::uint32_t>(image.rejects.count);
  t.reject_count_modulus = 0;  // full 32 bits
  t.speed_mm_s = image.speed_mm_s;
  t.position_mm = image.position_mm;
  t.tip_normal_um = d.tip_normal_um;
  t.tip_tangential_um = d.tip_tangential_um;
  t.frequency_hz = d.output.frequency_hz;
  t.amplitude_v = d.output.amplitude_v;
  t.phase_deg = d.output.phase_deg;
  t.load_n = d.output.load_n;
  t.lateness_p99_us = static_cast<double>(d.stats.lateness_p99_ns) / modbus::kTimingNsPerCount;
  t.lateness_max_us = static_cast<double>(d.stats.lateness_max_ns) / modbus::kTimingNsPerCount;
  t.overruns = static_cast<std::uint32_t>(d.stats.overruns);
  if (electrical_registers_) {
    t.electrical = d.electrical;
    t.stator_temperature_c = d.stator_temperature_c;
  }
  return t;
}

}  // namespace swum::host
