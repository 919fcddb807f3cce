// Fuzz target: the alive-counter rule of swum-emu's CAN command frames (protocol/can_codec.h
// AliveCounter), over a stream of frames of one identifier the way the CAN transport uses it:
// check(), and accept() only what check() passed.
// Input: 3 bytes per frame: the 4-bit counter (low nibble of byte 0; bit 7: a sender that counts
// correctly with next_alive() instead), then the time since the previous frame (bytes 1-2,
// little-endian, in units of 20 ms: 0 .. 21 min, so both sides of the 1 s resync are reached).
// Invariants: check() answers exactly the documented rule (first frame, and the first after
// more than 1 s, take any counter; otherwise 1..7 ahead mod 16 passes and 0 or 8..15 ahead is
// stale), a refused frame changes nothing (the next answer is the same as if it never came), and
// a sender counting with next_alive() at least once a second is never refused.
#include <cstddef>
#include <cstdint>

#include "can_codec.h"
#include "fuzz_check.h"

namespace {

using swum::protocol::Reason;
namespace can = swum::protocol::can;

constexpr std::int64_t kStepNs = 20'000'000;

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  can::AliveCounter counter;
  bool seen = false;
  std::uint8_t last = 0;
  std::int64_t last_ns = 0;
  std::int64_t now = 1'000'000'000;  // a monotonic clock well after its epoch
  bool honest_so_far = true;         // every frame from next_alive(), at most 1 s apart
  for (std::size_t i = 0; i + 3 <= size; i += 3) {
    const bool honest = (data[i] & 0x80U) != 0;
    const std::int64_t gap = static_cast<std::int64_t>(data[i + 1] | (data[i + 2] << 8)) * kStepNs;
    now += gap;
    const std::uint8_t alive = honest && seen ? can::next_alive(last) : static_cast<std::uint8_t>(data[i] & 0x0FU);
    honest_so_far = honest_so_far && (!seen || (honest && gap <= can::kAliveResyncNs));

    const unsigned ahead = (static_cast<unsigned>(alive) - last) & 0x0FU;
    const bool fresh = !seen || now - last_ns > can::kAliveResyncNs || (ahead >= 1 && ahead <= 7);
    const Reason why = counter.check(alive, now);
    FUZZ_CHECK((why == Reason::none) == fresh, "frame %zu: counter %u after %u, %lld ns later: %s", i / 3, alive, last,
               static_cast<long long>(now - last_ns), swum::protocol::to_string(why));
    FUZZ_CHECK(why == Reason::none || why == Reason::stale_alive_counter, "reason %s", swum::protocol::to_string(why));
    if (honest_so_far) FUZZ_CHECK(why == Reason::none, "a correctly counting sender refused at frame %zu", i / 3);
    if (why != Reason::none) continue;  // refused: changes nothing (the model keeps its state too)
    counter.accept(alive, now);
    seen = true;
    last = alive;
    last_ns = now;
  }
  return 0;
}
