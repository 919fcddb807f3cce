#include "core/loop_statistics.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>

namespace swum::emu {

std::size_t Histogram::bucket_of(std::uint64_t v) {
  if (v < 128) return static_cast<std::size_t>(v);
  const int msb = 63 - std::countl_zero(v);
  const int shift = msb - 6;  // v >> shift in [64, 127]
  const std::size_t index = 128 + static_cast<std::size_t>(shift - 1) * 64 +
                            static_cast<std::size_t>((v >> shift) - 64);
  return std::min(index, kBuckets - 1);
}

std::uint64_t Histogram::bucket_upper(std::size_t bucket) {
  if (bucket < 128) return bucket;
  const std::size_t k = bucket - 128;
  const unsigned shift = static_cast<unsigned>(k / 64 + 1);
  const std::uint64_t sub = k % 64 + 64;
  return ((sub + 1) << shift) - 1;
}

void Histogram::record(std::uint64_t v) {
  ++buckets_[bucket_of(v)];
  ++count_;
  sum_ += v;
  max_ = std::max(max_, v);
  min_ = std::min(min_, v);
}

void Histogram::clear() { *this = Histogram{}; }

std::uint64_t Histogram::percentile(double q) const {
  if (count_ == 0) return 0;
  const auto rank = static_cast<std::uint64_t>(std::ceil(q * static_cast<double>(count_)));
  std::uint64_t seen = 0;
  for (std::size_t i = 0; i < kBuckets; ++i) {
    seen += buckets_[i];
    if (seen >= std::max<std::uint64_t>(rank, 1)) return std::min(bucket_upper(i), max_);
  }
  return max_;
}

LoopStatsSummary LoopStatistics::summary() const {
  LoopStatsSummary s;
  s.ticks = lateness_.count();
  s.overruns = overruns_;
  s.lateness_p50_ns = lateness_.percentile(0.50);
  s.lateness_p99_ns = lateness_.percentile(0.99);
  s.lateness_p999_ns = lateness_.percentile(0.999);
  s.lateness_max_ns = lateness_.max();
  s.compute_p50_ns = compute_.percentile(0.50);
  s.compute_p99_ns = compute_.percentile(0.99);
  s.compute_max_ns = compute_.max();
  s.compute_mean_ns = compute_.mean();
  s.commands = command_.count();
  s.command_p50_ns = command_.percentile(0.50);
  s.command_p99_ns = command_.percentile(0.99);
  s.command_max_ns = command_.max();
  return s;
}

std::string format_summary(const LoopStatsSummary& s, double tick_hz) {
  char buffer[900];
  const double pct = s.ticks ? 100.0 * static_cast<double>(s.overruns) / static_cast<double>(s.ticks) : 0.0;
  std::snprintf(buffer, sizeof buffer,
                "loop statistics: %llu ticks at %.0f Hz (%.3f s emulated)\n"
                "  lateness  p50 %.1f us  p99 %.1f us  p99.9 %.1f us  max %.1f us\n"
                "  compute   mean %.1f us  p50 %.1f us  p99 %.1f us  max %.1f us\n"
                "  overruns  %llu (%.4f %% of ticks)\n"
                "  commands  %llu; accept-to-effect p50 %.1f us  p99 %.1f us  max %.1f us\n",
                static_cast<unsigned long long>(s.ticks), tick_hz, static_cast<double>(s.ticks) / tick_hz,
                static_cast<double>(s.lateness_p50_ns) / 1e3, static_cast<double>(s.lateness_p99_ns) / 1e3,
                static_cast<double>(s.lateness_p999_ns) / 1e3, static_cast<double>(s.lateness_max_ns) / 1e3,
                s.compute_mean_ns / 1e3, static_cast<double>(s.compute_p50_ns) / 1e3,
                static_cast<double>(s.compute_p99_ns) / 1e3, static_cast<double>(s.compute_max_ns) / 1e3,
                static_cast<unsigned long long>(s.overruns), pct, static_cast<unsigned long long>(s.commands),
                static_cast<double>(s.command_p50_ns) / 1e3, static_cast<double>(s.command_p99_ns) / 1e3,
                static_cast<double>(s.command_max_ns) / 1e3);
  return buffer;
}

const char* to_string(Drop d) {
  switch (d) {
    case Drop::no_slot: return "no slot";
    case Drop::evicted: return "evicted";
    case Drop::idle: return "idle";
    case Drop::frame_timeout: return "frame timeout";
    case Drop::reply_timeout: return "reply timeout";
    case Drop::bad_header: return "bad header";
    case Drop::too_long: return "too long";
    case Drop::other_unit: return "other unit";
    case Drop::bad_crc: return "bad crc";
    case Drop::bad_length: return "bad length";
    case Drop::partial_frame: return "partial frame";
    case Drop::kCount: break;
  }
  return "?";
}

std::string format_drops(const char* label, const DropCounters& counts, std::initializer_list<Drop> shown) {
  std::string line = std::string("  ") + label + " ";
  const char* separator = "";
  for (const Drop d : shown) {
    line += separator;
    line += to_string(d);
    line += ' ';
    line += std::to_string(counts[d]);
    separator = ", ";
  }
  return line + "\n";
}

}  // namespace swum::emu
