// Device over CANopen: the host as the master of one CiA 402 drive (swum-emu --can-profile
// cia402, or a board that speaks CiA 301/402 with swum's manufacturer objects: docs/canopen.md,
// "The host tool as a master"), in the manufacturer open-loop mode -1, where the host's tools set
// frequency, amplitude and phase themselves.
//
// Opening: NMT enter pre-operational to the node (no reset: CiA 402 reads a reset as the master's
// connection aborted, and a running drive would react to a second master's `swum log`); the
// node must answer an SDO read of the device type 0x1000
// (profile 402) and the supported modes 0x6502 (bit 16: mode -1) checked by SDO; 0x6060 = -1; the
// PDOs of canopen_pdo_layout.h mapped by CiA 301's procedure (COB-ID bit 31 set, count 0, entries,
// count, transmission type, COB-ID valid); the drive's controlword and set-points read back, so
// that a passive `swum log` changes neither; NMT start; one SYNC whose four TPDOs prove the cycle.
//
// The cycle: set-points and controlword in RPDO1/RPDO2 (acted on when received), the actual
// values in TPDO1-4 sampled at a SYNC the host sends; the slews by SDO. The CiA 402 state machine
// is walked one checked transition per exchange (cia402_master.h): command() walks on until the
// state is reached (or the response timeout passes), step() takes one transition per cycle, and
// read() carries on a walk not yet done.
//
// Keep-alive: none. The drive's amplifier watchdog is fed by the drive itself; CiA 301's answer to
// a lost master is the heartbeat, and the host neither produces one nor configures the node's
// consumer (0x1016): a host that dies leaves the drive as it was, like a master that stops
// without NMT. Ending a run (the tools' drive-off) disables it as on the other protocols.
//
// Lockstep (CanopenNode::sync_ticks > 0, swum-emu --clock external): each SYNC runs one cycle of
// sync_ticks ticks. read() sends one SYNC (one cycle: a sweep or log in lockstep advances by its
// reads); step() sends ticks / sync_ticks SYNCs and returns the telemetry of the last, sampled at
// its start (CANopen synchronous semantics: what was sent before a SYNC acts in the cycle it
// starts and shows at the next one). The device time and tick are the host's count of its SYNCs
// (none is on the bus), from its first SYNC. On the wall clock they are absent.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <memory>
#include <span>
#include <string>

#include "can_bus.h"
#include "cia402.h"
#include "device/canopen_pdo_layout.h"
#include "device/cia402_master.h"
#include "device/device.h"
#include "sdo_client.h"

namespace swum::host {

// "IFACE:NODE" (node 1..127): the node, and the interface in `interface`. Throws
// std::invalid_argument ("--canopen: ...") for anything else.
std::uint8_t parse_canopen_address(const std::string& address, std::string& interface);

class CanopenDevice final : public Device {
 public:
  // Throws std::invalid_argument for a malformed address or settings, DeviceError when the
  // interface cannot be opened or the node does not answer, is no CiA 402 drive with mode -1,
  // refuses its configuration or sends no PDOs.
  CanopenDevice(const std::string& address, const CanopenNode& settings, const DeviceTimeouts& timeouts);
  // For tests: any bus (e.g. the in-process fake) and node.
  CanopenDevice(std::unique_ptr<io::CanBus> bus, std::uint8_t node, const CanopenNode& settings,
                const DeviceTimeouts& timeouts);

  std::string name() const override;
  // Throws DeviceError for a load (the drive's dictionary has no load input: the test bench's
  // load stays with the scenario, --inject and the HTTP API) or a set-point its objects cannot hold.
  void set_drive(const DriveSetpoint& setpoint) override;
  void set_slew(double frequency_hz_per_s, double amplitude_v_per_s) override;
  void command(DeviceAction action) override;
  DeviceTelemetry read() override;
  bool lockstep() const override { return settings_.sync_ticks > 0; }
  // Throws DeviceError when not in lockstep or `ticks` is not a multiple of the node's sync_ticks.
  DeviceTelemetry step(const DriveSetpoint& setpoint, const DriveSlew& slew, DeviceAction action,
                       std::uint32_t ticks) override;

  // The last controlword sent (or read from the drive at opening).
  [[nodiscard]] std::uint16_t controlword() const { return controlword_; }
  [[nodiscard]] std::uint64_t syncs_sent() const { return syncs_; }

 private:
  void start(const DeviceTimeouts& timeouts);
  void reach();  // NMT enter pre-operational, then the node must answer an SDO
  void configure();
  void configure_pdo(const canopen_layout::Pdo& pdo, std::uint16_t communication, std::uint16_t mapping);
  std::uint32_t upload(std::uint16_t index, std::uint8_t sub, const char* what);
  void download(std::uint16_t index, std::uint8_t sub, std::uint32_t value, std::size_t bytes, const char* what);
  void transfer(protocol::CanFrame request, std::uint16_t index, std::uint8_t sub, const char* what);
  void send(const protocol::CanFrame& frame, const char* what);
  void drain();
  void check_boot_up(const protocol::CanFrame& frame) const;
  void check_setpoint(const DriveSetpoint& setpoint);
  void write_slews(const DriveSlew& slew);
  void send_setpoints();
  void send_controlword(std::uint16_t controlword);
  void walk_one();  // the controlword for the next transition, sent when it changes
  DeviceTelemetry sync_and_collect(std::chrono::milliseconds timeout);

  std::unique_ptr<io::CanBus> bus_;
  std::uint8_t node_ = 1;
  CanopenNode settings_;
  std::chrono::milliseconds response_timeout_{500};
  canopen::SdoClient sdo_;
  DriveSetpoint setpoint_;
  canopen_layout::Setpoints encoded_;
  bool slews_known_ = false;  // the drive's slews are the host's (written once at least)
  DriveSlew slew_;
  cia402::Goal goal_ = cia402::Goal::none;
  std::uint16_t controlword_ = 0;
  canopen::Cia402State state_ = canopen::Cia402State::unknown;  // of the last telemetry
  std::uint64_t syncs_ = 0;
  std::uint32_t device_type_ = 0;  // 0x1000, read when the node was reached
  bool configured_ = false;        // NMT start sent: a boot-up from now on is a reboot
};

}  // namespace swum::host
