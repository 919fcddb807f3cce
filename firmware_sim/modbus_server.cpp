#include "modbus_server.h"

#include <arpa/inet.h>
#include <modbus.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

#include "register_map.h"

namespace swum::emu {

namespace {

std::string errno_text(const char* call, int e) { return std::string(call) + ": " + std::strerror(e); }

std::uint64_t monotonic_ns() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<std::uint64_t>(ts.tv_sec) * 1'000'000'000ULL + static_cast<std::uint64_t>(ts.tv_nsec);
}

// One request: validate, queue writes, serve reads. False when the connection should close.
bool serve(modbus_t* ctx, const std::uint8_t* adu, int length, int checksum_length, modbus_mapping_t* map,
           SharedState& shared, const AmplifierLimits& limits, ModbusStats& stats) {
  stats.requests.fetch_add(1, std::memory_order_relaxed);
  const int header = modbus_get_header_length(ctx);
  const int pdu_length = length - header - checksum_length;
  if (pdu_length < 1) return true;
  const std::span<const std::uint8_t> pdu(adu + header, static_cast<std::size_t>(pdu_length));

  modbus::Request request;
  Reason reason = Reason::none;
  std::uint8_t exception = modbus::parse_request(pdu, request, &reason);
  modbus::Decision decision;
  if (exception == modbus::kNoException) {
    decision = modbus::decide(request, limits);
    exception = decision.exception;
    reason = decision.reason;
  }
  if (exception == modbus::kNoException && decision.has_command) {
    decision.command.accepted_ns = monotonic_ns();
    if (shared.submit(decision.command) != Reason::none) exception = modbus::kServerDeviceBusy;
  }
  if (exception != modbus::kNoException) {
    stats.exceptions.fetch_add(1, std::memory_order_relaxed);
    if (exception != modbus::kServerDeviceBusy) shared.rejects.record(reason, CommandSource::modbus);
    return modbus_reply_exception(ctx, adu, exception) != -1;
  }
  const Telemetry t = shared.telemetry.load();
  if (request.function == modbus::kReadInputRegisters) {
    const modbus::RejectSnapshot rejects{
        static_cast<Reason>(shared.rejects.last_reason.load(std::memory_order_relaxed)),
        shared.rejects.count.load(std::memory_order_acquire)};
    modbus::fill_input(t, rejects, std::span<std::uint16_t, modbus::input::kCount>(map->tab_input_registers,
                                                                                   modbus::input::kCount));
  } else {
    modbus::fill_holding(t, std::span<std::uint16_t, modbus::holding::kCount>(map->tab_registers,
                                                                             modbus::holding::kCount));
  }
  return modbus_reply(ctx, adu, length, map) != -1;
}

}  // namespace

ModbusTcpServer::ModbusTcpServer(const std::string& host, std::uint16_t port, SharedState& shared,
                                 AmplifierLimits limits, int max_clients)
    : host_(host), shared_(shared), limits_(limits), max_clients_(max_clients) {
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
  if (::listen(listen_fd_, 16) != 0) {
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

ModbusTcpServer::~ModbusTcpServer() {
  stop();
  if (listen_fd_ >= 0) ::close(listen_fd_);
  if (wake_fd_ >= 0) ::close(wake_fd_);
}

void ModbusTcpServer::start() { acceptor_ = std::thread([this] { accept_loop(); }); }

void ModbusTcpServer::stop() {
  if (stopping_.exchange(true)) return;
  const std::uint64_t one = 1;
  if (::write(wake_fd_, &one, sizeof one) < 0) { /* eventfd write cannot block; nothing else to do */ }
  if (acceptor_.joinable()) acceptor_.join();
  {
    std::lock_guard lock(mutex_);
    for (int fd : client_fds_) ::shutdown(fd, SHUT_RDWR);  // wakes modbus_receive in the client threads
  }
  for (auto& t : clients_) t.join();
  clients_.clear();
}

void ModbusTcpServer::accept_loop() {
  for (;;) {
    pollfd fds[2] = {{listen_fd_, POLLIN, 0}, {wake_fd_, POLLIN, 0}};
    const int rc = ::poll(fds, 2, -1);
    if (rc < 0) {
      if (errno == EINTR) continue;
      std::fprintf(stderr, "swum-emu: Modbus TCP: %s\n", errno_text("poll", errno).c_str());
      return;
    }
    if (fds[1].revents || stopping_.load()) return;
    if (!(fds[0].revents & POLLIN)) continue;
    const int fd = ::accept4(listen_fd_, nullptr, nullptr, SOCK_CLOEXEC);
    if (fd < 0) {
      const int e = errno;
      if (e != EINTR && e != EAGAIN && e != ECONNABORTED)
        std::fprintf(stderr, "swum-emu: Modbus TCP: %s\n", errno_text("accept", e).c_str());
      if (e == EMFILE || e == ENFILE) ::poll(nullptr, 0, 10);
      continue;
    }
    if (active_.load() >= max_clients_) {
      stats_.refused_connections.fetch_add(1);
      ::close(fd);
      continue;
    }
    const int one = 1;
    if (setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one) != 0)
      std::fprintf(stderr, "swum-emu: Modbus TCP: %s\n", errno_text("setsockopt(TCP_NODELAY)", errno).c_str());
    stats_.connections.fetch_add(1);
    active_.fetch_add(1);
    std::lock_guard lock(mutex_);
    client_fds_.push_back(fd);
    clients_.emplace_back([this, fd] { client_loop(fd); });
  }
}

void ModbusTcpServer::client_loop(int fd) {
  modbus_t* ctx = modbus_new_tcp("127.0.0.1", 0);  // only a framing context: the socket is ours
  modbus_mapping_t* map = modbus_mapping_new(0, 0, modbus::holding::kCount, modbus::input::kCount);
  if (ctx && map) {
    modbus_set_socket(ctx, fd);
    std::uint8_t adu[MODBUS_TCP_MAX_ADU_LENGTH];
    while (!stopping_.load(std::memory_order_relaxed)) {
      const int rc = modbus_receive(ctx, adu);
      if (rc == 0) continue;
      if (rc < 0) {
        // EMBBADDATA etc.: a malformed frame breaks the TCP stream framing; close the connection.
        if (errno != ECONNRESET && errno != 0 && !stopping_.load()) stats_.receive_errors.fetch_add(1);
        break;
      }
      if (!serve(ctx, adu, rc, 0, map, shared_, limits_, stats_)) break;
    }
  } else {
    std::fprintf(stderr, "swum-emu: Modbus TCP: cannot allocate a libmodbus context\n");
  }
  if (map) modbus_mapping_free(map);
  if (ctx) modbus_free(ctx);  // does not close the socket set with modbus_set_socket
  {
    std::lock_guard lock(mutex_);
    std::erase(client_fds_, fd);
    ::close(fd);
  }
  active_.fetch_sub(1);
}

ModbusRtuServer::ModbusRtuServer(const std::string& device, int baud, int unit, SharedState& shared,
                                 AmplifierLimits limits)
    : device_(device), shared_(shared), limits_(limits) {
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
  // A bounded wait lets stop() end the thread.
  modbus_set_indication_timeout(ctx, 0, 200000);
  // libmodbus sleeps this long and then flushes after a frame for another unit (to skip that
  // unit's answer); a request to us arriving meanwhile would be lost, so keep it short.
  modbus_set_response_timeout(ctx, 0, 20000);
  ctx_ = ctx;
}

ModbusRtuServer::~ModbusRtuServer() {
  stop();
  if (ctx_) {
    modbus_close(static_cast<modbus_t*>(ctx_));
    modbus_free(static_cast<modbus_t*>(ctx_));
  }
}

void ModbusRtuServer::start() { thread_ = std::thread([this] { loop(); }); }

void ModbusRtuServer::stop() {
  stopping_.store(true);
  if (thread_.joinable()) thread_.join();
}

void ModbusRtuServer::loop() {
  auto* ctx = static_cast<modbus_t*>(ctx_);
  modbus_mapping_t* map = modbus_mapping_new(0, 0, modbus::holding::kCount, modbus::input::kCount);
  if (!map) return;
  std::uint8_t adu[MODBUS_RTU_MAX_ADU_LENGTH];
  // Resynchronise on the RTU inter-frame gap: discard bytes until the line is silent for
  // a few character times (libmodbus may stop reading a frame for another unit early, and a
  // bad frame's tail must not be taken for the start of the next one).
  const int fd = modbus_get_socket(ctx);
  auto drain_until_idle = [&] {
    for (;;) {
      pollfd p{fd, POLLIN, 0};
      const int r = ::poll(&p, 1, 5);
      if (r <= 0) return;  // silent for 5 ms (or poll failed: nothing better to do)
      std::uint8_t junk[256];
      if (::read(fd, junk, sizeof junk) <= 0) return;
    }
  };
  while (!stopping_.load(std::memory_order_relaxed)) {
    const int rc = modbus_receive(ctx, adu);
    if (rc == 0) {  // addressed to another unit
      drain_until_idle();
      continue;
    }
    if (rc < 0) {
      if (errno != ETIMEDOUT) {
        stats_.receive_errors.fetch_add(1);
        drain_until_idle();  // bad CRC / garbage
      }
      continue;
    }
    serve(ctx, adu, rc, 2, map, shared_, limits_, stats_);
  }
  modbus_mapping_free(map);
}

std::string parse_modbus_endpoint(const std::string& text, ModbusEndpoint& out) {
  if (text.rfind("tcp://", 0) == 0) {
    const std::string rest = text.substr(6);
    const auto colon = rest.rfind(':');
    if (colon == std::string::npos) return "expected tcp://HOST:PORT";
    out.tcp = true;
    out.host = rest.substr(0, colon);
    try {
      const int port = std::stoi(rest.substr(colon + 1));
      if (port < 0 || port > 65535) return "port out of range";
      out.port = static_cast<std::uint16_t>(port);
    } catch (const std::exception&) {
      return "bad port in '" + text + "'";
    }
    if (out.host == "localhost") out.host = "127.0.0.1";
    return {};
  }
  if (text.rfind("rtu:", 0) == 0) {
    const std::string rest = text.substr(4);
    const auto colon = rest.rfind(':');
    out.tcp = false;
    if (colon == std::string::npos) {
      out.device = rest;
      return {};
    }
    out.device = rest.substr(0, colon);
    try {
      out.baud = std::stoi(rest.substr(colon + 1));
    } catch (const std::exception&) {
      return "bad baud rate in '" + text + "'";
    }
    if (out.baud <= 0) return "bad baud rate in '" + text + "'";
    return {};
  }
  return "expected tcp://HOST:PORT or rtu:/dev/DEVICE:BAUD, got '" + text + "'";
}

}  // namespace swum::emu
