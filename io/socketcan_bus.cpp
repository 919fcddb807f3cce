#include "socketcan_bus.h"

#include <linux/can.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <ctime>
#include <vector>

namespace swum::io {
namespace {

std::string errno_text(int e) {
  return std::string(strerrorname_np(e) ? strerrorname_np(e) : "?") + " (" + std::strerror(e) + ")";
}

CanResult failure(CanStatus status, int e, std::string what) {
  return CanResult{status, e, std::move(what) + (e ? ": " + errno_text(e) : std::string{})};
}

}  // namespace

SocketCanBus::SocketCanBus(const std::string& interface, Options options) : interface_(interface) {
  auto fail = [&](const std::string& what, int e) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
    throw CanOpenError("SocketCAN '" + interface + "': " + what + (e ? ": " + errno_text(e) : ""), e);
  };
  if (interface.empty()) fail("empty interface name", EINVAL);
  if (interface.size() >= IFNAMSIZ)
    fail("interface name longer than " + std::to_string(IFNAMSIZ - 1) + " characters", EINVAL);

  fd_ = ::socket(PF_CAN, SOCK_RAW | SOCK_CLOEXEC | SOCK_NONBLOCK, CAN_RAW);
  if (fd_ < 0) {
    const int e = errno;
    if (e == EAFNOSUPPORT)
      fail("kernel has no CAN support (socket(PF_CAN) failed; load the 'can' module or run through tools/vm/with-vcan)",
           e);
    if (e == EPROTONOSUPPORT) fail("kernel has no CAN_RAW protocol (load the 'can-raw' module)", e);
    fail("socket(PF_CAN, SOCK_RAW, CAN_RAW) failed", e);
  }
  ifreq ifr{};
  std::memcpy(ifr.ifr_name, interface.c_str(), interface.size() + 1);
  if (::ioctl(fd_, SIOCGIFINDEX, &ifr) < 0) {
    const int e = errno;
    if (e == ENODEV) fail("no such CAN interface (create it: ip link add dev " + interface + " type vcan)", e);
    fail("ioctl(SIOCGIFINDEX) failed", e);
  }
  const int one = 1;
  if (::setsockopt(fd_, SOL_SOCKET, SO_TIMESTAMPNS, &one, sizeof one) < 0)
    fail("setsockopt(SO_TIMESTAMPNS) failed", errno);
  if (::setsockopt(fd_, SOL_SOCKET, SO_RXQ_OVFL, &one, sizeof one) < 0) fail("setsockopt(SO_RXQ_OVFL) failed", errno);
  const can_err_mask_t err_mask = options.receive_error_frames ? CAN_ERR_MASK : 0;
  if (::setsockopt(fd_, SOL_CAN_RAW, CAN_RAW_ERR_FILTER, &err_mask, sizeof err_mask) < 0)
    fail("setsockopt(CAN_RAW_ERR_FILTER) failed", errno);
  const int own = options.receive_own ? 1 : 0;
  if (::setsockopt(fd_, SOL_CAN_RAW, CAN_RAW_RECV_OWN_MSGS, &own, sizeof own) < 0)
    fail("setsockopt(CAN_RAW_RECV_OWN_MSGS) failed", errno);

  sockaddr_can addr{};
  addr.can_family = AF_CAN;
  addr.can_ifindex = ifr.ifr_ifindex;
  if (::bind(fd_, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) < 0) {
    const int e = errno;
    if (e == ENODEV) fail("not a CAN interface", e);
    fail("bind failed", e);
  }
}

SocketCanBus::~SocketCanBus() {
  if (fd_ >= 0) ::close(fd_);
}

CanResult SocketCanBus::send(const CanFrame& frame) {
  if (auto why = validate(frame); !why.empty()) return CanResult{CanStatus::error, EINVAL, why};
  can_frame cf{};
  cf.can_id = frame.id | (frame.extended ? CAN_EFF_FLAG : 0U);
  cf.len = frame.dlc;
  std::memcpy(cf.data, frame.data.data(), frame.dlc);
  for (;;) {
    const ssize_t n = ::send(fd_, &cf, sizeof cf, MSG_DONTWAIT | MSG_NOSIGNAL);
    if (n == static_cast<ssize_t>(sizeof cf)) return {};
    if (n >= 0)
      return failure(CanStatus::error, 0, "short write on " + interface_ + " (" + std::to_string(n) + " bytes)");
    const int e = errno;
    if (e == EINTR) continue;
    if (e == ENOBUFS || e == EAGAIN)
      return failure(CanStatus::retry, e, "transmit queue of " + interface_ + " full, retry later");
    return failure(CanStatus::error, e, "send on " + interface_ + " failed");
  }
}

CanResult SocketCanBus::receive(CanFrame& frame, std::chrono::milliseconds timeout) {
  using clock = std::chrono::steady_clock;
  const auto deadline = clock::now() + timeout;
  for (;;) {
    can_frame cf{};
    iovec iov{&cf, sizeof cf};
    alignas(cmsghdr) char control[CMSG_SPACE(sizeof(timespec)) + CMSG_SPACE(sizeof(std::uint32_t)) + 64];
    msghdr msg{};
    msg.msg_iov = &iov;
    msg.msg_iovlen = 1;
    msg.msg_control = control;
    msg.msg_controllen = sizeof control;
    const ssize_t n = ::recvmsg(fd_, &msg, MSG_DONTWAIT);
    if (n < 0) {
      const int e = errno;
      if (e == EINTR) continue;
      if (e != EAGAIN && e != EWOULDBLOCK) return failure(CanStatus::error, e, "recvmsg on " + interface_ + " failed");
      const auto left = deadline - clock::now();
      if (left <= clock::duration::zero())
        return CanResult{CanStatus::timeout, 0,
                         "no frame on " + interface_ + " within " + std::to_string(timeout.count()) + " ms"};
      const auto ns = std::chrono::duration_cast<std::chrono::nanoseconds>(left).count();
      const timespec ts{static_cast<time_t>(ns / 1000000000), static_cast<long>(ns % 1000000000)};
      pollfd pfd{fd_, POLLIN, 0};
      const int r = ::ppoll(&pfd, 1, &ts, nullptr);
      if (r < 0 && errno != EINTR) return failure(CanStatus::error, errno, "ppoll on " + interface_ + " failed");
      if (r > 0 && (pfd.revents & (POLLERR | POLLNVAL)) && !(pfd.revents & POLLIN)) {
        int soerr = 0;
        socklen_t len = sizeof soerr;
        if (::getsockopt(fd_, SOL_SOCKET, SO_ERROR, &soerr, &len) < 0)
          return failure(CanStatus::error, errno, "getsockopt(SO_ERROR) on " + interface_ + " failed");
        return failure(CanStatus::error, soerr ? soerr : EIO, "socket error on " + interface_);
      }
      continue;
    }
    if (n != static_cast<ssize_t>(sizeof cf))
      return failure(CanStatus::error, 0, "unexpected frame size " + std::to_string(n) + " on " + interface_);

    frame = CanFrame{};  // timestamp stays zero unless the kernel attached one
    for (cmsghdr* c = CMSG_FIRSTHDR(&msg); c != nullptr; c = CMSG_NXTHDR(&msg, c)) {
      if (c->cmsg_level != SOL_SOCKET) continue;
      if (c->cmsg_type == SCM_TIMESTAMPNS && c->cmsg_len >= CMSG_LEN(sizeof(timespec))) {
        timespec ts{};
        std::memcpy(&ts, CMSG_DATA(c), sizeof ts);
        frame.timestamp = std::chrono::seconds(ts.tv_sec) + std::chrono::nanoseconds(ts.tv_nsec);
      } else if (c->cmsg_type == SO_RXQ_OVFL && c->cmsg_len >= CMSG_LEN(sizeof(std::uint32_t))) {
        std::memcpy(&kernel_drops_, CMSG_DATA(c), sizeof kernel_drops_);
      }
    }
    // MSG_CTRUNC (control buffer too small) cannot happen with the buffer above; if it did, the
    // timestamp may be missing and stays zero: the consumer sees that and uses its own clock.
    frame.dlc = cf.len > 8 ? 8 : cf.len;
    std::memcpy(frame.data.data(), cf.data, frame.dlc);
    if (cf.can_id & CAN_ERR_FLAG) {
      frame.id = cf.can_id & CAN_ERR_MASK;
      return CanResult{CanStatus::error_frame, 0, decode_error_frame(frame).describe() + " on " + interface_};
    }
    frame.extended = (cf.can_id & CAN_EFF_FLAG) != 0;
    frame.id = cf.can_id & (frame.extended ? CAN_EFF_MASK : CAN_SFF_MASK);
    return {};
  }
}

CanResult SocketCanBus::set_filters(std::span<const CanFilter> filters) {
  std::vector<can_filter> kf;
  if (filters.empty()) {
    kf.push_back(can_filter{0, 0});  // the kernel's default: everything
  }
  for (const auto& f : filters) {
    if (auto why = validate(f); !why.empty()) return CanResult{CanStatus::error, EINVAL, why};
    const canid_t width = f.extended ? CAN_EFF_MASK : CAN_SFF_MASK;
    // CAN_RTR_FLAG in the mask, clear in the identifier: only data frames pass (a remote frame on
    // a PDO's identifier, legal traffic of other devices, must not read as a PDO of zeros).
    kf.push_back(
        can_filter{(f.id & width) | (f.extended ? CAN_EFF_FLAG : 0U), (f.mask & width) | CAN_EFF_FLAG | CAN_RTR_FLAG});
  }
  if (::setsockopt(fd_, SOL_CAN_RAW, CAN_RAW_FILTER, kf.data(),
                   static_cast<socklen_t>(kf.size() * sizeof(can_filter))) < 0) {
    return failure(CanStatus::error, errno, "setsockopt(CAN_RAW_FILTER) on " + interface_ + " failed");
  }
  return {};
}

}  // namespace swum::io
