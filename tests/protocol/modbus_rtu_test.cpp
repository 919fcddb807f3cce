// RTU framing facts (protocol/modbus_rtu): the request length as a line delivers it byte by
// byte, and CRC-16/MODBUS; the emulator's RTU server frames with them (docs/emulator.md).
#include "modbus_rtu.h"

#include <gtest/gtest.h>

#include <vector>

namespace swum::protocol::modbus::rtu {
namespace {

// The length libmodbus 3.1.6 reads for a request (_modbus_receive_msg, MSG_INDICATION), grown
// byte by byte as the frame arrives.
int final_length(const std::vector<std::uint8_t>& frame) {
  std::size_t have = 0;
  for (;;) {
    const int need = rtu::request_length(std::span<const std::uint8_t>(frame.data(), have));
    if (need < 0 || static_cast<std::size_t>(need) == have) return need;
    EXPECT_GT(static_cast<std::size_t>(need), have);
    if (static_cast<std::size_t>(need) > frame.size()) return need;  // more bytes than given
    ++have;
  }
}

TEST(RtuRequestLength, FollowsTheFunctionCode) {
  EXPECT_EQ(rtu::request_length({}), 2);
  EXPECT_EQ(final_length({7, 3, 0, 0, 0, 10, 0, 0}), 8);  // read holding
  EXPECT_EQ(final_length({7, 4, 0, 0, 0, 1, 0, 0}), 8);   // read input
  EXPECT_EQ(final_length({7, 6, 0, 3, 0x0F, 0xA0, 0, 0}), 8);
  EXPECT_EQ(final_length({7, 0, 0, 0, 0, 0, 0, 0}), 8);  // function 0: as the reads (libmodbus)
  std::vector<std::uint8_t> fc16{7, 16, 0, 1, 0, 2, 4, 1, 2, 3, 4, 0, 0};
  EXPECT_EQ(final_length(fc16), 13);                             // 7 + byte count 4 + CRC
  EXPECT_EQ(final_length({7, 22, 0, 0, 0, 0, 0, 0, 0, 0}), 10);  // mask write
  std::vector<std::uint8_t> fc23(13 + 2 + 2, 0);
  fc23[0] = 7, fc23[1] = 23, fc23[10] = 2;
  EXPECT_EQ(final_length(fc23), 15);
  EXPECT_EQ(final_length({7, 0x11, 0, 0}), 4);               // report slave id: unit, function, CRC
  EXPECT_EQ(final_length({7, 0x2B, 0, 0}), 4);               // unknown: the same
  EXPECT_EQ(final_length({7, 16, 0, 0, 0, 123, 246}), 255);  // 9 + 246 = 255: fits
  EXPECT_EQ(final_length({7, 16, 0, 0, 0, 124, 248}), -1);   // 259: above 256 bytes
}

TEST(RtuCrc16, KnownVector) {
  // "01 03 00 00 00 0A" -> CRC C5 CD on the wire (low byte first).
  const std::uint8_t frame[] = {0x01, 0x03, 0x00, 0x00, 0x00, 0x0A};
  EXPECT_EQ(rtu::crc16(frame), 0xCDC5);
  // CRC-16/MODBUS check value over "123456789".
  const std::uint8_t check[] = {'1', '2', '3', '4', '5', '6', '7', '8', '9'};
  EXPECT_EQ(rtu::crc16(check), 0x4B37);
}

}  // namespace
}  // namespace swum::protocol::modbus::rtu
