// The Modbus RTU server (modbus_server.h): one thread frames the serial line itself (the
// frame-length rule and CRC of protocol/modbus_rtu, with the frame deadline and the inter-frame
// gap), serves each request by modbus_serve; libmodbus only builds and sends the replies.
#include "transports/modbus_server.h"

#include <modbus.h>
#include <poll.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <optional>
#include <span>
#include <stdexcept>

#include "modbus_codec.h"
#include "modbus_rtu.h"
#include "transports/modbus_serve.h"

namespace swum::emu {

namespace rtu = protocol::modbus::rtu;
// The frame-length rule (rtu::request_length) stops at rtu::kMaxAduLength bytes, the buffer
// below is libmodbus's largest RTU ADU, and the server hands libmodbus that buffer: one size.
static_assert(rtu::kMaxAduLength == MODBUS_RTU_MAX_ADU_LENGTH,
              "protocol/modbus_rtu.h's kMaxAduLength must be libmodbus's MODBUS_RTU_MAX_ADU_LENGTH");

ModbusRtuServer::ModbusRtuServer(const std::string& device, int baud, int unit, SharedState& shared,
                                 AmplifierLimits limits, int frame_timeout_ms)
    : device_(device), baud_(baud), unit_(unit), frame_timeout_ms_(frame_timeout_ms), shared_(shared), limits_(limits) {
  modbus_t* ctx = modbus_new_rtu(device.c_str(), baud, 'N', 8, 1);
  if (!ctx) throw std::runtime_error("Modbus RTU: " + errno_text("modbus_new_rtu", errno));
  if (modbus_set_slave(ctx, unit) != 0) {
    const int e = errno;
    modbus_free(ctx);
    throw std::runtime_error("Modbus RTU: unit id " + std::to_string(unit) + ": " + modbus_strerror(e));
  }
  if (modbus_connect(ctx) != 0) {
    const int e = errno;
    modbus_free(ctx);
    throw std::runtime_error("Modbus RTU: cannot open " + device + ": " + modbus_strerror(e));
  }
  // Frames are read here (loop()); libmodbus only builds and sends the replies. Should it ever
  // flush the line after a reply (it does after some refusals), it first sleeps this long.
  if (modbus_set_response_timeout(ctx, 0, 20000) != 0) {
    const int e = errno;
    modbus_close(ctx);
    modbus_free(ctx);
    throw std::runtime_error("Modbus RTU: modbus_set_response_timeout: " + std::string(modbus_strerror(e)));
  }
  ctx_ = ctx;
}

ModbusRtuServer::~ModbusRtuServer() {
  stop();
  if (ctx_) {
    modbus_close(static_cast<modbus_t*>(ctx_));
    modbus_free(static_cast<modbus_t*>(ctx_));
  }
}

void ModbusRtuServer::start() {
  thread_ = std::thread([this] { loop(); });
}

void ModbusRtuServer::stop() {
  stopping_.store(true);
  if (thread_.joinable()) thread_.join();
}

namespace {

// 8N1: ten bits a character.
std::uint64_t character_ns(int baud) { return 10'000'000'000ULL / static_cast<std::uint64_t>(baud); }

// Waits until `fd` is readable or `timeout_ns` passed (bounded so that stop() is seen). 1:
// readable, 0: not (yet), -1: the line failed (hang-up, error; errno set).
int wait_readable(int fd, std::uint64_t timeout_ns) {
  timeout_ns = std::min<std::uint64_t>(timeout_ns, 200'000'000ULL);
  const timespec ts = to_timespec(static_cast<std::int64_t>(timeout_ns));
  pollfd p{fd, POLLIN, 0};
  const int r = ::ppoll(&p, 1, &ts, nullptr);
  if (r < 0) return errno == EINTR ? 0 : -1;
  if (r == 0) return 0;
  if (p.revents & POLLIN) return 1;
  errno = (p.revents & POLLHUP) ? EPIPE : EIO;  // hang-up or error without data
  return -1;
}

}  // namespace

void ModbusRtuServer::drain(int fd) {
  // Resynchronise on the RTU inter-frame gap: a frame for another unit (and that unit's
  // answer), garbage, the tail of a cut frame are discarded until the line has been silent
  // for max(3.5 characters, 5 ms).
  const std::uint64_t silence = std::max<std::uint64_t>(35 * character_ns(baud_) / 10, 5'000'000ULL);
  std::uint64_t last = now_ns();
  while (!stopping_.load(std::memory_order_relaxed)) {
    const std::uint64_t now = now_ns();
    if (now >= last + silence) return;
    const int r = wait_readable(fd, last + silence - now);
    if (r < 0) return;  // the next read reports it
    if (r == 0) continue;
    std::uint8_t junk[256];
    const ssize_t got = ::read(fd, junk, sizeof junk);
    if (got > 0) last = now_ns();
    else if (got < 0 && errno != EAGAIN && errno != EINTR) return;
  }
}

void ModbusRtuServer::loop() {
  auto* ctx = static_cast<modbus_t*>(ctx_);
  modbus_mapping_t* map = modbus_mapping_new(0, 0, protocol::modbus::holding::kCount, protocol::modbus::input::kCount);
  if (!map) {
    std::fprintf(stderr, "swum-emu: Modbus RTU: cannot allocate a libmodbus mapping\n");
    return;
  }
  const int fd = modbus_get_socket(ctx);
  const std::uint64_t character = character_ns(baud_);
  // Inside a frame a silence this long ends it (Modbus over serial line: 1.5 characters; USB
  // adapters deliver in bursts up to their latency timer, FTDI's 16 ms by default).
  const std::uint64_t gap = std::max<std::uint64_t>(35 * character / 10, 20'000'000ULL);
  // From its first byte a request has the frame timeout plus the time of a largest frame.
  const std::uint64_t budget = ms_to_ns(frame_timeout_ms_) + std::uint64_t{rtu::kMaxAduLength} * character;
  std::uint8_t adu[MODBUS_RTU_MAX_ADU_LENGTH];
  std::uint64_t line_errors = 0;
  auto line_failed = [&](int e) {
    if (++line_errors <= 5)
      std::fprintf(stderr, "swum-emu: Modbus RTU: %s: %s%s\n", device_.c_str(), std::strerror(e),
                   line_errors == 5 ? " (further errors counted only)" : "");
    stats_.receive_errors.fetch_add(1);
    ::poll(nullptr, 0, 100);  // a hung-up line stays readable: do not spin
  };
  auto discard = [&](Drop why, bool then_drain) {
    stats_.drops.count(why);
    if (then_drain) drain(fd);
  };
  while (!stopping_.load(std::memory_order_relaxed)) {
    // Idle: wait for the first byte.
    const int first = wait_readable(fd, 200'000'000ULL);
    if (first < 0) {
      line_failed(errno);
      continue;
    }
    if (first == 0) continue;
    const std::uint64_t deadline = now_ns() + budget;
    std::uint64_t last_byte = now_ns();
    std::size_t have = 0;
    bool failed = false;
    std::optional<Drop> dropped;
    for (;;) {
      const int need = rtu::request_length(std::span<const std::uint8_t>(adu, have));
      if (need < 0) {
        dropped = Drop::bad_length;
        break;
      }
      if (static_cast<std::size_t>(need) == have) break;  // complete
      const std::uint64_t now = now_ns();
      if (now >= deadline) {
        dropped = Drop::frame_timeout;
        break;
      }
      if (have > 0 && now >= last_byte + gap) {
        dropped = Drop::partial_frame;
        break;
      }
      if (stopping_.load(std::memory_order_relaxed)) break;
      const int r = wait_readable(fd, std::min(deadline, have > 0 ? last_byte + gap : deadline) - now);
      if (r < 0) {
        failed = true;
        break;
      }
      if (r == 0) continue;
      // Read no further than this frame: the next one may already be behind it.
      const ssize_t got = ::read(fd, adu + have, static_cast<std::size_t>(need) - have);
      if (got < 0) {
        if (errno == EAGAIN || errno == EINTR) continue;
        failed = true;
        break;
      }
      if (got == 0) continue;
      have += static_cast<std::size_t>(got);
      last_byte = now_ns();
    }
    if (failed) {
      line_failed(errno);
      continue;
    }
    if (stopping_.load(std::memory_order_relaxed)) break;
    if (dropped) {
      // A partial frame ended in silence: the line is quiet already, the next byte starts a frame.
      discard(*dropped, *dropped != Drop::partial_frame);
      continue;
    }
    const std::uint16_t crc = rtu::crc16(std::span<const std::uint8_t>(adu, have - 2));
    if (adu[have - 2] != (crc & 0xFF) || adu[have - 1] != (crc >> 8)) {
      discard(Drop::bad_crc, true);
      continue;
    }
    if (adu[0] != unit_ && adu[0] != 0) {  // 0: broadcast, served without an answer (libmodbus)
      discard(Drop::other_unit, true);     // and skip that unit's answer
      continue;
    }
    serve(ctx, adu, static_cast<int>(have), 2, map, shared_, limits_, stats_);
  }
  modbus_mapping_free(map);
}

}  // namespace swum::emu
