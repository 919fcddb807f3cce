#include "can_frame.h"

#include <algorithm>
#include <charconv>
#include <cstdio>

namespace swum::protocol {

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

std::size_t to_cansend(const CanFrame& frame, std::span<char, kCansendMaxLength + 1> out) {
  int n = std::snprintf(out.data(), out.size(), frame.extended ? "%08X#" : "%03X#", frame.id);
  for (int i = 0; i < std::min<int>(frame.dlc, 8); ++i) {
    n += std::snprintf(out.data() + n, out.size() - static_cast<std::size_t>(n), "%02X",
                       frame.data[static_cast<std::size_t>(i)]);
  }
  return static_cast<std::size_t>(n);
}

std::string to_cansend(const CanFrame& frame) {
  std::array<char, kCansendMaxLength + 1> text{};
  return std::string(text.data(), to_cansend(frame, text));
}

std::string parse_cansend(std::string_view text, CanFrame& out) {
  auto fail = [&](const std::string& why) { return "bad CAN frame '" + std::string(text) + "': " + why; };
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
  out = frame;
  return {};
}

}  // namespace swum::protocol
