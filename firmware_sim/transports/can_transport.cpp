#include "transports/can_transport.h"

#include "core/lockstep_clock.h"
#include "core/monotonic_clock.h"
#include "transports/swum_can_profile.h"

#include <time.h>

#include <array>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <stdexcept>

#include "can_codec.h"  // the CiA 301 SYNC that steps the lockstep clock, whatever the profile

namespace swum::emu {

namespace {
// CLOCK_REALTIME now, or -1 (reported once) if clock_gettime fails.
std::int64_t realtime_ns() {
  timespec ts{};
  if (clock_gettime(CLOCK_REALTIME, &ts) != 0) {
    static std::atomic<bool> reported{false};
    if (!reported.exchange(true))
      std::fprintf(stderr, "swum-emu: clock_gettime(CLOCK_REALTIME): %s; CAN receive timestamps unused\n",
                   std::strerror(errno));
    return -1;
  }
  return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}
}  // namespace

RxStamp receive_time(std::chrono::nanoseconds timestamp, std::int64_t realtime_now_ns, std::int64_t monotonic_now_ns) {
  RxStamp r;
  r.monotonic_ns = monotonic_now_ns;
  if (timestamp.count() == 0) return r;  // missing
  const std::int64_t age = realtime_now_ns - static_cast<std::int64_t>(timestamp.count());
  if (realtime_now_ns < 0 || age < -1'000'000 || age > kMaxFrameAgeNs) {
    r.source = RxStampSource::implausible;
    return r;
  }
  r.source = RxStampSource::bus;
  r.age_ns = age > 0 ? age : 0;
  r.monotonic_ns = monotonic_now_ns - r.age_ns;
  return r;
}

// What the profile is handed: sending goes through the transport's counters and recording;
// submitting checks the limits and stamps the frame's receive time before the queue.
class CanTransport::Port final : public CanNodePort {
 public:
  Port(CanTransport& transport, bool record, std::int64_t receive_ns = 0)
      : transport_(transport), record_(record), receive_ns_(receive_ns) {}
  void send(const io::CanFrame& frame) override { transport_.send(frame, record_); }
  Reason submit(Command command) override {
    if (const Reason r = validate(command, transport_.limits_); r != Reason::none) return r;
    command.accepted_ns = static_cast<std::uint64_t>(receive_ns_);
    return transport_.shared_.submit(command);
  }

 private:
  CanTransport& transport_;
  bool record_;
  std::int64_t receive_ns_;
};

CanTransport::CanTransport(std::unique_ptr<io::CanBus> rx_bus, std::unique_ptr<io::CanBus> tx_bus,
                           CanTransportConfig config, SharedState& shared, AmplifierLimits limits)
    : CanTransport(std::move(rx_bus), std::move(tx_bus),
                   std::make_unique<SwumCanProfile>(SwumCanProfileConfig{config.node, config.heartbeat_s}), config,
                   shared, limits) {}

CanTransport::CanTransport(std::unique_ptr<io::CanBus> rx_bus, std::unique_ptr<io::CanBus> tx_bus,
                           std::unique_ptr<CanProfile> profile, CanTransportConfig config, SharedState& shared,
                           AmplifierLimits limits)
    : rx_bus_(std::move(rx_bus)),
      tx_bus_(std::move(tx_bus)),
      profile_(std::move(profile)),
      bus_name_(rx_bus_->name()),
      config_(config),
      shared_(shared),
      limits_(limits) {
  if (!profile_) throw std::invalid_argument("CAN: no profile (the frame set the node speaks)");
  const io::CanResult r = rx_bus_->set_filters(profile_->filters());
  if (!r.ok()) throw std::runtime_error("CAN: cannot set receive filters on " + rx_bus_->name() + ": " + r.message);
  filters_generation_ = profile_->filters_generation();
}

CanTransport::~CanTransport() { stop(); }

void CanTransport::start() {
  rx_thread_ = std::thread([this] { rx_loop(); });
  tx_thread_ = std::thread([this] { tx_loop(); });
}

void CanTransport::stop() {
  stopping_.store(true);
  if (rx_thread_.joinable()) rx_thread_.join();
  if (tx_thread_.joinable()) tx_thread_.join();
}

void CanTransport::rx_loop() {
  io::CanFrame frame;
  std::uint64_t reported_errors = 0;
  while (!stopping_.load(std::memory_order_relaxed)) {
    const io::CanResult r = rx_bus_->receive(frame, std::chrono::milliseconds(50));
    if (r.status == io::CanStatus::timeout) continue;
    if (r.status == io::CanStatus::error_frame) {
      stats_.error_frames.fetch_add(1);
      const io::CanErrorInfo info = io::decode_error_frame(frame);
      if (info.bus_off) {
        stats_.bus_off.fetch_add(1);
        std::fprintf(stderr, "swum-emu: CAN %s: bus-off (%s); waiting for the controller to restart\n",
                     rx_bus_->name().c_str(), info.describe().c_str());
      }
      continue;
    }
    if (r.status != io::CanStatus::ok) {
      stats_.rx_errors.fetch_add(1);
      if (reported_errors++ < 5)
        std::fprintf(stderr, "swum-emu: CAN %s: receive: %s\n", rx_bus_->name().c_str(), r.message.c_str());
      ::timespec pause{0, 10'000'000};
      ::nanosleep(&pause, nullptr);  // e.g. ENETDOWN: do not spin
      continue;
    }
    stats_.rx_frames.fetch_add(1, std::memory_order_relaxed);
    log_frame(frame);
    // A scenario's bus-off: the node hears nothing, except that a SYNC still steps the emulated
    // clock (unanswered: send_telemetry() sends nothing then); otherwise, with SYNC as the clock,
    // emulated time would never reach the end of the bus-off.
    const bool sync = frame.id == protocol::can::kSyncId && !frame.extended;
    if (shared_.can_faults.off() && !(sync && shared_.lockstep != nullptr)) {
      stats_.bus_off_discarded.fetch_add(1, std::memory_order_relaxed);
      continue;
    }
    const RxStamp stamp = receive_time(frame.timestamp, realtime_ns(), monotonic_ns());
    switch (stamp.source) {
      case RxStampSource::bus:
        stats_.rx_stamped.fetch_add(1, std::memory_order_relaxed);
        receive_age_.record(static_cast<std::uint64_t>(stamp.age_ns));
        break;
      case RxStampSource::missing: stats_.rx_stamp_missing.fetch_add(1, std::memory_order_relaxed); break;
      case RxStampSource::implausible: stats_.rx_stamp_implausible.fetch_add(1, std::memory_order_relaxed); break;
    }
    CanRxResult result;
    if (sync && shared_.lockstep != nullptr) {
      const Reason reason = on_sync(frame);
      if (reason == Reason::none) continue;  // a step, not a command: not counted as accepted
      result = {CanRxStatus::refused, reason};
    } else {
      // Protocol timeouts (the swum alive counter's resynchronisation window): on the emulated
      // clock in lockstep, so that whether a command counts never depends on wall time.
      const std::int64_t clock_ns = shared_.lockstep != nullptr ? static_cast<std::int64_t>(std::llround(
                                                                      shared_.telemetry.load().sim_time_s * 1e9))
                                                                : stamp.monotonic_ns;
      Port port(*this, true, stamp.monotonic_ns);
      result = profile_->receive(frame, CanRxTime{stamp.monotonic_ns, clock_ns}, port);
      if (const std::uint64_t g = profile_->filters_generation(); g != filters_generation_) {
        filters_generation_ = g;  // e.g. an RPDO's new COB-ID: the kernel lets its frames in from now on
        if (const io::CanResult f = rx_bus_->set_filters(profile_->filters()); !f.ok()) {
          stats_.rx_errors.fetch_add(1);
          std::fprintf(stderr, "swum-emu: CAN %s: cannot change the receive filters: %s\n", rx_bus_->name().c_str(),
                       f.message.c_str());
        }
      }
    }
    if (result.status == CanRxStatus::accepted) {
      stats_.accepted.fetch_add(1, std::memory_order_relaxed);
    } else if (result.status == CanRxStatus::refused) {
      stats_.rejected.fetch_add(1, std::memory_order_relaxed);
      if (result.reason != Reason::queue_full)
        shared_.rejects.record(result.reason, CommandSource::can);  // submit() logged it
    }
  }
}

// candump -l: "(SECONDS.MICROSECONDS) IFACE ID#DATA". In lockstep the time is the emulated time
// (the same run gives the same file); the profile's wall-clock frames (heartbeats) are not
// logged then (send_periodic()).
void CanTransport::log_frame(const io::CanFrame& frame) {
  if (config_.can_log == nullptr) return;
  const bool lockstep = shared_.lockstep != nullptr;
  const std::int64_t ns = lockstep ? static_cast<std::int64_t>(std::llround(shared_.telemetry.load().sim_time_s * 1e9))
                                   : realtime_ns();
  // The protocol's cansend text: 3 digits for a standard identifier, 8 for an extended one.
  std::array<char, protocol::kCansendMaxLength + 1> text{};
  protocol::to_cansend(frame, text);
  const std::lock_guard lock(log_mutex_);
  std::fprintf(config_.can_log, "(%lld.%06lld) %s %s\n", static_cast<long long>(ns / 1'000'000'000),
               static_cast<long long>((ns % 1'000'000'000) / 1000), bus_name_.c_str(), text.data());
}

void CanTransport::send(const io::CanFrame& frame, bool record) {
  io::CanBus& bus = tx_bus_ ? *tx_bus_ : *rx_bus_;
  const io::CanResult r = bus.send(frame);
  if (r.ok()) {
    if (record) log_frame(frame);
    stats_.tx_frames.fetch_add(1, std::memory_order_relaxed);
  } else if (r.status == io::CanStatus::retry) {
    stats_.tx_dropped.fetch_add(1, std::memory_order_relaxed);  // queue full: telemetry is periodic, drop it
  } else {
    if (stats_.tx_errors.fetch_add(1) < 5)
      std::fprintf(stderr, "swum-emu: CAN %s: send: %s\n", bus.name().c_str(), r.message.c_str());
  }
}

Reason CanTransport::on_sync(const io::CanFrame& frame) {
  protocol::can::SyncFrame sync;
  if (const Reason r = protocol::can::decode_sync(frame, sync); r != Reason::none) return r;
  if (shared_.lockstep == nullptr) return Reason::clock_not_external;
  // CANopen synchronous semantics: the actual values sampled at this SYNC go out now; the
  // set-points received since the last SYNC (queued already, in order) act from the cycle's first
  // tick; frames arriving meanwhile wait in the socket for the next cycle. False: the run ended.
  send_telemetry();
  stats_.syncs.fetch_add(1, std::memory_order_relaxed);
  shared_.lockstep->advance(config_.sync_ticks);
  return Reason::none;
}

void CanTransport::send_telemetry() {
  if (shared_.can_faults.off() || shared_.telemetry_silent.load(std::memory_order_relaxed))
    return;  // a scenario's bus-off or telemetry silence
  const Telemetry t = shared_.telemetry.load();
  const RejectSnapshot rejects{static_cast<Reason>(shared_.rejects.last_reason.load()), shared_.rejects.count.load()};
  Port out(*this, true);
  profile_->send_telemetry(t, rejects, out);
}

void CanTransport::tx_loop() {
  const auto telemetry_period = static_cast<std::int64_t>(1e9 /
                                                          (config_.telemetry_hz > 0 ? config_.telemetry_hz : 100.0));
  // The loop runs at the profile's own interval when it has one (CANopen's services), else at
  // the telemetry period; the telemetry keeps its period either way.
  const std::int64_t interval = profile_->periodic_interval_ns();
  const std::int64_t period = interval > 0 ? interval : telemetry_period;
  std::int64_t next = monotonic_ns();
  std::int64_t next_telemetry = next;
  // Lockstep: telemetry goes out at each SYNC (on_sync), never on the wall clock.
  const bool periodic_telemetry = config_.telemetry_hz > 0 && shared_.lockstep == nullptr;
  // The profile's wall-clock frames; in lockstep they stay out of the recording (emulated time).
  Port periodic(*this, shared_.lockstep == nullptr);
  while (!stopping_.load(std::memory_order_relaxed)) {
    const std::int64_t now = monotonic_ns();
    if (periodic_telemetry && now >= next_telemetry) {
      send_telemetry();
      next_telemetry += telemetry_period;
      if (next_telemetry < now) next_telemetry = now + telemetry_period;  // fell behind: no burst
    }
    if (!shared_.can_faults.off()) profile_->send_periodic(now, periodic);
    next += period;
    if (next < now) next = now + period;  // fell behind (e.g. stopped in a debugger): no burst
    const timespec ts = to_timespec(next);
    while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
    }
  }
}

}  // namespace swum::emu
