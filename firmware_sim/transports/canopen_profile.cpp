#include "transports/canopen_profile.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "core/monotonic_clock.h"

namespace swum::emu {

namespace co = canopen;

namespace {

constexpr std::uint8_t kMaxNodeId = 127;  // CiA 301 7.3.2: node ids 1..127

// A physical value in bus units, rounded and held inside the object's type (a value out of the
// type's range reads as its limit, never as a wrapped number).
std::int64_t to_units(double value, double units_per_si) {
  const double scaled = std::round(value * units_per_si);
  if (!std::isfinite(scaled)) return 0;
  return static_cast<std::int64_t>(std::clamp(scaled, -9.0e18, 9.0e18));
}

// The raw bits of a number for an object of `type`, clamped to the type's range.
std::uint32_t raw_for(co::DataType type, std::int64_t value) {
  switch (type) {
    case co::DataType::integer8: return static_cast<std::uint8_t>(std::clamp<std::int64_t>(value, -128, 127));
    case co::DataType::integer16: return static_cast<std::uint16_t>(std::clamp<std::int64_t>(value, -32768, 32767));
    case co::DataType::integer32:
      return static_cast<std::uint32_t>(static_cast<std::int32_t>(std::clamp<std::int64_t>(
          value, std::numeric_limits<std::int32_t>::min(), std::numeric_limits<std::int32_t>::max())));
    case co::DataType::boolean: return value != 0 ? 1U : 0U;
    case co::DataType::unsigned8: return static_cast<std::uint32_t>(std::clamp<std::int64_t>(value, 0, 0xFF));
    case co::DataType::unsigned16: return static_cast<std::uint32_t>(std::clamp<std::int64_t>(value, 0, 0xFFFF));
    default: return static_cast<std::uint32_t>(std::clamp<std::int64_t>(value, 0, 0xFFFFFFFFLL));
  }
}

}  // namespace

// Where an EMCY goes in a state that may not send one (stopped): nowhere, while the dictionary
// still records it (CiA 301: 0x1001 and 0x1003 in every state).
class DiscardSink final : public co::FrameSink {
 public:
  void send(const protocol::CanFrame& /*frame*/) override {}
};

// A CanSender as the frame sink canopen/'s parts send through.
class CanopenProfile::Sink final : public co::FrameSink {
 public:
  explicit Sink(CanSender& out) : out_(out) {}
  void send(const protocol::CanFrame& frame) override { out_.send(frame); }

 private:
  CanSender& out_;
};

CanopenProfile::CanopenProfile(CanopenProfileConfig config, SharedState& shared)
    : config_(config),
      shared_(shared),
      od_(co::swum_eds_objects(),
          config.node >= 1 && config.node <= kMaxNodeId
              ? config.node
              : throw std::invalid_argument("CANopen node id must be 1.." + std::to_string(kMaxNodeId))),
      sdo_(od_, config.node),
      pdos_(od_, config.node),
      emcy_(od_) {
  auto& s = slots_;
  s.controlword = od_.slot(0x6040, 0);
  s.mode = od_.slot(0x6060, 0);
  s.target_velocity = od_.slot(0x60FF, 0);
  s.acceleration = od_.slot(0x6083, 0);
  s.deceleration = od_.slot(0x6084, 0);
  s.quick_stop_deceleration = od_.slot(0x6085, 0);
  s.quick_stop_option = od_.slot(0x605A, 0);
  s.velocity_window = od_.slot(0x606D, 0);
  s.velocity_window_time = od_.slot(0x606E, 0);
  s.abort_connection = od_.slot(0x6007, 0);
  s.frequency_set = od_.slot(0x2001, 0);
  s.amplitude_set = od_.slot(0x2002, 0);
  s.phase_set = od_.slot(0x2003, 0);
  s.frequency_slew = od_.slot(0x2004, 0);
  s.amplitude_slew = od_.slot(0x2005, 0);
  s.motional_setpoint = od_.slot(0x2031, 0);
  s.error_code = od_.slot(0x603F, 0);
  s.statusword = od_.slot(0x6041, 0);
  s.mode_display = od_.slot(0x6061, 0);
  s.position = od_.slot(0x6064, 0);
  s.velocity = od_.slot(0x606C, 0);
  s.error_register = od_.slot(0x1001, 0);
  s.frequency_actual = od_.slot(0x2010, 0);
  s.amplitude_actual = od_.slot(0x2011, 0);
  s.phase_actual = od_.slot(0x2012, 0);
  s.current_a = od_.slot(0x2020, 0);
  s.current_b = od_.slot(0x2021, 0);
  s.vi_phase_a = od_.slot(0x2022, 0);
  s.vi_phase_b = od_.slot(0x2023, 0);
  s.motional_a = od_.slot(0x2024, 0);
  s.motional_b = od_.slot(0x2025, 0);
  s.power = od_.slot(0x2026, 0);
  s.temperature = od_.slot(0x2027, 0);
  s.tracking_frequency = od_.slot(0x2030, 0);
  s.overruns = od_.slot(0x2040, 0);
  s.lateness_p99 = od_.slot(0x2041, 0);
  s.compute_p99 = od_.slot(0x2042, 0);
  s.sdo_aborts = od_.slot(0x2050, 0);
  s.pdo_length_errors = od_.slot(0x2051, 0);
  s.malformed = od_.slot(0x2052, 0);
  s.sync_cob_id = od_.slot(0x1005, 0);
  s.heartbeat_time = od_.slot(0x1017, 0);
  for (std::uint8_t i = 0; i < 4; ++i) s.consumer[i] = od_.slot(0x1016, static_cast<std::uint8_t>(i + 1));
  for (std::uint16_t i = 0; i < 4; ++i) s.rpdo_cob_id[i] = od_.slot(static_cast<std::uint16_t>(0x1400 + i), 1);
  rebuild_filters();
  od_.set_observer(this);
  request_.active = true;
  publish_request();
}

void CanopenProfile::rebuild_filters() {
  std::array<io::CanFilter, 3 + 4 + 4> next{};
  std::size_t n = 0;
  next[n++] = io::CanFilter{co::kNmtId, io::kCanStandardIdMax, false};
  next[n++] = io::CanFilter{sync_id_, io::kCanStandardIdMax, false};
  next[n++] = io::CanFilter{0x600U + config_.node, io::kCanStandardIdMax, false};
  for (const std::size_t slot : slots_.consumer) {  // bits 16-23: the consumed node (0: unused)
    const std::uint32_t node = (od_.u32(slot) >> 16) & 0xFF;
    if (node >= 1 && node <= kMaxNodeId && node != config_.node && (od_.u32(slot) & 0xFFFF) != 0)
      next[n++] = io::CanFilter{co::kHeartbeatBaseId + node, io::kCanStandardIdMax, false};
  }
  for (const std::size_t slot : slots_.rpdo_cob_id) {  // bit 31: not valid; bit 29: 29-bit (unused)
    const std::uint32_t cob_id = od_.u32(slot);
    if ((cob_id & 0xA0000000U) == 0) next[n++] = io::CanFilter{cob_id & 0x7FF, io::kCanStandardIdMax, false};
  }
  if (n == filter_count_ && std::equal(next.begin(), next.begin() + static_cast<std::ptrdiff_t>(n), filters_.begin(),
                                       [](const io::CanFilter& a, const io::CanFilter& b) {
                                         return a.id == b.id && a.mask == b.mask && a.extended == b.extended;
                                       }))
    return;
  filters_ = next;
  filter_count_ = n;
  ++filters_generation_;
}

std::int64_t CanopenProfile::profile_now_ns() const {
  if (shared_.lockstep != nullptr) return std::llround(shared_.telemetry.load().sim_time_s * 1e9);
  return monotonic_ns();
}

void CanopenProfile::set_nmt(co::NmtState state) {
  nmt_ = state;
  nmt_published_.store(state, std::memory_order_relaxed);
  shared_.canopen_nmt_state.store(static_cast<std::uint8_t>(state), std::memory_order_relaxed);
}

// CiA 301 7.3.2.2: a reset returns the objects of its area to their defaults, the node then
// sends its boot-up message and enters pre-operational on its own.
void CanopenProfile::boot(co::NmtCommand reset, std::int64_t now_ns, CanSender& out) {
  set_nmt(co::NmtState::initialising);
  if (reset == co::NmtCommand::reset_node) od_.reset_application();
  od_.reset_communication();
  if (config_.heartbeat_ms >= 0)
    od_.set(slots_.heartbeat_time, static_cast<std::uint32_t>(std::min(config_.heartbeat_ms, 0xFFFF)));
  sdo_.reset();
  pdos_.reset(profile_now_ns());
  sync_id_ = od_.u32(slots_.sync_cob_id) & 0x7FF;
  if (booted_) rebuild_filters();  // a reset by NMT (receive thread); power-up keeps the defaults
  heartbeat_.configure(static_cast<std::uint16_t>(od_.u32(slots_.heartbeat_time)));
  std::array<std::uint32_t, 4> entries{};
  for (std::size_t i = 0; i < entries.size(); ++i) entries[i] = od_.u32(slots_.consumer[i]);
  consumer_.configure(entries);
  emcy_.reset();
  last_error_code_ = 0;
  pdo_error_active_ = false;
  // The request's event counters run on across resets: the drive reacts to their changes, so a
  // counter set back to 0 would read as one more fault reset or heartbeat loss.
  const std::uint32_t reset_edges = request_.fault_reset_edges;
  const std::uint32_t comm_losses = request_.comm_loss_events;
  request_ = DriveRequest{};
  request_.active = true;
  request_.fault_reset_edges = reset_edges;
  request_.comm_loss_events = comm_losses;
  // CiA 402 0x6007: reset application and reset communication abort the master's connection (the
  // drive reacts only while operation is enabled). Not the power-up boot.
  if (booted_) ++request_.comm_loss_events;
  last_controlword_ = 0;
  // 0x2050-0x2052 count since the start, not since the last reset.
  od_.set(slots_.sdo_aborts, static_cast<std::uint32_t>(counters_.sdo_aborts.load(std::memory_order_relaxed)));
  od_.set(slots_.pdo_length_errors,
          static_cast<std::uint32_t>(counters_.pdo_length_errors.load(std::memory_order_relaxed)));
  od_.set(slots_.malformed, static_cast<std::uint32_t>(counters_.malformed.load(std::memory_order_relaxed)));
  // The drive objects' defaults (the dictionary is the source; DriveRequest's initial values
  // only mirror them), then the request the drive sees.
  publish_request();
  out.send(co::boot_up_frame(config_.node));
  heartbeat_.restart(now_ns);
  set_nmt(co::NmtState::pre_operational);
}

void CanopenProfile::on_nmt(co::NmtCommand command, std::int64_t now_ns, CanSender& out) {
  switch (command) {
    case co::NmtCommand::reset_node:
    case co::NmtCommand::reset_communication: boot(command, now_ns, out); return;
    default: break;
  }
  const co::NmtState next = co::next_state(nmt_, command);
  if (next == co::NmtState::operational && nmt_ != co::NmtState::operational) pdos_.reset(profile_now_ns());
  if (next == co::NmtState::stopped && nmt_ != co::NmtState::stopped) {
    ++request_.comm_loss_events;  // CiA 402 0x6007: NMT stopped entered
    request_dirty_ = true;
  }
  set_nmt(next);
}

void CanopenProfile::on_sync(std::uint8_t counter, std::int64_t now_ns, CanSender& out) {
  if (!co::pdo_allowed(nmt_)) return;
  Sink sink(out);
  pdos_.on_sync(counter, sink);  // latched RPDOs act now (written() republishes), TPDOs sampled now
  pdos_.poll(now_ns, sink);
}

CanRxResult CanopenProfile::receive(const io::CanFrame& frame, const CanRxTime& time, CanNodePort& node) {
  if (frame.extended) return {};  // CANopen (CiA 301) uses 11-bit identifiers only
  const std::lock_guard lock(mutex_);
  const CanRxResult result = handle(frame, time, node);
  finish(node);
  return result;
}

CanRxResult CanopenProfile::handle(const io::CanFrame& frame, const CanRxTime& time, CanNodePort& node) {
  // Two clocks: the protocol timeouts a master's own clock measures (SDO, heartbeat) run on the
  // wall clock; what the process data does (PDO timers, EMCY inhibit) on the node's clock,
  // emulated time in lockstep, so that a lockstep recording never depends on wall time.
  const std::int64_t now_ns = time.receive_ns;
  const std::int64_t process_ns = time.clock_ns;
  if (!booted_) {  // a frame before the first send_periodic(): boot first, as a device does on power-up
    boot(co::NmtCommand::reset_node, now_ns, node);
    booted_ = true;
  }
  auto malformed = [this] {
    counters_.malformed.fetch_add(1, std::memory_order_relaxed);
    od_.set(slots_.malformed, static_cast<std::uint32_t>(counters_.malformed.load(std::memory_order_relaxed)));
    return CanRxResult{CanRxStatus::refused, Reason::wrong_length};
  };
  if (frame.id == 0x000) {  // NMT
    co::NmtCommand command{};
    switch (co::decode_nmt(frame, config_.node, command)) {
      case co::NmtDecode::not_for_us: return {};
      case co::NmtDecode::malformed: return malformed();
      case co::NmtDecode::for_us: on_nmt(command, now_ns, node); return {CanRxStatus::accepted, Reason::none};
    }
    return {};
  }
  if (frame.id == sync_id_) {  // SYNC on the wall clock (in lockstep the transport steps with it)
    std::uint8_t counter = 0;
    switch (co::decode_sync(frame, sync_id_, counter)) {
      case co::SyncDecode::malformed: return malformed();
      case co::SyncDecode::not_sync: return {};
      case co::SyncDecode::sync: break;
    }
    write_actuals(shared_.telemetry.load());
    on_sync(counter, process_ns, node);
    return {CanRxStatus::accepted, Reason::none};
  }
  if (frame.id == 0x600U + config_.node) {    // SDO request
    if (!co::sdo_allowed(nmt_)) return {};    // stopped: only NMT (CiA 301 Table 83)
    write_actuals(shared_.telemetry.load());  // an SDO read sees the latest snapshot
    protocol::CanFrame response;
    const std::uint64_t aborts_before = sdo_.aborts_sent();
    if (sdo_.receive(frame, now_ns, response)) node.send(response);
    if (sdo_.aborts_sent() != aborts_before) {
      counters_.sdo_aborts.store(sdo_.aborts_sent(), std::memory_order_relaxed);
      od_.set(slots_.sdo_aborts, static_cast<std::uint32_t>(sdo_.aborts_sent()));
      return {CanRxStatus::refused, Reason::illegal_address};
    }
    return {CanRxStatus::accepted, Reason::none};
  }
  if (frame.id >= 0x701 && frame.id <= 0x77F && frame.id != 0x700U + config_.node) {  // consumed heartbeats
    consumer_.on_frame(frame, now_ns);
    return {CanRxStatus::accepted, Reason::none};
  }
  if (!co::pdo_allowed(nmt_)) return {};
  switch (pdos_.receive(frame)) {
    case co::Pdos::RpdoStatus::not_rpdo: return {};
    case co::Pdos::RpdoStatus::applied:
    case co::Pdos::RpdoStatus::latched:
      if (pdo_error_active_) {  // a PDO of the right length again: the length error is gone
        pdo_error_active_ = false;
        clear_emcy(co::error_register_bits(last_error_code_), process_ns, node);
      }
      return {CanRxStatus::accepted, Reason::none};
    case co::Pdos::RpdoStatus::length_error: {
      counters_.pdo_length_errors.fetch_add(1, std::memory_order_relaxed);
      od_.set(slots_.pdo_length_errors,
              static_cast<std::uint32_t>(counters_.pdo_length_errors.load(std::memory_order_relaxed)));
      if (!pdo_error_active_) {  // CiA 301: PDO not processed due to length error, until one fits
        pdo_error_active_ = true;
        raise_emcy(kPdoLengthError, process_ns, node);
      }
      return {CanRxStatus::refused, Reason::wrong_length};
    }
    case co::Pdos::RpdoStatus::refused: return {CanRxStatus::refused, Reason::illegal_address};
  }
  return {};
}

void CanopenProfile::write_actuals(const Telemetry& t) {
  auto put = [this](std::size_t slot, std::int64_t value) {
    od_.set(slot, raw_for(od_.description(slot).type, value));
  };
  const auto& s = slots_;
  put(s.statusword, t.cia402.statusword);
  put(s.mode_display, t.cia402.mode_display);
  put(s.error_code, t.cia402.error_code);
  put(s.position, to_units(t.position_m, 1e6));
  put(s.velocity, to_units(t.speed_m_s, 1e6));
  put(s.frequency_actual, to_units(t.output.frequency_hz, 1e3));
  put(s.amplitude_actual, to_units(t.cia402.terminal_amplitude_v, 1e3));
  put(s.phase_actual, to_units(t.output.phase_deg, 100.0));
  put(s.current_a, to_units(t.electrical.current_a_a, 1e3));
  put(s.current_b, to_units(t.electrical.current_b_a, 1e3));
  put(s.vi_phase_a, to_units(t.electrical.phase_a_deg, 100.0));
  put(s.vi_phase_b, to_units(t.electrical.phase_b_deg, 100.0));
  put(s.motional_a, to_units(t.electrical.motional_phase_a_deg, 100.0));
  put(s.motional_b, to_units(t.electrical.motional_phase_b_deg, 100.0));
  put(s.power, to_units(t.electrical.power_w(), 1e3));
  put(s.temperature, to_units(t.stator_temperature_c, 100.0));
  put(s.tracking_frequency, to_units(t.cia402.tracking_frequency_hz, 1e3));
  put(s.overruns, static_cast<std::int64_t>(std::min<std::uint64_t>(t.stats.overruns, 0xFFFFFFFF)));
  put(s.lateness_p99, static_cast<std::int64_t>(std::min<std::uint64_t>(t.stats.lateness_p99_ns, 0xFFFFFFFF)));
  put(s.compute_p99, static_cast<std::int64_t>(std::min<std::uint64_t>(t.stats.compute_p99_ns, 0xFFFFFFFF)));
}

// EMCY (CiA 301 7.2.7, CiA 402 0x603F): one message for each new error code of the drive, the
// error reset message when it clears; 0x1001 holds the bits of the errors in force (the drive's
// and an RPDO length error). In stopped no EMCY is sent; the dictionary records it all the same.
void CanopenProfile::update_emcy(std::uint16_t drive_code, std::int64_t now_ns, CanSender& out) {
  if (drive_code != last_error_code_) {
    last_error_code_ = drive_code;
    if (drive_code != 0) {
      raise_emcy(drive_code, now_ns, out);
    } else {
      clear_emcy(pdo_error_active_ ? co::error_register_bits(kPdoLengthError) : 0, now_ns, out);
    }
  }
  Sink sink(out);
  DiscardSink discard;
  emcy_.poll(now_ns, co::emcy_allowed(nmt_) ? static_cast<co::FrameSink&>(sink) : discard);
}

void CanopenProfile::raise_emcy(std::uint16_t code, std::int64_t now_ns, CanSender& out) {
  Sink sink(out);
  DiscardSink discard;
  emcy_.raise(code, now_ns, co::emcy_allowed(nmt_) ? static_cast<co::FrameSink&>(sink) : discard);
  // The register of what is in force now (raise() adds the new code's bits to the old ones).
  std::uint8_t bits = co::error_register_bits(last_error_code_);
  if (pdo_error_active_) bits |= co::error_register_bits(kPdoLengthError);
  od_.set(slots_.error_register, bits);
}

void CanopenProfile::clear_emcy(std::uint8_t remaining_register, std::int64_t now_ns, CanSender& out) {
  Sink sink(out);
  DiscardSink discard;
  emcy_.clear(now_ns, co::emcy_allowed(nmt_) ? static_cast<co::FrameSink&>(sink) : discard, remaining_register);
}

// After a frame or a snapshot: the drive sees the request once, whole (an RPDO's objects
// together, never half of them).
void CanopenProfile::finish(CanSender& /*out*/) {
  if (request_dirty_) publish_request();
}

void CanopenProfile::send_telemetry(const Telemetry& t, const RejectSnapshot& /*rejects*/, CanSender& out) {
  // On the wall clock the node's services run in send_periodic() at their own rate; in lockstep
  // this call is the SYNC (CanTransport::on_sync): everything of the cycle happens at it.
  if (shared_.lockstep == nullptr) return;
  const std::lock_guard lock(mutex_);
  if (!booted_) return;
  const std::int64_t now_ns = profile_now_ns();
  write_actuals(t);
  update_emcy(t.cia402.error_code, now_ns, out);
  on_sync(0, now_ns, out);
  finish(out);
}

void CanopenProfile::send_periodic(std::int64_t now_ns, CanSender& out) {
  const std::lock_guard lock(mutex_);
  if (!booted_) {  // power-up: boot-up message, pre-operational (CiA 301 7.3.2.2)
    boot(co::NmtCommand::reset_node, now_ns, out);
    booted_ = true;
  }
  Sink sink(out);
  heartbeat_.poll(now_ns, config_.node, nmt_, sink);
  protocol::CanFrame abort;
  if (sdo_.poll(now_ns, abort)) {
    out.send(abort);
    counters_.sdo_aborts.store(sdo_.aborts_sent(), std::memory_order_relaxed);
    od_.set(slots_.sdo_aborts, static_cast<std::uint32_t>(sdo_.aborts_sent()));
  }
  if (consumer_.poll(now_ns) != 0) {  // a consumed node's heartbeat is lost: the drive reacts (0x6007)
    ++request_.comm_loss_events;
    request_dirty_ = true;
  }
  if (shared_.lockstep == nullptr) {  // the wall clock: EMCY and the event-driven TPDOs, every period
    write_actuals(shared_.telemetry.load());
    update_emcy(shared_.telemetry.load().cia402.error_code, now_ns, out);
    if (co::pdo_allowed(nmt_)) pdos_.poll(now_ns, sink);
  }
  finish(out);
}

co::SdoAbort CanopenProfile::check(std::size_t slot, std::uint32_t raw) {
  const auto& s = slots_;
  const auto as_signed = [&](std::size_t sl) {
    const co::DataType type = od_.description(sl).type;
    if (type == co::DataType::integer8) return static_cast<std::int32_t>(static_cast<std::int8_t>(raw));
    if (type == co::DataType::integer16) return static_cast<std::int32_t>(static_cast<std::int16_t>(raw));
    return static_cast<std::int32_t>(raw);
  };
  if (slot == s.mode) {  // 0x6502: no mode, profile velocity, open loop
    const std::int32_t mode = as_signed(slot);
    return mode == 0 || mode == 3 || mode == -1 ? co::SdoAbort::none : co::SdoAbort::value_range;
  }
  if (slot == s.quick_stop_option) {  // the options this drive implements (docs/canopen.md)
    const std::int32_t option = as_signed(slot);
    return option == 0 || option == 1 || option == 2 || option == 5 || option == 6 ? co::SdoAbort::none
                                                                                   : co::SdoAbort::value_range;
  }
  if (slot == s.frequency_set) {
    const double hz = raw * 1e-3;
    if (hz < config_.limits.min_frequency_hz) return co::SdoAbort::value_too_low;
    if (hz > config_.limits.max_frequency_hz) return co::SdoAbort::value_too_high;
  }
  if (slot == s.amplitude_set && raw * 1e-3 > config_.limits.max_amplitude_v) return co::SdoAbort::value_too_high;
  if (slot == s.sync_cob_id && raw != 0x80) return co::SdoAbort::value_range;  // SYNC steps lockstep on 0x080
  return co::SdoAbort::none;  // 0x1016's duplicate node ids: the dictionary's own rule
}

void CanopenProfile::written(std::size_t slot) {
  const auto& s = slots_;
  if (slot == s.controlword) {
    const std::uint16_t word = static_cast<std::uint16_t>(od_.u32(slot));
    if ((word & 0x80U) != 0 && (last_controlword_ & 0x80U) == 0) ++request_.fault_reset_edges;  // CiA 402: edge
    last_controlword_ = word;
  }
  if (slot == s.heartbeat_time) heartbeat_.configure(static_cast<std::uint16_t>(od_.u32(slot)));
  for (std::size_t i = 0; i < s.consumer.size(); ++i) {
    if (slot == s.consumer[i]) {
      std::array<std::uint32_t, 4> entries{};
      for (std::size_t k = 0; k < entries.size(); ++k) entries[k] = od_.u32(s.consumer[k]);
      consumer_.configure(entries);
    }
  }
  rebuild_filters();
  request_dirty_ = true;  // published once the frame is done (finish())
}

void CanopenProfile::publish_request() {
  request_dirty_ = false;
  publications_.fetch_add(1, std::memory_order_relaxed);
  const auto& s = slots_;
  DriveRequest& r = request_;
  r.active = true;
  r.controlword = static_cast<std::uint16_t>(od_.u32(s.controlword));
  r.mode = static_cast<std::int8_t>(od_.i32(s.mode));
  r.target_velocity_um_s = od_.i32(s.target_velocity);
  r.profile_acceleration_um_s2 = od_.u32(s.acceleration);
  r.profile_deceleration_um_s2 = od_.u32(s.deceleration);
  r.quick_stop_deceleration_um_s2 = od_.u32(s.quick_stop_deceleration);
  r.quick_stop_option = static_cast<std::int16_t>(od_.i32(s.quick_stop_option));
  r.velocity_window_um_s = static_cast<std::uint16_t>(od_.u32(s.velocity_window));
  r.velocity_window_time_ms = static_cast<std::uint16_t>(od_.u32(s.velocity_window_time));
  r.abort_connection_option = static_cast<std::int16_t>(od_.i32(s.abort_connection));
  r.frequency_mhz = od_.u32(s.frequency_set);
  r.amplitude_mv = od_.u32(s.amplitude_set);
  r.phase_cdeg = static_cast<std::int16_t>(od_.i32(s.phase_set));
  r.frequency_slew_hz_per_s = od_.u32(s.frequency_slew);
  r.amplitude_slew_v_per_s = od_.u32(s.amplitude_slew);
  r.motional_phase_setpoint_cdeg = static_cast<std::int16_t>(od_.i32(s.motional_setpoint));
  shared_.drive_request.store(r);
}

}  // namespace swum::emu
