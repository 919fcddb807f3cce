#include "can_bus.h"

#include <linux/can.h>
#include <linux/can/error.h>

#include <algorithm>
#include <charconv>
#include <cstdio>

namespace swum::io {

bool same_content(const CanFrame& a, const CanFrame& b) {
  return a.id == b.id && a.extended == b.extended && a.dlc == b.dlc &&
         std::equal(a.data.begin(), a.data.begin() + std::min<int>(a.dlc, 8), b.data.begin());
}

std::string validate(const CanFrame& frame) {
  char buf[96];
  if (frame.dlc > 8) {
    std::snprintf(buf, sizeof buf, "CAN dlc %u exceeds 8 bytes", unsigned{frame.dlc});
    return buf;
  }
  const std::uint32_t max = frame.extended ? kCanExtendedIdMax : kCanStandardIdMax;
  if (frame.id > max) {
    std::snprintf(buf, sizeof buf, "CAN id 0x%X exceeds 0x%X for a%s frame", frame.id, max,
                  frame.extended ? "n extended (29-bit)" : " standard (11-bit)");
    return buf;
  }
  return {};
}

std::string validate(const CanFilter& filter) {
  const std::uint32_t max = filter.extended ? kCanExtendedIdMax : kCanStandardIdMax;
  if (filter.id > max) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "CAN filter id 0x%X exceeds 0x%X", filter.id, max);
    return buf;
  }
  return {};
}

std::string to_cansend(const CanFrame& frame) {
  char buf[48];
  int n = std::snprintf(buf, sizeof buf, frame.extended ? "%08X#" : "%03X#", frame.id);
  for (int i = 0; i < std::min<int>(frame.dlc, 8); ++i) {
    n += std::snprintf(buf + n, sizeof buf - static_cast<std::size_t>(n), "%02X", frame.data[static_cast<std::size_t>(i)]);
  }
  return std::string(buf, static_cast<std::size_t>(n));
}

std::optional<CanFrame> parse_cansend(std::string_view text, std::string* error) {
  auto fail = [&](std::string why) -> std::optional<CanFrame> {
    if (error) *error = "bad CAN frame '" + std::string(text) + "': " + why;
    return std::nullopt;
  };
  const auto hash = text.find('#');
  if (hash == std::string_view::npos) return fail("no '#' between id and data");
  const auto id_text = text.substr(0, hash);
  auto data_text = text.substr(hash + 1);
  CanFrame frame;
  if (id_text.size() == 3) {
    frame.extended = false;
  } else if (id_text.size() == 8) {
    frame.extended = true;
  } else {
    return fail("id must have 3 (standard) or 8 (extended) hex digits");
  }
  auto [p, ec] = std::from_chars(id_text.data(), id_text.data() + id_text.size(), frame.id, 16);
  if (ec != std::errc{} || p != id_text.data() + id_text.size()) return fail("id is not hexadecimal");
  std::string cleaned;
  for (char c : data_text) {
    if (c != '.') cleaned += c;
  }
  if (cleaned.size() % 2 != 0) return fail("odd number of data hex digits");
  if (cleaned.size() > 16) return fail("more than 8 data bytes");
  frame.dlc = static_cast<std::uint8_t>(cleaned.size() / 2);
  for (std::size_t i = 0; i < frame.dlc; ++i) {
    auto [q, ec2] = std::from_chars(cleaned.data() + 2 * i, cleaned.data() + 2 * i + 2, frame.data[i], 16);
    if (ec2 != std::errc{} || q != cleaned.data() + 2 * i + 2) return fail("data is not hexadecimal");
  }
  if (auto why = validate(frame); !why.empty()) return fail(why);
  return frame;
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
