// canopen/sdo_server: the exact bytes of CiA 301 7.2.4.3's expedited and segmented transfers
// both ways, and of every abort issue 33 names (object or sub-index missing, length too high or
// too low, read-only, value range, not mappable, toggle bit, timeout), counted; the server
// allocates nothing per frame.
#include "sdo_server.h"

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <string>

#include "allocation_count.h"
#include "sdo_abort_print.h"

namespace swum::canopen {
namespace {

using Bytes = std::array<std::uint8_t, 8>;
constexpr std::uint8_t kNode = 5;
constexpr std::int64_t kSecond = 1'000'000'000;

protocol::CanFrame request(const Bytes& data, std::uint8_t dlc = 8) {
  protocol::CanFrame frame;
  frame.id = 0x600 + kNode;
  frame.dlc = dlc;
  frame.data = data;
  return frame;
}

class Sdo : public ::testing::Test {
 protected:
  // The answer to one request: its 8 bytes, after checking it is an SDO response of this node.
  Bytes ask(const Bytes& data, std::int64_t now_ns = 0) {
    protocol::CanFrame response;
    EXPECT_TRUE(server.receive(request(data), now_ns, response));
    EXPECT_EQ(response.id, 0x580u + kNode);
    EXPECT_EQ(response.dlc, 8);
    EXPECT_FALSE(response.extended);
    return response.data;
  }
  std::uint32_t value(std::uint16_t index, std::uint8_t sub) const { return od.u32(od.slot(index, sub)); }

  ObjectDictionary od{swum_eds_objects(), kNode};
  SdoServer server{od, kNode};
};

TEST_F(Sdo, ExpeditedUploadCarriesTheSizeOfTheType) {
  EXPECT_EQ(ask({0x40, 0x00, 0x10, 0x00}), (Bytes{0x43, 0x00, 0x10, 0x00, 0x92, 0x01, 0x02, 0x00}));  // 4 bytes
  EXPECT_EQ(ask({0x40, 0x17, 0x10, 0x00}), (Bytes{0x4B, 0x17, 0x10, 0x00, 0xE8, 0x03, 0x00, 0x00}));  // 2: 1000
  EXPECT_EQ(ask({0x40, 0x18, 0x10, 0x00}), (Bytes{0x4F, 0x18, 0x10, 0x00, 0x04, 0x00, 0x00, 0x00}));  // 1
  EXPECT_EQ(ask({0x40, 0x18, 0x10, 0x04}), (Bytes{0x43, 0x18, 0x10, 0x04, kNode, 0x00, 0x00, 0x00}));
  EXPECT_EQ(server.aborts_sent(), 0u);
}

TEST_F(Sdo, ExpeditedDownloadWithAndWithoutSize) {
  // 2B: e = 1, s = 1, n = 2 (two bytes): controlword 0x000F
  EXPECT_EQ(ask({0x2B, 0x40, 0x60, 0x00, 0x0F, 0x00, 0xAA, 0xBB}), (Bytes{0x60, 0x40, 0x60, 0x00, 0, 0, 0, 0}));
  EXPECT_EQ(value(0x6040, 0), 0x000Fu);
  // 23: four bytes: target velocity 300000 um/s
  EXPECT_EQ(ask({0x23, 0xFF, 0x60, 0x00, 0xE0, 0x93, 0x04, 0x00}), (Bytes{0x60, 0xFF, 0x60, 0x00, 0, 0, 0, 0}));
  EXPECT_EQ(value(0x60FF, 0), 300000u);
  // 22: e = 1 without a size: the object's own size (one byte of mode -1)
  EXPECT_EQ(ask({0x22, 0x60, 0x60, 0x00, 0xFF, 0x11, 0x22, 0x33}), (Bytes{0x60, 0x60, 0x60, 0x00, 0, 0, 0, 0}));
  EXPECT_EQ(od.i32(od.slot(0x6060, 0)), -1);
}

TEST_F(Sdo, SegmentedUploadOfTheDeviceName) {
  const std::string name = "swum-emu bimodal standing-wave ultrasonic motor drive";
  ASSERT_EQ(name.size(), 53u);
  EXPECT_EQ(ask({0x40, 0x08, 0x10, 0x00}), (Bytes{0x41, 0x08, 0x10, 0x00, 53, 0x00, 0x00, 0x00}));
  std::string received;
  bool toggle = false;
  for (int segment = 1; segment <= 8; ++segment) {
    const Bytes answer = ask({static_cast<std::uint8_t>(0x60 | (toggle ? 0x10 : 0))}, segment * 1000);
    EXPECT_EQ(answer[0] & 0xE0, 0x00) << segment;           // scs 0
    EXPECT_EQ((answer[0] & 0x10) != 0, toggle) << segment;  // the toggle echoed
    const std::size_t unused = (answer[0] >> 1) & 0x07;
    received.append(answer.begin() + 1, answer.begin() + 1 + static_cast<std::ptrdiff_t>(7 - unused));
    EXPECT_EQ((answer[0] & 0x01) != 0, segment == 8) << segment;  // c on the last only
    if (segment == 1) {
      EXPECT_EQ(answer, (Bytes{0x00, 's', 'w', 'u', 'm', '-', 'e', 'm'}));
    }
    if (segment == 8) {
      EXPECT_EQ(answer, (Bytes{0x17, 'r', 'i', 'v', 'e', 0, 0, 0}));  // t = 1, n = 3, c = 1
    }
    toggle = !toggle;
  }
  EXPECT_EQ(received, name);
  EXPECT_FALSE(server.transfer_in_progress());
  // A further segment request belongs to no transfer.
  EXPECT_EQ(ask({0x60}), (Bytes{0x80, 0x00, 0x00, 0x00, 0x01, 0x00, 0x04, 0x05}));
}

TEST_F(Sdo, SegmentedDownloadToAFourByteObject) {
  // 21: e = 0, s = 1, size 4 in bytes 4-7: profile acceleration
  EXPECT_EQ(ask({0x21, 0x83, 0x60, 0x00, 0x04, 0x00, 0x00, 0x00}), (Bytes{0x60, 0x83, 0x60, 0x00, 0, 0, 0, 0}));
  EXPECT_TRUE(server.transfer_in_progress());
  EXPECT_EQ(value(0x6083, 0), 2000000u);  // not yet
  // 07: t = 0, n = 3 (4 bytes), c = 1: 1000000
  EXPECT_EQ(ask({0x07, 0x40, 0x42, 0x0F, 0x00, 0xEE, 0xEE, 0xEE}), (Bytes{0x20, 0, 0, 0, 0, 0, 0, 0}));
  EXPECT_EQ(value(0x6083, 0), 1000000u);
  EXPECT_FALSE(server.transfer_in_progress());
  // Without a size, in two segments of two bytes (the toggle alternating).
  EXPECT_EQ(ask({0x20, 0x84, 0x60, 0x00}), (Bytes{0x60, 0x84, 0x60, 0x00, 0, 0, 0, 0}));
  EXPECT_EQ(ask({0x0A, 0x40, 0x42}), (Bytes{0x20, 0, 0, 0, 0, 0, 0, 0}));  // n = 5: 2 bytes
  EXPECT_EQ(ask({0x1B, 0x0F, 0x00}), (Bytes{0x30, 0, 0, 0, 0, 0, 0, 0}));  // t = 1, n = 5, c = 1
  EXPECT_EQ(value(0x6084, 0), 1000000u);
  EXPECT_EQ(server.aborts_sent(), 0u);
}

TEST_F(Sdo, SegmentedDownloadWhoseLengthDisagrees) {
  // More bytes than the object holds, in the segments.
  ask({0x20, 0x83, 0x60, 0x00});
  EXPECT_EQ(ask({0x00, 1, 2, 3, 4, 5, 6, 7}), (Bytes{0x80, 0x83, 0x60, 0x00, 0x12, 0x00, 0x07, 0x06}));
  // Fewer than the object's size.
  ask({0x20, 0x83, 0x60, 0x00});
  EXPECT_EQ(ask({0x0B, 1, 2}), (Bytes{0x80, 0x83, 0x60, 0x00, 0x13, 0x00, 0x07, 0x06}));
  // A size indicated that is not the object's is refused at once.
  EXPECT_EQ(ask({0x21, 0x83, 0x60, 0x00, 0x08, 0x00, 0x00, 0x00}),
            (Bytes{0x80, 0x83, 0x60, 0x00, 0x12, 0x00, 0x07, 0x06}));
  EXPECT_EQ(ask({0x21, 0x83, 0x60, 0x00, 0x02, 0x00, 0x00, 0x00}),
            (Bytes{0x80, 0x83, 0x60, 0x00, 0x13, 0x00, 0x07, 0x06}));
  // Indicated 4, sent 3 and ended: the lengths do not match.
  ask({0x21, 0x83, 0x60, 0x00, 0x04, 0x00, 0x00, 0x00});
  EXPECT_EQ(ask({0x09, 1, 2, 3}), (Bytes{0x80, 0x83, 0x60, 0x00, 0x10, 0x00, 0x07, 0x06}));
  EXPECT_EQ(value(0x6083, 0), 2000000u);
  EXPECT_EQ(server.aborts_sent(), 5u);
}

TEST_F(Sdo, ToggleBitErrorsAbortBothWays) {
  ask({0x21, 0x83, 0x60, 0x00, 0x04, 0x00, 0x00, 0x00});
  EXPECT_EQ(ask({0x17, 0x40, 0x42, 0x0F, 0x00}), (Bytes{0x80, 0x83, 0x60, 0x00, 0x00, 0x00, 0x03, 0x05}));
  EXPECT_EQ(value(0x6083, 0), 2000000u);
  EXPECT_EQ(server.last_abort(), SdoAbort::toggle_bit);
  ask({0x40, 0x08, 0x10, 0x00});
  ask({0x60});
  EXPECT_EQ(ask({0x60}), (Bytes{0x80, 0x08, 0x10, 0x00, 0x00, 0x00, 0x03, 0x05}));  // the toggle did not alternate
  EXPECT_FALSE(server.transfer_in_progress());
  EXPECT_EQ(server.aborts_sent(), 2u);
}

TEST_F(Sdo, ASegmentedTransferIdleLongerThanTheTimeoutIsAbortedOnce) {
  protocol::CanFrame abort;
  EXPECT_FALSE(server.poll(10 * kSecond, abort));  // nothing under way
  ask({0x40, 0x08, 0x10, 0x00}, 0);
  ask({0x60}, kSecond / 2);  // each segment restarts the clock
  EXPECT_FALSE(server.poll(kSecond, abort));
  EXPECT_FALSE(server.poll(kSecond / 2 + kSecond, abort));
  ASSERT_TRUE(server.poll(kSecond / 2 + kSecond + 1, abort));
  EXPECT_EQ(abort.id, 0x585u);
  EXPECT_EQ(abort.dlc, 8);
  EXPECT_EQ(abort.data, (Bytes{0x80, 0x08, 0x10, 0x00, 0x00, 0x00, 0x04, 0x05}));
  EXPECT_FALSE(server.poll(3 * kSecond, abort));
  EXPECT_EQ(server.aborts_sent(), 1u);
  EXPECT_EQ(server.last_abort(), SdoAbort::timeout);
  // A shorter timeout of the constructor's.
  SdoServer quick(od, kNode, 1000);
  protocol::CanFrame response;
  ASSERT_TRUE(quick.receive(request({0x21, 0x83, 0x60, 0x00, 0x04}), 0, response));
  EXPECT_FALSE(quick.poll(1000, abort));
  EXPECT_TRUE(quick.poll(1001, abort));
  EXPECT_EQ(abort.data, (Bytes{0x80, 0x83, 0x60, 0x00, 0x00, 0x00, 0x04, 0x05}));
}

TEST_F(Sdo, EachAbortOfIssue33HasItsCode) {
  // object does not exist
  EXPECT_EQ(ask({0x40, 0x34, 0x12, 0x00}), (Bytes{0x80, 0x34, 0x12, 0x00, 0x00, 0x00, 0x02, 0x06}));
  EXPECT_EQ(ask({0x2B, 0x34, 0x12, 0x00, 1, 0}), (Bytes{0x80, 0x34, 0x12, 0x00, 0x00, 0x00, 0x02, 0x06}));
  // sub-index does not exist
  EXPECT_EQ(ask({0x40, 0x18, 0x10, 0x09}), (Bytes{0x80, 0x18, 0x10, 0x09, 0x11, 0x00, 0x09, 0x06}));
  EXPECT_EQ(ask({0x40, 0x00, 0x18, 0x04}), (Bytes{0x80, 0x00, 0x18, 0x04, 0x11, 0x00, 0x09, 0x06}));
  // length too high / too low (4 and 1 bytes to the 2-byte controlword)
  EXPECT_EQ(ask({0x23, 0x40, 0x60, 0x00, 1, 0, 0, 0}), (Bytes{0x80, 0x40, 0x60, 0x00, 0x12, 0x00, 0x07, 0x06}));
  EXPECT_EQ(ask({0x2F, 0x40, 0x60, 0x00, 1, 0, 0, 0}), (Bytes{0x80, 0x40, 0x60, 0x00, 0x13, 0x00, 0x07, 0x06}));
  // read-only (also before a segmented download begins)
  EXPECT_EQ(ask({0x23, 0x00, 0x10, 0x00, 1, 0, 0, 0}), (Bytes{0x80, 0x00, 0x10, 0x00, 0x02, 0x00, 0x01, 0x06}));
  EXPECT_EQ(ask({0x21, 0x08, 0x10, 0x00, 3, 0, 0, 0}), (Bytes{0x80, 0x08, 0x10, 0x00, 0x02, 0x00, 0x01, 0x06}));
  // value range exceeded: 0x1003 takes only 0; above and below a limit
  EXPECT_EQ(ask({0x2F, 0x03, 0x10, 0x00, 1}), (Bytes{0x80, 0x03, 0x10, 0x00, 0x30, 0x00, 0x09, 0x06}));
  EXPECT_EQ(ask({0x23, 0xFF, 0x60, 0x00, 0x41, 0x42, 0x0F, 0x00}),  // 1000001
            (Bytes{0x80, 0xFF, 0x60, 0x00, 0x31, 0x00, 0x09, 0x06}));
  EXPECT_EQ(ask({0x23, 0x83, 0x60, 0x00, 0, 0, 0, 0}), (Bytes{0x80, 0x83, 0x60, 0x00, 0x32, 0x00, 0x09, 0x06}));
  // not mappable: the device type into TPDO1, by CiA 301's procedure
  ask({0x23, 0x00, 0x18, 0x01, 0x85, 0x01, 0x00, 0x80});  // invalidate TPDO1
  ask({0x2F, 0x00, 0x1A, 0x00, 0x00});                    // mapping off
  EXPECT_EQ(ask({0x23, 0x00, 0x1A, 0x01, 0x20, 0x00, 0x00, 0x10}),
            (Bytes{0x80, 0x00, 0x1A, 0x01, 0x41, 0x00, 0x04, 0x06}));
  // PDO length exceeded: three 32-bit objects
  ask({0x23, 0x00, 0x1A, 0x01, 0x20, 0x00, 0x6C, 0x60});
  ask({0x23, 0x00, 0x1A, 0x02, 0x20, 0x00, 0x64, 0x60});
  ask({0x23, 0x00, 0x1A, 0x03, 0x20, 0x00, 0x27, 0x20});
  EXPECT_EQ(ask({0x2F, 0x00, 0x1A, 0x00, 0x03}), (Bytes{0x80, 0x00, 0x1A, 0x00, 0x42, 0x00, 0x04, 0x06}));
  EXPECT_EQ(server.aborts_sent(), 13u);
  EXPECT_EQ(server.last_abort(), SdoAbort::pdo_too_long);
}

TEST_F(Sdo, RequestsOutsideTheProtocolAreAborted) {
  // Block download (ccs 6) and block upload (ccs 5) are not offered; ccs 7 is no command.
  EXPECT_EQ(ask({0xC6, 0x83, 0x60, 0x00, 4}), (Bytes{0x80, 0x83, 0x60, 0x00, 0x01, 0x00, 0x04, 0x05}));
  EXPECT_EQ(ask({0xA4, 0x08, 0x10, 0x00, 0x7F}), (Bytes{0x80, 0x08, 0x10, 0x00, 0x01, 0x00, 0x04, 0x05}));
  EXPECT_EQ(ask({0xE0, 0x00, 0x10, 0x00}), (Bytes{0x80, 0x00, 0x10, 0x00, 0x01, 0x00, 0x04, 0x05}));
  // A segment with no transfer, or of the other direction.
  EXPECT_EQ(ask({0x00, 1, 2}), (Bytes{0x80, 0x00, 0x00, 0x00, 0x01, 0x00, 0x04, 0x05}));
  ask({0x40, 0x08, 0x10, 0x00});
  EXPECT_EQ(ask({0x00, 1, 2}), (Bytes{0x80, 0x08, 0x10, 0x00, 0x01, 0x00, 0x04, 0x05}));
  EXPECT_FALSE(server.transfer_in_progress());
  // An SDO frame is 8 bytes (CiA 301 7.2.4.3): a shorter one is answered with a general error.
  protocol::CanFrame response;
  ASSERT_TRUE(server.receive(request({0x40, 0x00, 0x10, 0x00}, 4), 0, response));
  EXPECT_EQ(response.data, (Bytes{0x80, 0x00, 0x10, 0x00, 0x00, 0x00, 0x00, 0x08}));
  ASSERT_TRUE(server.receive(request({0x40, 0x00, 0x10, 0x07, 0x55}, 2), 0, response));  // index cut: none named
  EXPECT_EQ(response.data, (Bytes{0x80, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x08}));
  ASSERT_TRUE(server.receive(request({}, 0), 0, response));
  EXPECT_EQ(response.data, (Bytes{0x80, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x08}));
  EXPECT_EQ(server.aborts_sent(), 8u);
  EXPECT_EQ(server.last_abort(), SdoAbort::general);
}

TEST_F(Sdo, AClientsAbortEndsTheTransferSilently) {
  ask({0x40, 0x08, 0x10, 0x00});
  protocol::CanFrame response;
  EXPECT_FALSE(server.receive(request({0x80, 0x08, 0x10, 0x00, 0x00, 0x00, 0x04, 0x05}), 0, response));
  EXPECT_FALSE(server.transfer_in_progress());
  EXPECT_FALSE(server.receive(request({0x80}, 1), 0, response));  // even a short one gets no answer
  EXPECT_EQ(server.aborts_sent(), 0u);
  EXPECT_EQ(ask({0x60}), (Bytes{0x80, 0x00, 0x00, 0x00, 0x01, 0x00, 0x04, 0x05}));
}

TEST_F(Sdo, OnlyItsOwnRequestIdentifierIsServed) {
  protocol::CanFrame response;
  response.id = 0x123;
  protocol::CanFrame other = request({0x40, 0x00, 0x10, 0x00});
  other.id = 0x606;
  EXPECT_FALSE(server.receive(other, 0, response));
  other.id = 0x585;  // its own response identifier
  EXPECT_FALSE(server.receive(other, 0, response));
  other.id = 0x605;
  other.extended = true;
  EXPECT_FALSE(server.receive(other, 0, response));
  EXPECT_EQ(response.id, 0x123u);  // untouched
  EXPECT_EQ(server.aborts_sent(), 0u);
}

TEST_F(Sdo, ANewInitiateOrAResetDropsTheTransferUnderWay) {
  ask({0x40, 0x08, 0x10, 0x00});
  ask({0x60});
  // A new upload starts over (its first segment has toggle 0 again).
  ask({0x40, 0x09, 0x10, 0x00});
  EXPECT_EQ(ask({0x60}), (Bytes{0x01, 'v', 'i', 'r', 't', 'u', 'a', 'l'}));  // "virtual": one segment, c = 1
  ask({0x40, 0x08, 0x10, 0x00});
  server.reset();
  EXPECT_FALSE(server.transfer_in_progress());
  protocol::CanFrame abort;
  EXPECT_FALSE(server.poll(100 * kSecond, abort));
  EXPECT_EQ(ask({0x60}), (Bytes{0x80, 0x00, 0x00, 0x00, 0x01, 0x00, 0x04, 0x05}));
}

TEST_F(Sdo, AbortsAreCountedAndTheLastKept) {
  EXPECT_EQ(server.last_abort(), SdoAbort::none);
  for (int i = 1; i <= 5; ++i) {
    ask({0x40, 0x34, 0x12, 0x00});
    EXPECT_EQ(server.aborts_sent(), static_cast<std::uint64_t>(i));
  }
  EXPECT_EQ(server.last_abort(), SdoAbort::no_object);
  ask({0x40, 0x00, 0x10, 0x00});  // a success changes neither
  EXPECT_EQ(server.aborts_sent(), 5u);
  EXPECT_EQ(server.last_abort(), SdoAbort::no_object);
}

TEST_F(Sdo, ServingAllocatesNothing) {
  protocol::CanFrame response;
  const long before = test::allocation_count();
  for (int round = 0; round < 3; ++round) {
    server.receive(request({0x40, 0x08, 0x10, 0x00}), 0, response);
    for (int segment = 0; segment < 8; ++segment)
      server.receive(request({static_cast<std::uint8_t>(segment % 2 ? 0x70 : 0x60)}), 0, response);
    server.receive(request({0x21, 0x83, 0x60, 0x00, 0x04}), 0, response);
    server.receive(request({0x07, 0x40, 0x42, 0x0F, 0x00}), 0, response);
    server.receive(request({0x40, 0x34, 0x12, 0x00}), 0, response);
    server.receive(request({0x40, 0x08, 0x10, 0x00}), 0, response);
    server.poll(10 * kSecond, response);
  }
  EXPECT_EQ(test::allocation_count(), before);
  EXPECT_EQ(server.aborts_sent(), 6u);
}

}  // namespace
}  // namespace swum::canopen
