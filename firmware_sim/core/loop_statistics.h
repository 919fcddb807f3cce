// Per-tick statistics of the real-time loop: log-linear histograms (HDR style: exact below
// 128 ns, then 64 sub-buckets per octave, < 1.6 % relative error) of the wake-up lateness and of
// the compute time per tick, plus the overrun count. Fixed storage; record() is O(1) and never
// allocates; summary() scans ~2400 buckets.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <initializer_list>
#include <string>

namespace swum::emu {

class Histogram {
 public:
  static constexpr std::size_t kBuckets = 128 + 35 * 64;
  void record(std::uint64_t value_ns);
  void clear();
  [[nodiscard]] std::uint64_t count() const { return count_; }
  [[nodiscard]] std::uint64_t max() const { return max_; }
  [[nodiscard]] std::uint64_t min() const { return count_ ? min_ : 0; }
  [[nodiscard]] double mean() const { return count_ ? static_cast<double>(sum_) / static_cast<double>(count_) : 0.0; }
  // Smallest bucket upper bound with at least q of the samples at or below it (clamped to max).
  [[nodiscard]] std::uint64_t percentile(double q) const;

  static std::size_t bucket_of(std::uint64_t value_ns);
  static std::uint64_t bucket_upper(std::size_t bucket);

 private:
  std::array<std::uint64_t, kBuckets> buckets_{};
  std::uint64_t count_ = 0;
  std::uint64_t sum_ = 0;
  std::uint64_t max_ = 0;
  std::uint64_t min_ = ~std::uint64_t{0};
};

// Plain summary, trivially copyable (published with the telemetry).
struct LoopStatsSummary {
  std::uint64_t ticks = 0;
  std::uint64_t overruns = 0;  // ticks whose work ended after the next tick's deadline
  std::uint64_t lateness_p50_ns = 0, lateness_p99_ns = 0, lateness_p999_ns = 0, lateness_max_ns = 0;
  std::uint64_t compute_p50_ns = 0, compute_p99_ns = 0, compute_max_ns = 0;
  double compute_mean_ns = 0.0;
  // Accept (transport thread) -> effect (start of the tick that applied it), per command.
  std::uint64_t commands = 0;
  std::uint64_t command_p50_ns = 0, command_p99_ns = 0, command_max_ns = 0;
};

class LoopStatistics {
 public:
  void record(std::uint64_t lateness_ns, std::uint64_t compute_ns, bool overrun) {
    lateness_.record(lateness_ns);
    compute_.record(compute_ns);
    if (overrun) ++overruns_;
  }
  void record_command_latency(std::uint64_t ns) { command_.record(ns); }
  [[nodiscard]] LoopStatsSummary summary() const;
  [[nodiscard]] const Histogram& lateness() const { return lateness_; }
  [[nodiscard]] const Histogram& compute() const { return compute_; }
  [[nodiscard]] std::uint64_t overruns() const { return overruns_; }

 private:
  Histogram lateness_;
  Histogram compute_;
  Histogram command_;
  std::uint64_t overruns_ = 0;
};

// Multi-line human-readable report (printed at exit).
std::string format_summary(const LoopStatsSummary& s, double tick_hz);

// What a transport threw away on its own, by reason: Modbus TCP connections it closed and Modbus
// RTU frames it discarded (docs/emulator.md, "Modbus: no client locks the others out"). Counted
// by the transport threads, printed with the loop statistics at exit.
enum class Drop : std::uint8_t {
  no_slot,        // TCP: every slot busy, no holder idle long enough to evict: closed at once
  evicted,        // TCP: the longest-idle holder, closed to make room for a new connection
  idle,           // TCP: no request for --modbus-idle-timeout-ms
  frame_timeout,  // TCP, RTU: a request still incomplete at its deadline (first byte + frame timeout)
  reply_timeout,  // TCP: a reply the client did not take within the frame timeout
  bad_header,     // TCP: MBAP protocol id not 0, or a length field shorter than the frame or beyond an ADU
  too_long,       // TCP: a request longer than an ADU (260 bytes) by its function code's byte count
  other_unit,     // RTU: a well-formed frame for another unit id (not an error: a shared line)
  bad_crc,        // RTU: CRC mismatch (garbage, noise, a frame cut short)
  bad_length,     // RTU: a frame that would exceed 256 bytes
  partial_frame,  // RTU: a frame that stopped: silence before its last byte
  kCount
};
const char* to_string(Drop d);

class DropCounters {
 public:
  // Returns the count of `d` including this one (callers log the first few).
  std::uint64_t count(Drop d) {
    return counts_[static_cast<std::size_t>(d)].fetch_add(1, std::memory_order_relaxed) + 1;
  }
  [[nodiscard]] std::uint64_t operator[](Drop d) const {
    return counts_[static_cast<std::size_t>(d)].load(std::memory_order_relaxed);
  }

 private:
  std::array<std::atomic<std::uint64_t>, static_cast<std::size_t>(Drop::kCount)> counts_{};
};

// One report line: "  LABEL  no slot 3, evicted 1, ..." over the reasons in `shown`, in that order.
std::string format_drops(const char* label, const DropCounters& counts, std::initializer_list<Drop> shown);

}  // namespace swum::emu
