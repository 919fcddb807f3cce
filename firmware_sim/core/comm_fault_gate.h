// A transport's communication faults (docs/scenarios.md: modbus_drop, modbus_delay,
// can_bus_off): the loop sets them at each tick boundary from the faults in force, the transport
// consults its own gate for every reply or frame. One shape for every transport, so a new one
// (or a new bus profile) gets the same drop/delay/off semantics without a new flag in
// SharedState; a fault a transport has no event for simply stays at rest. Lock-free atomics: the
// loop's tick and the transports' per-frame paths neither block nor allocate here.
#pragma once

#include <atomic>
#include <cstdint>

namespace swum::emu {

// The communication faults of one tick, for one transport.
struct CommFaults {
  std::uint64_t drops_started = 0;  // replies to withhold, added by events starting this tick
  double delay_ms = 0.0;            // every reply this late (emulated ms); 0: none
  bool off = false;                 // neither send nor receive (bus-off)
};

class CommFaultGate {
 public:
  // The loop, at a tick boundary: drops accumulate (each event counted once, at its start
  // tick) until the transport uses them; delay and off are the tick's state.
  void set(const CommFaults& faults) noexcept {
    if (faults.drops_started != 0) drops_.fetch_add(faults.drops_started, std::memory_order_relaxed);
    delay_ms_.store(faults.delay_ms, std::memory_order_relaxed);
    off_.store(faults.off, std::memory_order_relaxed);
  }
  // The transport, per reply: true when this one is withheld (one pending drop used up).
  bool take_drop() noexcept {
    for (std::uint64_t n = drops_.load(std::memory_order_relaxed); n > 0;) {
      if (drops_.compare_exchange_weak(n, n - 1, std::memory_order_relaxed)) return true;
    }
    return false;
  }
  [[nodiscard]] double delay_ms() const noexcept { return delay_ms_.load(std::memory_order_relaxed); }
  [[nodiscard]] bool off() const noexcept { return off_.load(std::memory_order_relaxed); }
  [[nodiscard]] std::uint64_t pending_drops() const noexcept { return drops_.load(std::memory_order_relaxed); }

 private:
  std::atomic<std::uint64_t> drops_{0};
  std::atomic<double> delay_ms_{0.0};
  std::atomic<bool> off_{false};
};

}  // namespace swum::emu
