#include "can_bus.h"

#include <linux/can.h>
#include <linux/can/error.h>

#include <algorithm>
#include <charconv>
#include <cstdio>

namespace swum::io {

std::string validate(const CanFilter& filter) {
  const std::uint32_t max = filter.extended ? kCanExtendedIdMax : kCanStandardIdMax;
  if (filter.id > max) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "CAN filter id 0x%X exceeds 0x%X", filter.id, max);
    return buf;
  }
  return {};
}

bool matches(const CanFilter& filter, const CanFrame& frame) {
  if (filter.extended != frame.extended) return false;
  const std::uint32_t width = frame.extended ? kCanExtendedIdMax : kCanStandardIdMax;
  const std::uint32_t mask = filter.mask & width;
  return (frame.id & mask) == (filter.id & mask);
}

bool matches_any(std::span<const CanFilter> filters, const CanFrame& frame) {
  if (filters.empty()) return true;
  return std::any_of(filters.begin(), filters.end(), [&](const CanFilter& f) { return matches(f, frame); });
}

const char* to_string(CanStatus status) {
  switch (status) {
    case CanStatus::ok: return "ok";
    case CanStatus::timeout: return "timeout";
    case CanStatus::retry: return "retry";
    case CanStatus::error_frame: return "error_frame";
    case CanStatus::error: return "error";
  }
  return "?";
}

CanErrorInfo decode_error_frame(const CanFrame& f) {
  CanErrorInfo info;
  info.classes = f.id & CAN_ERR_MASK;
  info.bus_off = (info.classes & CAN_ERR_BUSOFF) != 0;
  info.tx_timeout = (info.classes & CAN_ERR_TX_TIMEOUT) != 0;
  info.lost_arbitration = (info.classes & CAN_ERR_LOSTARB) != 0;
  info.no_ack = (info.classes & CAN_ERR_ACK) != 0;
  info.bus_error = (info.classes & (CAN_ERR_PROT | CAN_ERR_BUSERROR)) != 0;
  info.restarted = (info.classes & CAN_ERR_RESTARTED) != 0;
  if ((info.classes & CAN_ERR_CRTL) && f.dlc > 1) {
    const std::uint8_t c = f.data[1];
    info.error_passive = (c & (CAN_ERR_CRTL_RX_PASSIVE | CAN_ERR_CRTL_TX_PASSIVE)) != 0;
    info.error_warning = (c & (CAN_ERR_CRTL_RX_WARNING | CAN_ERR_CRTL_TX_WARNING)) != 0;
  }
  return info;
}

std::string CanErrorInfo::describe() const {
  std::string s = "CAN error frame:";
  if (bus_off) s += " bus-off";
  if (error_passive) s += " error-passive";
  if (error_warning) s += " error-warning";
  if (bus_error) s += " bus-error";
  if (tx_timeout) s += " tx-timeout";
  if (lost_arbitration) s += " lost-arbitration";
  if (no_ack) s += " no-ack";
  if (restarted) s += " restarted";
  char buf[32];
  std::snprintf(buf, sizeof buf, " (classes 0x%X)", classes);
  return s + buf;
}

}  // namespace swum::io
