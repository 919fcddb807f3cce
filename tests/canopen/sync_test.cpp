// canopen/sync.h: SYNC frames with and without the counter on 0x1005's identifier, others ignored,
// longer ones malformed (CiA 301 7.2.5).
#include "sync.h"

#include <gtest/gtest.h>

namespace swum::canopen {
namespace {

protocol::CanFrame frame(std::uint32_t id, std::uint8_t dlc, bool extended = false) {
  protocol::CanFrame f;
  f.id = id;
  f.dlc = dlc;
  f.extended = extended;
  f.data = {7, 1, 2, 3, 4, 5, 6, 7};
  return f;
}

TEST(Sync, WithoutDataTheCounterIsZero) {
  std::uint8_t counter = 99;
  EXPECT_EQ(decode_sync(frame(0x080, 0), 0x80, counter), SyncDecode::sync);
  EXPECT_EQ(counter, 0);
}

TEST(Sync, OneByteIsTheCounter) {
  std::uint8_t counter = 0;
  EXPECT_EQ(decode_sync(frame(0x080, 1), 0x80, counter), SyncDecode::sync);
  EXPECT_EQ(counter, 7);
}

TEST(Sync, LongerIsMalformedOtherIdentifiersAreNotSync) {
  std::uint8_t counter = 99;
  for (std::uint8_t dlc = 2; dlc <= 8; ++dlc)
    EXPECT_EQ(decode_sync(frame(0x080, dlc), 0x80, counter), SyncDecode::malformed);
  EXPECT_EQ(decode_sync(frame(0x081, 0), 0x80, counter), SyncDecode::not_sync);
  EXPECT_EQ(decode_sync(frame(0x080, 0, true), 0x80, counter), SyncDecode::not_sync);
  EXPECT_EQ(counter, 99);
}

TEST(Sync, TheIdentifierComesFromTheCobIdWithoutItsFlagBits) {
  std::uint8_t counter = 0;
  // Bit 30 (this node produces SYNC) and bit 31 (do not care) are no part of the identifier.
  EXPECT_EQ(decode_sync(frame(0x123, 0), 0xC0000123, counter), SyncDecode::sync);
  EXPECT_EQ(decode_sync(frame(0x080, 0), 0xC0000123, counter), SyncDecode::not_sync);
  // Bit 29: a 29-bit identifier.
  EXPECT_EQ(decode_sync(frame(0x1ABCDEF, 0, true), 0x21ABCDEF, counter), SyncDecode::sync);
  EXPECT_EQ(decode_sync(frame(0x1ABCDEF & 0x7FF, 0), 0x21ABCDEF, counter), SyncDecode::not_sync);
}

}  // namespace
}  // namespace swum::canopen
