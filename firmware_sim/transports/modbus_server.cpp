#include "transports/modbus_server.h"

#include "core/lockstep_clock.h"
#include "core/monotonic_clock.h"

#include <arpa/inet.h>
#include <modbus.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/eventfd.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <optional>
#include <stdexcept>
#include <system_error>

#include "modbus_codec.h"

namespace swum::emu {

namespace {

std::string errno_text(const char* call, int e) { return std::string(call) + ": " + std::strerror(e); }

// The deadlines here are unsigned nanoseconds on the shared monotonic clock.
std::uint64_t now_ns() { return static_cast<std::uint64_t>(monotonic_ns()); }

std::uint64_t ms_to_ns(int ms) { return static_cast<std::uint64_t>(ms) * 1'000'000ULL; }

// Phases of a TCP connection (ModbusTcpServer::Connection::phase).
constexpr int kIdle = 0;       // waiting for a request's first byte: the idle timeout runs
constexpr int kReceiving = 1;  // inside a request: the frame timeout runs from its first byte
constexpr int kReplying = 2;   // serving and sending: the frame timeout runs again
constexpr int kClosing = 3;    // shut down by the server (or ended); no longer holds a slot
constexpr int kStepping = 4;   // lockstep: waiting for the ticks it asked for; no deadline runs

void wake(int eventfd_fd) {
  const std::uint64_t one = 1;
  if (::write(eventfd_fd, &one, sizeof one) < 0 && errno != EAGAIN)  // EAGAIN: a wake-up is pending anyway
    std::fprintf(stderr, "swum-emu: Modbus TCP: %s\n", errno_text("write(eventfd)", errno).c_str());
}

// Ends every blocking call on the socket in its client thread (ENOTCONN: the peer is gone already).
void shut(int fd) {
  if (fd >= 0 && ::shutdown(fd, SHUT_RDWR) != 0 && errno != ENOTCONN)
    std::fprintf(stderr, "swum-emu: Modbus TCP: %s\n", errno_text("shutdown", errno).c_str());
}

// Bytes of the next request already in the socket: the connection is no longer idle (idle time
// ends at a request's first byte), even when its thread has not yet run to read them, as in a
// starved or descheduled process. False at end of stream.
bool request_waiting(int fd) {
  int bytes = 0;
  return fd >= 0 && ::ioctl(fd, FIONREAD, &bytes) == 0 && bytes > 0;
}

// Nothing of the reply is waiting in the send queue: the client is not holding it up (a client
// that does not read keeps the queue full); only the connection's own thread has yet to move on.
bool nothing_unsent(int fd) {
  int bytes = 0;
  return fd >= 0 && ::ioctl(fd, TIOCOUTQ, &bytes) == 0 && bytes == 0;
}

// The first few connections closed for each reason go to stderr; all are counted.
void log_drop(std::uint64_t nth, Drop reason, const std::string& peer) {
  constexpr std::uint64_t kLogged = 5;
  if (nth > kLogged) return;
  std::fprintf(stderr, "swum-emu: Modbus TCP: closed %s: %s%s\n", peer.c_str(), to_string(reason),
               nth == kLogged ? " (further ones counted only)" : "");
}

// Reads and drops `count` bytes of the request being received (blocking: the frame deadline
// shuts the socket down). False on end of stream or an error.
bool discard_bytes(int fd, std::size_t count) {
  std::array<std::uint8_t, 256> sink{};
  while (count > 0) {
    const ssize_t n = ::recv(fd, sink.data(), std::min(count, sink.size()), 0);
    if (n > 0) {
      count -= static_cast<std::size_t>(n);
    } else if (n < 0 && errno == EINTR) {
      continue;
    } else {
      return false;
    }
  }
  return true;
}

// One request: validate, queue writes, serve reads. False when the connection should close.
// `surplus`: the MBAP length counted bytes after what the function code frames; a supported
// function code with them is malformed (exception 03, wrong length), an unsupported one is
// refused as such (01).
// A scenario's communication faults, after the request was processed: false when its reply is
// withheld (modbus_drop: the next N requests; telemetry_silence: FC04 reads); a modbus_delay
// holds the reply back by delay_ms of emulated time (lockstep: the motor runs on that many ticks
// while the controller waits; wall time: delay_ms / speedup).
bool reply_allowed(SharedState& shared, std::uint8_t function, ModbusStats& stats,
                   const std::function<bool(bool)>& stepping) {
  for (std::uint64_t drops = shared.modbus_drops.load(std::memory_order_relaxed); drops > 0;) {
    if (shared.modbus_drops.compare_exchange_weak(drops, drops - 1, std::memory_order_relaxed)) {
      stats.withheld_replies.fetch_add(1, std::memory_order_relaxed);
      return false;
    }
  }
  if (function == protocol::modbus::kReadInputRegisters && shared.telemetry_silent.load(std::memory_order_relaxed)) {
    stats.withheld_replies.fetch_add(1, std::memory_order_relaxed);
    return false;
  }
  const double delay_ms = shared.modbus_delay_ms.load(std::memory_order_relaxed);
  if (delay_ms > 0.0) {
    stats.delayed_replies.fetch_add(1, std::memory_order_relaxed);
    if (stepping && !stepping(true)) return false;  // the delay is the device's: no deadline on it
    if (shared.lockstep != nullptr) {
      const auto ticks = static_cast<std::uint64_t>(std::llround(delay_ms * 1e-3 * shared.tick_hz));
      if (ticks > 0) shared.lockstep->advance(ticks);
    } else if (shared.speedup > 0.0) {
      const auto ns = static_cast<long long>(delay_ms * 1e6 / shared.speedup);
      timespec pause{static_cast<time_t>(ns / 1'000'000'000), static_cast<long>(ns % 1'000'000'000)};
      while (nanosleep(&pause, &pause) != 0 && errno == EINTR) {
      }
    }
    if (stepping && !stepping(false)) return false;
  }
  return true;
}

// `stepping(true)` before a lockstep step waits for the loop, `stepping(false)` after it (the TCP
// server suspends the connection's deadlines meanwhile); false: the connection is being closed.
using SteppingHook = std::function<bool(bool)>;
bool serve(modbus_t* ctx, const std::uint8_t* adu, int length, int checksum_length, modbus_mapping_t* map,
           SharedState& shared, const AmplifierLimits& limits, ModbusStats& stats, bool surplus = false,
           const SteppingHook& stepping = {}) {
  stats.requests.fetch_add(1, std::memory_order_relaxed);
  const int header = modbus_get_header_length(ctx);
  const int pdu_length = length - header - checksum_length;
  if (pdu_length < 1) return true;
  const std::span<const std::uint8_t> pdu(adu + header, static_cast<std::size_t>(pdu_length));

  protocol::modbus::Request request;
  Reason reason = Reason::none;
  std::uint8_t exception = protocol::modbus::parse_request(pdu, request, &reason);
  if (surplus && exception == protocol::modbus::kNoException) {
    exception = protocol::modbus::kIllegalDataValue;
    reason = Reason::wrong_length;
  }
  protocol::modbus::Decision decision;
  if (exception == protocol::modbus::kNoException) {
    decision = protocol::modbus::decide(request, limits);
    exception = decision.exception;
    reason = decision.reason;
    if (exception == protocol::modbus::kNoException && decision.advance_ticks != 0 && shared.lockstep == nullptr) {
      exception = protocol::modbus::kIllegalDataValue;  // nothing of the request is applied
      reason = Reason::clock_not_external;
    }
  }
  if (exception == protocol::modbus::kNoException && decision.has_command) {
    decision.command.accepted_ns = now_ns();
    if (shared.submit(decision.command) != Reason::none) exception = protocol::modbus::kServerDeviceBusy;
  }
  if (exception == protocol::modbus::kNoException && decision.advance_ticks != 0) {
    // The command above is queued first, so the first of these ticks applies it.
    if (stepping && !stepping(true)) return false;
    const bool ran = shared.lockstep->advance(decision.advance_ticks);
    if (stepping && !stepping(false)) return false;
    if (!ran) exception = protocol::modbus::kServerDeviceFailure;  // the emulator stopped first
  }
  if (!reply_allowed(shared, pdu[0], stats, stepping)) return true;  // a scenario's communication fault
  if (exception != protocol::modbus::kNoException) {
    stats.exceptions.fetch_add(1, std::memory_order_relaxed);
    if (exception != protocol::modbus::kServerDeviceBusy && exception != protocol::modbus::kServerDeviceFailure)
      shared.rejects.record(reason, CommandSource::modbus);
    if (pdu[0] & 0x80) {
      // libmodbus answers function + 0x80 in one byte: a code that has the top bit already
      // (128-255, those of exception replies) would come back as function - 128, e.g. 0x84 as
      // "04 01", a malformed FC04 reply. With the bit cleared in the request it gives function | 0x80.
      std::array<std::uint8_t, 8> head{};  // the MBAP header (7) or the RTU unit id (1), then the code
      if (header + 1 > static_cast<int>(head.size())) return false;
      std::copy_n(adu, header + 1, head.begin());
      head[static_cast<std::size_t>(header)] &= 0x7F;
      return modbus_reply_exception(ctx, head.data(), exception) != -1;
    }
    return modbus_reply_exception(ctx, adu, exception) != -1;
  }
  const Telemetry t = shared.telemetry.load();
  if (request.function == protocol::modbus::kReadInputRegisters) {
    const RejectSnapshot rejects{static_cast<Reason>(shared.rejects.last_reason.load(std::memory_order_relaxed)),
                                 shared.rejects.count.load(std::memory_order_acquire)};
    protocol::modbus::fill_input(t, rejects,
                                 std::span<std::uint16_t, protocol::modbus::input::kCount>(
                                     map->tab_input_registers, protocol::modbus::input::kCount));
  } else {
    protocol::modbus::fill_holding(t, std::span<std::uint16_t, protocol::modbus::holding::kCount>(
                                          map->tab_registers, protocol::modbus::holding::kCount));
  }
  return modbus_reply(ctx, adu, length, map) != -1;
}

}  // namespace

ModbusTcpServer::ModbusTcpServer(const std::string& host, std::uint16_t port, SharedState& shared,
                                 AmplifierLimits limits, ModbusTcpOptions options)
    : host_(host), shared_(shared), limits_(limits), options_(options) {
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(port);
  if (inet_pton(AF_INET, host.c_str(), &address.sin_addr) != 1)
    throw std::runtime_error("Modbus TCP: '" + host + "' is not an IPv4 address");
  listen_fd_ = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (listen_fd_ < 0) throw std::runtime_error("Modbus TCP: " + errno_text("socket", errno));
  const int one = 1;
  if (setsockopt(listen_fd_, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one) != 0) {
    const int e = errno;
    ::close(listen_fd_);
    throw std::runtime_error("Modbus TCP: " + errno_text("setsockopt(SO_REUSEADDR)", e));
  }
  if (::bind(listen_fd_, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0) {
    const int e = errno;
    ::close(listen_fd_);
    throw std::runtime_error("Modbus TCP: cannot bind " + host + ":" + std::to_string(port) + ": " +
                             errno_text("bind", e));
  }
  if (::listen(listen_fd_, 64) != 0) {  // a burst of connections waits here to be sorted, not dropped
    const int e = errno;
    ::close(listen_fd_);
    throw std::runtime_error("Modbus TCP: " + errno_text("listen", e));
  }
  socklen_t len = sizeof address;
  if (getsockname(listen_fd_, reinterpret_cast<sockaddr*>(&address), &len) != 0) {
    const int e = errno;
    ::close(listen_fd_);
    throw std::runtime_error("Modbus TCP: " + errno_text("getsockname", e));
  }
  port_ = ntohs(address.sin_port);
  wake_fd_ = eventfd(0, EFD_CLOEXEC | EFD_NONBLOCK);
  if (wake_fd_ < 0) {
    const int e = errno;
    ::close(listen_fd_);
    throw std::runtime_error("Modbus TCP: " + errno_text("eventfd", e));
  }
}

// One client connection. phase, since_ns, reason and fd are guarded by the server's mutex_.
struct ModbusTcpServer::Connection {
  int fd = -1;                 // closed (and -1) once the client thread has ended
  std::string peer;            // "ADDRESS:PORT", for the log
  int phase = kIdle;           // kIdle, kReceiving, kReplying, kClosing
  std::uint64_t since_ns = 0;  // start of the phase (kIdle: accept or last reply)
  std::optional<Drop> reason;  // why the server closes it; none when the client hung up
  bool ended = false;          // the thread is done with the connection (join it)
  std::thread thread;
};

ModbusTcpServer::~ModbusTcpServer() {
  stop();
  if (listen_fd_ >= 0) ::close(listen_fd_);
  if (wake_fd_ >= 0) ::close(wake_fd_);
}

void ModbusTcpServer::start() {
  acceptor_ = std::thread([this] { supervise(); });
}

void ModbusTcpServer::stop() {
  if (stopping_.exchange(true)) return;
  wake(wake_fd_);
  if (acceptor_.joinable()) acceptor_.join();
  // A request being answered gets its reply out before the sockets close (within one frame
  // timeout): e.g. a lockstep step that the end of the run has just answered with exception 04.
  const std::uint64_t until = now_ns() + ms_to_ns(options_.frame_timeout_ms);
  for (;;) {
    {
      std::lock_guard lock(mutex_);
      if (std::none_of(connections_.begin(), connections_.end(),
                       [](const auto& c) { return !c->ended && (c->phase == kStepping || c->phase == kReplying); }))
        break;
    }
    if (now_ns() >= until) break;
    const timespec pause{0, 1'000'000};
    nanosleep(&pause, nullptr);
  }
  {
    std::lock_guard lock(mutex_);
    for (auto& c : connections_) {
      c->phase = kClosing;
      if (!c->ended) shut(c->fd);  // wakes poll / modbus_receive / send in the client thread
    }
  }
  for (auto& c : connections_) {
    if (c->thread.joinable()) c->thread.join();
  }
  connections_.clear();
}

void ModbusTcpServer::supervise() {
  int timeout_ms = -1;
  for (;;) {
    pollfd fds[2] = {{listen_fd_, POLLIN, 0}, {wake_fd_, POLLIN, 0}};
    const int rc = ::poll(fds, 2, timeout_ms);
    if (rc < 0 && errno != EINTR) {
      std::fprintf(stderr, "swum-emu: Modbus TCP: %s (no longer accepting)\n", errno_text("poll", errno).c_str());
      return;
    }
    if (rc > 0 && (fds[1].revents & POLLIN)) {
      std::uint64_t count = 0;
      if (::read(wake_fd_, &count, sizeof count) < 0 && errno != EAGAIN)
        std::fprintf(stderr, "swum-emu: Modbus TCP: %s\n", errno_text("read(eventfd)", errno).c_str());
    }
    // After draining the eventfd, not before: a stop() between the check and the read would
    // have its wake-up swallowed and leave this thread in poll(-1) for ever.
    if (stopping_.load()) return;
    reap();
    if (rc > 0 && (fds[0].revents & POLLIN)) accept_one(now_ns());
    timeout_ms = enforce_deadlines(now_ns());
  }
}

void ModbusTcpServer::accept_one(std::uint64_t now) {
  sockaddr_in address{};
  socklen_t length = sizeof address;
  const int fd = ::accept4(listen_fd_, reinterpret_cast<sockaddr*>(&address), &length, SOCK_CLOEXEC);
  if (fd < 0) {
    const int e = errno;
    if (e != EINTR && e != EAGAIN && e != ECONNABORTED)
      std::fprintf(stderr, "swum-emu: Modbus TCP: %s\n", errno_text("accept", e).c_str());
    if (e == EMFILE || e == ENFILE) ::poll(nullptr, 0, 10);  // out of descriptors: do not spin
    return;
  }
  char text[INET_ADDRSTRLEN] = "?";
  if (!inet_ntop(AF_INET, &address.sin_addr, text, sizeof text))
    std::fprintf(stderr, "swum-emu: Modbus TCP: %s\n", errno_text("inet_ntop", errno).c_str());
  const std::string peer = std::string(text) + ":" + std::to_string(ntohs(address.sin_port));

  std::unique_lock lock(mutex_);
  const auto holders = std::count_if(connections_.begin(), connections_.end(),
                                     [](const auto& c) { return c->phase != kClosing; });
  if (holders >= options_.max_clients) {
    // Every slot taken: the longest-idle holder makes room if it has been idle long enough;
    // otherwise the newcomer is closed at once (a bound on threads: at most as many connections
    // again may still be closing).
    Connection* victim = nullptr;
    const std::uint64_t guard = ms_to_ns(options_.evict_idle_ms);
    for (auto& c : connections_) {
      // since_ns may be later than `now` (taken before the lock): not idle, and no unsigned wrap.
      if (c->phase == kIdle && c->since_ns <= now && now - c->since_ns >= guard &&
          (!victim || c->since_ns < victim->since_ns) && !request_waiting(c->fd))
        victim = c.get();
    }
    if (!victim || connections_.size() >= 2 * static_cast<std::size_t>(options_.max_clients)) {
      lock.unlock();
      if (::close(fd) != 0) std::fprintf(stderr, "swum-emu: Modbus TCP: %s\n", errno_text("close", errno).c_str());
      log_drop(stats_.drops.count(Drop::no_slot), Drop::no_slot, peer);
      return;
    }
    victim->phase = kClosing;
    victim->reason = Drop::evicted;
    shut(victim->fd);
  }
  const int one = 1;
  if (setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one) != 0)
    std::fprintf(stderr, "swum-emu: Modbus TCP: %s\n", errno_text("setsockopt(TCP_NODELAY)", errno).c_str());
  auto connection = std::make_unique<Connection>();
  connection->fd = fd;
  connection->peer = peer;
  connection->since_ns = now;
  Connection& c = *connection;
  connections_.push_back(std::move(connection));
  try {
    c.thread = std::thread([this, &c] { client_loop(c); });
  } catch (const std::system_error& e) {
    std::fprintf(stderr, "swum-emu: Modbus TCP: cannot start a client thread: %s\n", e.what());
    if (::close(fd) != 0) std::fprintf(stderr, "swum-emu: Modbus TCP: %s\n", errno_text("close", errno).c_str());
    connections_.pop_back();
    return;
  }
  stats_.connections.fetch_add(1);
}

int ModbusTcpServer::enforce_deadlines(std::uint64_t now) {
  const std::uint64_t frame = ms_to_ns(options_.frame_timeout_ms);
  const std::uint64_t idle = ms_to_ns(options_.idle_timeout_ms);
  std::lock_guard lock(mutex_);
  // A client thread changes phase without telling this thread, so while any connection is open
  // look again at least every half frame timeout: a request that starts just after a check is
  // then seen before its deadline, and the next wake-up is set to that deadline.
  std::uint64_t next = connections_.empty() ? ~std::uint64_t{0} : now + frame / 2;
  for (auto& c : connections_) {
    if (c->phase == kClosing || c->phase == kStepping) continue;
    std::uint64_t deadline = 0;
    Drop reason = Drop::frame_timeout;
    if (c->phase == kIdle) {
      if (idle == 0) continue;
      deadline = c->since_ns + idle;
      reason = Drop::idle;
    } else {
      deadline = c->since_ns + frame;
      reason = c->phase == kReceiving ? Drop::frame_timeout : Drop::reply_timeout;
    }
    if (now >= deadline) {
      // A stall of the server's own thread is not the client's: spare a connection whose next
      // request is already waiting, or whose reply has left.
      if (c->phase == kIdle ? request_waiting(c->fd) : c->phase == kReplying && nothing_unsent(c->fd)) continue;
      c->phase = kClosing;
      c->reason = reason;
      shut(c->fd);
    } else {
      next = std::min(next, deadline);
    }
  }
  if (next == ~std::uint64_t{0}) return -1;
  return static_cast<int>((next - now + 999'999) / 1'000'000);  // round up: never wake before it
}

void ModbusTcpServer::reap() {
  std::vector<std::unique_ptr<Connection>> ended;
  {
    std::lock_guard lock(mutex_);
    for (auto it = connections_.begin(); it != connections_.end();) {
      if ((*it)->ended) {
        ended.push_back(std::move(*it));
        it = connections_.erase(it);
      } else {
        ++it;
      }
    }
  }
  for (auto& c : ended) c->thread.join();  // it has set `ended` as its last act: returns at once
}

bool ModbusTcpServer::enter(Connection& c, int phase) {
  std::lock_guard lock(mutex_);
  if (c.phase == kClosing) return false;
  c.phase = phase;
  c.since_ns = now_ns();
  return true;
}

void ModbusTcpServer::client_loop(Connection& c) {
  modbus_t* ctx = modbus_new_tcp("127.0.0.1", 0);  // only a framing context: the socket is ours
  modbus_mapping_t* map = modbus_mapping_new(0, 0, protocol::modbus::holding::kCount, protocol::modbus::input::kCount);
  if (ctx && map) {
    modbus_set_socket(ctx, c.fd);
    // libmodbus restarts its byte timeout at every byte, so only the deadline enforced by the
    // acceptor thread bounds a whole frame; a longer gap between two bytes ends it here.
    if (modbus_set_byte_timeout(ctx, static_cast<std::uint32_t>(options_.frame_timeout_ms / 1000),
                                static_cast<std::uint32_t>(options_.frame_timeout_ms % 1000) * 1000U) != 0)
      std::fprintf(stderr, "swum-emu: Modbus TCP: modbus_set_byte_timeout: %s\n", modbus_strerror(errno));
    std::uint8_t adu[MODBUS_TCP_MAX_ADU_LENGTH];
    for (;;) {
      // Idle until the first byte of a request (or end of stream, or a shutdown from the acceptor
      // thread or stop()).
      pollfd p{c.fd, POLLIN, 0};
      if (::poll(&p, 1, -1) < 0) {
        if (errno == EINTR) continue;
        std::fprintf(stderr, "swum-emu: Modbus TCP: %s\n", errno_text("poll", errno).c_str());
        break;
      }
      if (!enter(c, kReceiving)) break;
      const int rc = modbus_receive(ctx, adu);
      if (rc < 0) {
        const int e = errno;
        std::lock_guard lock(mutex_);
        if (c.phase != kClosing) {
          // ETIMEDOUT: libmodbus's byte timeout (= the frame timeout) passed inside a frame.
          // ECONNRESET: the client hung up. EMBBADDATA etc.: a malformed frame breaks the TCP
          // stream framing; close the connection.
          if (e == ETIMEDOUT) c.reason = Drop::frame_timeout;
          else if (e == EMBBADDATA) c.reason = Drop::too_long;  // libmodbus: the frame exceeds an ADU
          else if (e != ECONNRESET && e != 0 && !stopping_.load()) stats_.receive_errors.fetch_add(1);
        }
        break;
      }
      const protocol::modbus::MbapHeaderCheck header = protocol::modbus::check_mbap_header(
          std::span<const std::uint8_t>(adu, static_cast<std::size_t>(rc)));
      if (!header.valid) {
        std::lock_guard lock(mutex_);
        if (c.phase != kClosing) c.reason = Drop::bad_header;  // not answered: its framing cannot be trusted
        break;
      }
      // The rest of the request by its MBAP length (a body libmodbus does not frame), within the
      // same frame deadline (still kReceiving); a short read means the connection is ending.
      if (header.surplus_bytes > 0 && !discard_bytes(c.fd, header.surplus_bytes)) break;
      if (!enter(c, kReplying)) break;  // the deadline passed just as the frame completed
      const SteppingHook stepping = [&](bool begin) { return enter(c, begin ? kStepping : kReplying); };
      if (rc > 0 && !serve(ctx, adu, rc, 0, map, shared_, limits_, stats_, header.surplus_bytes > 0, stepping)) break;
      if (!enter(c, kIdle)) break;
    }
  } else {
    std::fprintf(stderr, "swum-emu: Modbus TCP: cannot allocate a libmodbus context\n");
  }
  if (map) modbus_mapping_free(map);
  if (ctx) modbus_free(ctx);  // does not close the socket set with modbus_set_socket
  std::optional<Drop> reason;
  {
    std::lock_guard lock(mutex_);
    if (::close(c.fd) != 0) std::fprintf(stderr, "swum-emu: Modbus TCP: %s\n", errno_text("close", errno).c_str());
    c.fd = -1;
    c.phase = kClosing;
    reason = c.reason;
    if (reason) log_drop(stats_.drops.count(*reason), *reason, c.peer);
    c.ended = true;  // from here on `c` belongs to reap()
  }
  wake(wake_fd_);
}

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
  const timespec ts{static_cast<time_t>(timeout_ns / 1'000'000'000ULL),
                    static_cast<long>(timeout_ns % 1'000'000'000ULL)};
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
  // From its first byte a request has the frame timeout plus the time of a 256-byte frame.
  const std::uint64_t budget = ms_to_ns(frame_timeout_ms_) + 256 * character;
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

std::string parse_milliseconds(std::string_view text, int min_ms, int max_ms, int& out) {
  const std::string range = " (" + std::to_string(min_ms) + " to " + std::to_string(max_ms) + " ms)";
  long long value = 0;
  const char* begin = text.data();
  const char* end = begin + text.size();
  const auto [ptr, ec] = std::from_chars(begin, end, value);
  if (text.empty() || ec == std::errc::invalid_argument || ptr != end)
    return "'" + std::string(text) + "' is not a whole number of milliseconds" + range;
  if (ec == std::errc::result_out_of_range || value < min_ms || value > max_ms)
    return "'" + std::string(text) + "' is out of range" + range;
  out = static_cast<int>(value);
  return {};
}

namespace rtu {

int request_length(std::span<const std::uint8_t> frame) {
  // Unit id, function code; then as libmodbus (_modbus_receive_msg, MSG_INDICATION): a fixed
  // part after the function code, a byte count for the multiple writes, the CRC.
  constexpr int kMax = MODBUS_RTU_MAX_ADU_LENGTH;
  if (frame.size() < 2) return 2;
  const int function = frame[1];
  int fixed = 0;
  if (function <= 6) fixed = 4;                          // reads, single writes: address, count/value
  else if (function == 15 || function == 16) fixed = 5;  // + byte count
  else if (function == 22) fixed = 6;                    // mask write
  else if (function == 23) fixed = 9;                    // read/write multiple registers
  if (frame.size() < static_cast<std::size_t>(2 + fixed)) return 2 + fixed;
  int data = 0;
  if (function == 15 || function == 16) data = frame[6];
  else if (function == 23) data = frame[10];
  const int total = 2 + fixed + data + 2;
  return total > kMax ? -1 : total;
}

std::uint16_t crc16(std::span<const std::uint8_t> bytes) {
  std::uint16_t crc = 0xFFFF;
  for (const std::uint8_t b : bytes) {
    crc ^= b;
    for (int i = 0; i < 8; ++i)
      crc = (crc & 1) ? static_cast<std::uint16_t>((crc >> 1) ^ 0xA001) : static_cast<std::uint16_t>(crc >> 1);
  }
  return crc;
}

}  // namespace rtu

}  // namespace swum::emu
