// The Modbus TCP server (modbus_server.h): the acceptor thread with the connection deadlines
// and evictions, one thread per client; each request is served by modbus_serve.
#include "transports/modbus_server.h"

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
#include <cstdio>
#include <optional>
#include <stdexcept>
#include <system_error>

#include "modbus_codec.h"
#include "transports/modbus_serve.h"

namespace swum::emu {

namespace {

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

}  // namespace swum::emu
