// Per-tick statistics of the real-time loop: log-linear histograms (HDR style: exact below
// 128 ns, then 64 sub-buckets per octave, < 1.6 % relative error) of the wake-up lateness and of
// the compute time per tick, plus the overrun count. Fixed storage; record() is O(1) and never
// allocates; summary() scans ~2400 buckets.
#pragma once

#include <array>
#include <cstdint>
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
  std::uint64_t overruns = 0;        // ticks whose work ended after the next tick's deadline
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

}  // namespace swum::emu
