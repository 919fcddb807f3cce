// Device over SocketCAN (frames of config/swum.dbc for one node id).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "can_bus.h"
#include "can_codec.h"
#include "device/device.h"

namespace swum::host {

class CanDevice final : public Device {
 public:
  // "IFACE[:NODE]" (node 1..127, default 1). Throws std::invalid_argument for a malformed
  // address, DeviceError when the interface cannot be opened or the node does not answer.
  CanDevice(const std::string& address, const DeviceTimeouts& timeouts);
  // For tests: any bus (e.g. the in-process fake) and node.
  CanDevice(std::unique_ptr<io::CanBus> bus, std::uint8_t node, const DeviceTimeouts& timeouts);

  std::string name() const override;
  void set_drive(const DriveSetpoint& setpoint) override;
  void set_slew(double frequency_hz_per_s, double amplitude_v_per_s) override;
  void command(DeviceAction action) override;
  DeviceTelemetry read() override;
  // Lockstep (swum-emu --clock external, Status bit ExternalClock): sets, sends one SYNC and
  // returns the telemetry that answers it, sampled at the SYNC: the command acts during the
  // cycle the SYNC starts and shows in the next step's telemetry (CANopen synchronous
  // semantics, one cycle of delay). `ticks` must be the device's --sync-ticks (checked from the
  // tick counter of consecutive answers).
  DeviceTelemetry step(const DriveSetpoint& setpoint, const DriveSlew& slew, DeviceAction action,
                       std::uint32_t ticks) override;
  bool lockstep() const override { return lockstep_; }

 private:
  void start(const DeviceTimeouts& timeouts);
  void send_command(std::uint8_t mode);
  void send_aux();
  void send(const io::CanFrame& frame, const char* what);

  std::unique_ptr<io::CanBus> bus_;
  std::uint8_t node_ = 1;
  std::chrono::milliseconds response_timeout_{500};
  DriveSetpoint setpoint_;
  double frequency_slew_hz_per_s_ = 0.0;
  double amplitude_slew_v_per_s_ = 0.0;
  std::uint8_t mode_ = protocol::can::mode::kDisable;  // what keep-alives repeat: 0 disable, 1 enable
  std::uint8_t command_alive_ = 0;
  std::uint8_t aux_alive_ = 0;
  bool lockstep_ = false;
  std::uint8_t sync_counter_ = 0;                    // CANopen SYNC counter 1..240
  std::optional<std::uint32_t> last_tick_;           // of the last SYNC's answer
  std::optional<DeviceTelemetry> last_sync_answer_;  // lockstep: what read() returns (the node is silent between SYNCs)
  DeviceTelemetry receive_set();
  void send_sync();
};

}  // namespace swum::host
