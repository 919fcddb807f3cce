// The CANopen profile (docs/canopen.md): swum-emu as a CiA 301 slave with the CiA 402 drive
// profile behind the CanProfile seam. The slave's parts are canopen/'s (the object dictionary
// generated from config/swum.eds, the SDO server, PDOs, NMT, heartbeat, EMCY); this class wires
// them to the node: NMT commands and resets, SDO requests answered on the bus, RPDOs and SDO
// writes of the drive objects latched into SharedState::drive_request (the loop's drive reads it
// at each tick), the actual values of each telemetry snapshot written into the dictionary for
// TPDOs and SDO reads, EMCY on each change of the drive's error code 0x603F, heartbeat produced
// and consumed (a lost node raises the drive's comm-loss reaction, 0x6007).
//
// Time: in lockstep (--clock external) the transport steps the loop with each SYNC and calls
// send_telemetry() then: synchronous RPDOs take effect and synchronous TPDOs are sampled at that
// instant, and event-driven TPDOs run on emulated time, so the same master script gives the same
// frames. On the wall clock a SYNC reaches receive(), and send_telemetry() (telemetry_hz) polls
// the event-driven TPDOs on the monotonic clock.
//
// Threads: receive() on the transport's receive thread, send_periodic() on its transmit thread,
// send_telemetry() on one of them (can_profile.h). Unlike the swum profile this one holds state
// that both threads change (the dictionary, the NMT state): one mutex of its own serialises the
// calls. Its critical sections are bounded (one frame, or one telemetry snapshot), allocate and
// throw nothing, and no call waits on the loop.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <mutex>

#include "core/amplifier.h"
#include "core/drive_request.h"
#include "core/shared_state.h"
#include "emcy.h"
#include "heartbeat.h"
#include "nmt.h"
#include "object_dictionary.h"
#include "pdo.h"
#include "sdo_server.h"
#include "sync.h"
#include "transports/can_profile.h"

namespace swum::emu {

struct CanopenProfileConfig {
  std::uint8_t node = 1;   // 1..127 (CiA 301)
  AmplifierLimits limits;  // the range checks of the manufacturer set-points
  // --heartbeat-ms: the producer heartbeat time 0x1017 at boot (the EDS default if negative).
  int heartbeat_ms = -1;
};

// The counts of bad input the profile sees (also readable as 0x2050-0x2052).
struct CanopenCounters {
  std::atomic<std::uint64_t> sdo_aborts{0};
  std::atomic<std::uint64_t> pdo_length_errors{0};
  std::atomic<std::uint64_t> malformed{0};  // NMT and SYNC frames of a wrong length or command
};

class CanopenProfile final : public CanProfile, private canopen::WriteObserver {
 public:
  // Throws std::invalid_argument for a node id out of range (load time).
  CanopenProfile(CanopenProfileConfig config, SharedState& shared);

  // NMT, SYNC, this node's SDO requests, the heartbeats of the consumed nodes and the valid
  // RPDOs' identifiers: the frames the node acts on, and never its own (can_profile.h).
  [[nodiscard]] std::span<const io::CanFilter> filters() const override { return {filters_.data(), filter_count_}; }
  [[nodiscard]] std::uint64_t filters_generation() const override { return filters_generation_; }
  CanRxResult receive(const io::CanFrame& frame, const CanRxTime& time, CanNodePort& node) override;
  void send_telemetry(const Telemetry& t, const RejectSnapshot& rejects, CanSender& out) override;
  void send_periodic(std::int64_t now_ns, CanSender& out) override;
  // The node's services (heartbeat, SDO timeout, EMCY, event-driven TPDOs) every millisecond,
  // whatever --telemetry-hz says.
  [[nodiscard]] std::int64_t periodic_interval_ns() const override { return 1'000'000; }

  [[nodiscard]] canopen::NmtState nmt_state() const { return nmt_published_.load(std::memory_order_relaxed); }
  [[nodiscard]] const CanopenCounters& counters() const { return counters_; }
  // How often the drive request was published (once per frame or snapshot that changed it).
  [[nodiscard]] std::uint64_t request_publications() const { return publications_.load(std::memory_order_relaxed); }

 private:
  class Sink;  // CanSender as canopen::FrameSink
  // canopen::WriteObserver: the drive's value checks, then the request republished.
  canopen::SdoAbort check(std::size_t slot, std::uint32_t raw) override;
  void written(std::size_t slot) override;

  CanRxResult handle(const io::CanFrame& frame, const CanRxTime& time, CanNodePort& node);
  void boot(canopen::NmtCommand reset, std::int64_t now_ns, CanSender& out);  // reset + boot-up
  void update_emcy(std::uint16_t drive_code, std::int64_t now_ns, CanSender& out);
  void raise_emcy(std::uint16_t code, std::int64_t now_ns, CanSender& out);
  void clear_emcy(std::uint8_t remaining_register, std::int64_t now_ns, CanSender& out);
  void finish(CanSender& out);  // publishes the request when a frame or snapshot changed it
  void on_nmt(canopen::NmtCommand command, std::int64_t now_ns, CanSender& out);
  void on_sync(std::uint8_t counter, std::int64_t now_ns, CanSender& out);
  void write_actuals(const Telemetry& t);
  void publish_request();
  void set_nmt(canopen::NmtState state);
  std::int64_t profile_now_ns() const;  // emulated time in lockstep, else the monotonic clock

  CanopenProfileConfig config_;
  SharedState& shared_;
  void rebuild_filters();  // receive thread (and the constructor) only
  std::array<io::CanFilter, 3 + 4 + 4> filters_{};
  std::size_t filter_count_ = 0;
  std::uint64_t filters_generation_ = 0;
  std::mutex mutex_;
  canopen::ObjectDictionary od_;
  canopen::SdoServer sdo_;
  canopen::Pdos pdos_;
  canopen::HeartbeatProducer heartbeat_;
  canopen::HeartbeatConsumer consumer_;
  canopen::EmcyProducer emcy_;
  canopen::NmtState nmt_ = canopen::NmtState::initialising;
  std::atomic<canopen::NmtState> nmt_published_{canopen::NmtState::initialising};
  bool booted_ = false;
  DriveRequest request_;
  std::uint16_t last_error_code_ = 0;
  static constexpr std::uint16_t kPdoLengthError = 0x8210;  // CiA 301: PDO not processed, length
  bool pdo_error_active_ = false;                           // an RPDO was too short; cleared by the next one that fits
  bool request_dirty_ = false;                              // the request changed since it was last published
  std::atomic<std::uint64_t> publications_{0};
  std::uint16_t last_controlword_ = 0;  // for the fault reset's rising edge
  std::uint32_t sync_id_ = 0x80;
  CanopenCounters counters_;
  // Bound slots of the objects the profile reads or writes (load time).
  struct Slots {
    std::size_t controlword, mode, target_velocity, acceleration, deceleration, quick_stop_deceleration,
        quick_stop_option, velocity_window, velocity_window_time, abort_connection, frequency_set, amplitude_set,
        phase_set, frequency_slew, amplitude_slew, motional_setpoint;
    std::size_t error_code, statusword, mode_display, position, velocity, error_register;
    std::size_t frequency_actual, amplitude_actual, phase_actual, current_a, current_b, vi_phase_a, vi_phase_b,
        motional_a, motional_b, power, temperature, tracking_frequency, overruns, lateness_p99, compute_p99;
    std::size_t sdo_aborts, pdo_length_errors, malformed;
    std::size_t sync_cob_id, heartbeat_time;
    std::array<std::size_t, 4> consumer;
    std::array<std::size_t, 4> rpdo_cob_id;
  } slots_;
};

}  // namespace swum::emu
