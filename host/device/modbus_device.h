// Device over Modbus TCP or RTU (libmodbus client); register map: docs/protocols.md.
#pragma once

#include <cstdint>
#include <string>

#include "device/device.h"

typedef struct _modbus modbus_t;

namespace swum::host {

class ModbusDevice final : public Device {
 public:
  // "tcp://HOST:PORT" or "rtu:DEVICE:BAUD". Throws std::invalid_argument for a malformed
  // address, DeviceError when the device cannot be reached or does not answer.
  ModbusDevice(const std::string& endpoint, const DeviceTimeouts& timeouts);
  ~ModbusDevice() override;
  ModbusDevice(const ModbusDevice&) = delete;
  ModbusDevice& operator=(const ModbusDevice&) = delete;

  std::string name() const override;
  void set_drive(const DriveSetpoint& setpoint) override;
  void set_slew(double frequency_hz_per_s, double amplitude_v_per_s) override;
  void command(DeviceAction action) override;
  DeviceTelemetry read() override;
  bool lockstep() const override { return lockstep_; }
  DeviceTelemetry step(const DriveSetpoint& setpoint, const DriveSlew& slew, DeviceAction action,
                       std::uint32_t ticks) override;

 private:
  void set_timeout(std::chrono::milliseconds timeout);
  void write_holding(std::uint16_t address, const std::uint16_t* values, int count, const std::string& what);
  [[noreturn]] void fail(const std::string& what) const;

  std::string endpoint_text_;
  modbus_t* context_ = nullptr;
  bool lockstep_ = false;  // input register 35 (clock) read when the device was opened
  // False for a board without the electrical input registers 36..44 (it answered the read of
  // the whole table with ILLEGAL DATA ADDRESS): then 0..35 are read, the electrical values absent.
  bool electrical_registers_ = true;
  // How many input registers a read asks for: the whole table, then without the amplifier's
  // output (45..50, a board or emulator from before them), then without the electrical port.
  int input_count_ = 0;
};

}  // namespace swum::host
