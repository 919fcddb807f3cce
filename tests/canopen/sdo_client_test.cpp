// canopen::SdoClient against the real canopen::SdoServer on a shared in-test wire (every frame
// in the order it was sent, exact bytes): expedited and segmented upload and download, the
// server's aborts decoded, and the client's own aborts (toggle bit, timeout, a buffer too small,
// a response that is not one) as CiA 301 7.2.4 writes them, each of which ends the server's
// transfer too.
#include "sdo_client.h"

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "allocation_count.h"
#include "canopen_test_support.h"
#include "object_dictionary.h"
#include "sdo_abort_print.h"
#include "sdo_server.h"

namespace swum::canopen {
namespace {

using test::bytes_of;
using test::frame;
using Bytes = std::vector<std::uint8_t>;

constexpr std::uint8_t kNode = 5;
constexpr std::int64_t kTimeoutNs = 1'000'000'000;

// The client and the server on one wire: what one sends, the other receives, and both are logged.
struct Wire {
  ObjectDictionary od{swum_eds_objects(), kNode};
  SdoServer server{od, kNode, kTimeoutNs};
  SdoClient client{kNode, kTimeoutNs};
  std::vector<protocol::CanFrame> frames;
  std::int64_t now_ns = 0;

  // Sends `request` to the server and its answers back until the transfer ends; the last progress.
  SdoProgress run(protocol::CanFrame request) {
    for (int exchanges = 0; exchanges < 100; ++exchanges) {
      frames.push_back(request);
      protocol::CanFrame response;
      if (!server.receive(request, now_ns, response)) return SdoProgress::ignored;  // an abort: no answer
      frames.push_back(response);
      const SdoProgress progress = client.receive(response, now_ns, request);
      if (progress != SdoProgress::send) {
        if (progress == SdoProgress::failed) {  // the client's abort reaches the server too
          frames.push_back(request);
          protocol::CanFrame none;
          EXPECT_FALSE(server.receive(request, now_ns, none)) << "an abort is not answered";
        }
        return progress;
      }
    }
    ADD_FAILURE() << "the transfer did not end";
    return SdoProgress::ignored;
  }
  SdoProgress upload(std::uint16_t index, std::uint8_t sub, std::span<std::uint8_t> into) {
    protocol::CanFrame request;
    client.start_upload(index, sub, into, now_ns, request);
    return run(request);
  }
  SdoProgress download(std::uint16_t index, std::uint8_t sub, const Bytes& data, bool segmented = false) {
    protocol::CanFrame request;
    EXPECT_TRUE(client.start_download(index, sub, data, now_ns, request, segmented));
    return run(request);
  }
};

TEST(SdoClient, ExpeditedUploadOfTheDeviceType) {
  Wire wire;
  std::array<std::uint8_t, 4> value{};
  ASSERT_EQ(wire.upload(0x1000, 0, value), SdoProgress::done);
  ASSERT_EQ(wire.frames.size(), 2U);
  EXPECT_EQ(wire.frames[0].id, 0x605U);
  EXPECT_EQ(bytes_of(wire.frames[0]), (Bytes{0x40, 0x00, 0x10, 0x00, 0, 0, 0, 0}));
  EXPECT_EQ(wire.frames[1].id, 0x585U);
  EXPECT_EQ(bytes_of(wire.frames[1]), (Bytes{0x43, 0x00, 0x10, 0x00, 0x92, 0x01, 0x02, 0x00}));
  EXPECT_EQ(Bytes(wire.client.uploaded().begin(), wire.client.uploaded().end()), (Bytes{0x92, 0x01, 0x02, 0x00}));
  EXPECT_FALSE(wire.client.busy());
}

TEST(SdoClient, ExpeditedUploadTakesTheIndicatedSize) {
  Wire wire;
  std::array<std::uint8_t, 4> value{0xAA, 0xAA, 0xAA, 0xAA};
  ASSERT_EQ(wire.upload(0x6060, 0, value), SdoProgress::done);  // INTEGER8: one byte, n = 3
  EXPECT_EQ(bytes_of(wire.frames[1]), (Bytes{0x4F, 0x60, 0x60, 0x00, 0x00, 0, 0, 0}));
  EXPECT_EQ(wire.client.uploaded().size(), 1U);
}

TEST(SdoClient, SegmentedUploadOfTheDeviceName) {
  Wire wire;
  const std::string name = "swum-emu bimodal standing-wave ultrasonic motor drive";  // 53 bytes: 7 segments + 4
  std::array<std::uint8_t, 128> text{};
  ASSERT_EQ(wire.upload(0x1008, 0, text), SdoProgress::done);
  EXPECT_EQ(std::string(wire.client.uploaded().begin(), wire.client.uploaded().end()), name);
  ASSERT_EQ(wire.frames.size(), 2U + 2U * 8U);
  EXPECT_EQ(bytes_of(wire.frames[1]), (Bytes{0x41, 0x08, 0x10, 0x00, 53, 0, 0, 0}));  // s = 1, size 53
  EXPECT_EQ(bytes_of(wire.frames[2]), (Bytes{0x60, 0, 0, 0, 0, 0, 0, 0}));            // segment, toggle 0
  EXPECT_EQ(bytes_of(wire.frames[3]), (Bytes{0x00, 's', 'w', 'u', 'm', '-', 'e', 'm'}));
  EXPECT_EQ(bytes_of(wire.frames[4]), (Bytes{0x70, 0, 0, 0, 0, 0, 0, 0}));  // toggle 1
  EXPECT_EQ(bytes_of(wire.frames[5]).front(), 0x10);
  // The eighth segment: toggle 1, n = 3 bytes unused, c = 1.
  EXPECT_EQ(bytes_of(wire.frames[16]), (Bytes{0x70, 0, 0, 0, 0, 0, 0, 0}));
  EXPECT_EQ(bytes_of(wire.frames[17]), (Bytes{0x17, 'r', 'i', 'v', 'e', 0, 0, 0}));
  EXPECT_FALSE(wire.server.transfer_in_progress());
}

TEST(SdoClient, ExpeditedDownloadOfTheOpenLoopMode) {
  Wire wire;
  ASSERT_EQ(wire.download(0x6060, 0, {0xFF}), SdoProgress::done);
  ASSERT_EQ(wire.frames.size(), 2U);
  EXPECT_EQ(bytes_of(wire.frames[0]), (Bytes{0x2F, 0x60, 0x60, 0x00, 0xFF, 0, 0, 0}));  // e = 1, s = 1, n = 3
  EXPECT_EQ(bytes_of(wire.frames[1]), (Bytes{0x60, 0x60, 0x60, 0x00, 0, 0, 0, 0}));
  EXPECT_EQ(wire.od.i32(wire.od.slot(0x6060, 0)), -1);
}

TEST(SdoClient, SegmentedDownloadWhenAsked) {
  Wire wire;
  ASSERT_EQ(wire.download(0x60FF, 0, {0x20, 0xA1, 0x07, 0x00}, true), SdoProgress::done);  // 500000 µm/s
  ASSERT_EQ(wire.frames.size(), 4U);
  EXPECT_EQ(bytes_of(wire.frames[0]), (Bytes{0x21, 0xFF, 0x60, 0x00, 4, 0, 0, 0}));  // e = 0, s = 1, size 4
  EXPECT_EQ(bytes_of(wire.frames[1]), (Bytes{0x60, 0xFF, 0x60, 0x00, 0, 0, 0, 0}));
  EXPECT_EQ(bytes_of(wire.frames[2]), (Bytes{0x07, 0x20, 0xA1, 0x07, 0x00, 0, 0, 0}));  // toggle 0, n = 3, c = 1
  EXPECT_EQ(bytes_of(wire.frames[3]), (Bytes{0x20, 0, 0, 0, 0, 0, 0, 0}));
  EXPECT_EQ(wire.od.i32(wire.od.slot(0x60FF, 0)), 500000);
}

TEST(SdoClient, SegmentedDownloadOfSeveralSegmentsTogglesAndEndsWithTheServersAbort) {
  Wire wire;
  // Nine bytes without the size: two segments (7 + 2); the server refuses the second (it holds a
  // number of four bytes at most) with "length too high", which the client takes as the end.
  const Bytes data{1, 2, 3, 4, 5, 6, 7, 8, 9};
  protocol::CanFrame request;
  ASSERT_TRUE(wire.client.start_download(0x60FF, 0, data, 0, request, true));
  request.data[0] = 0x20;  // s = 0: no size indicated, so the server cannot refuse at the start
  std::fill(request.data.begin() + 4, request.data.end(), 0);
  EXPECT_EQ(wire.run(request), SdoProgress::aborted);
  ASSERT_EQ(wire.frames.size(), 4U);
  EXPECT_EQ(bytes_of(wire.frames[2]), (Bytes{0x00, 1, 2, 3, 4, 5, 6, 7}));  // toggle 0, n = 0, c = 0
  EXPECT_EQ(bytes_of(wire.frames[3]), (Bytes{0x80, 0xFF, 0x60, 0x00, 0x12, 0x00, 0x07, 0x06}));
  EXPECT_EQ(wire.client.abort_code(), SdoAbort::length_too_high);
}

TEST(SdoClient, TheServersAbortsAreDecoded) {
  Wire wire;
  std::array<std::uint8_t, 4> value{};
  EXPECT_EQ(wire.upload(0x1234, 0, value), SdoProgress::aborted);
  EXPECT_EQ(wire.client.abort_code(), SdoAbort::no_object);
  EXPECT_STREQ(describe(wire.client.abort_code()), "object does not exist in the object dictionary");
  EXPECT_EQ(wire.upload(0x1018, 9, value), SdoProgress::aborted);
  EXPECT_EQ(wire.client.abort_code(), SdoAbort::no_sub_index);
  EXPECT_EQ(wire.download(0x1000, 0, {0, 0, 0, 0}), SdoProgress::aborted);
  EXPECT_EQ(wire.client.abort_code(), SdoAbort::read_only);
  EXPECT_EQ(wire.download(0x60FF, 0, {1, 2}), SdoProgress::aborted);  // INTEGER32 in two bytes
  EXPECT_EQ(wire.client.abort_code(), SdoAbort::length_too_low);
  EXPECT_EQ(wire.download(0x6060, 0, {0x05}), SdoProgress::aborted);  // above the EDS range -1..3
  EXPECT_EQ(wire.client.abort_code(), SdoAbort::value_too_high);
  EXPECT_EQ(bytes_of(wire.frames.back()), (Bytes{0x80, 0x60, 0x60, 0x00, 0x31, 0x00, 0x09, 0x06}));
  EXPECT_FALSE(wire.client.busy());
  // The next transfer starts clean.
  EXPECT_EQ(wire.upload(0x1000, 0, value), SdoProgress::done);
  EXPECT_EQ(wire.client.abort_code(), SdoAbort::none);
}

TEST(SdoClient, AnUploadLargerThanTheBufferIsAbortedWithOutOfMemory) {
  Wire wire;
  std::array<std::uint8_t, 16> small{};
  EXPECT_EQ(wire.upload(0x1008, 0, small), SdoProgress::failed);  // 53 bytes indicated
  EXPECT_EQ(bytes_of(wire.frames.back()), (Bytes{0x80, 0x08, 0x10, 0x00, 0x05, 0x00, 0x04, 0x05}));
  EXPECT_EQ(wire.client.abort_code(), SdoAbort::out_of_memory);
  EXPECT_FALSE(wire.server.transfer_in_progress()) << "the client's abort ends the server's upload";
  std::array<std::uint8_t, 2> two{};
  EXPECT_EQ(wire.upload(0x1000, 0, two), SdoProgress::failed);  // four bytes, expedited
  EXPECT_EQ(wire.client.abort_code(), SdoAbort::out_of_memory);
}

// A server that misbehaves, frame by frame.
protocol::CanFrame response(std::initializer_list<std::uint8_t> bytes) { return frame(0x585, bytes); }

TEST(SdoClient, AWrongToggleBitIsAborted) {
  SdoClient client(kNode);
  std::array<std::uint8_t, 64> text{};
  protocol::CanFrame request;
  client.start_upload(0x1008, 0, text, 0, request);
  ASSERT_EQ(client.receive(response({0x41, 0x08, 0x10, 0x00, 20, 0, 0, 0}), 0, request), SdoProgress::send);
  EXPECT_EQ(bytes_of(request), (Bytes{0x60, 0, 0, 0, 0, 0, 0, 0}));
  // The first segment must carry toggle 0; this one carries 1.
  EXPECT_EQ(client.receive(response({0x10, 'a', 'b', 'c', 'd', 'e', 'f', 'g'}), 0, request), SdoProgress::failed);
  EXPECT_EQ(request.id, 0x605U);
  EXPECT_EQ(bytes_of(request), (Bytes{0x80, 0x08, 0x10, 0x00, 0x00, 0x00, 0x03, 0x05}));
  EXPECT_EQ(client.abort_code(), SdoAbort::toggle_bit);
  EXPECT_FALSE(client.busy());
  // A download's segment answer with the wrong toggle too.
  const Bytes data{1, 2, 3, 4, 5, 6, 7, 8};
  ASSERT_TRUE(client.start_download(0x2001, 0, data, 0, request));
  ASSERT_EQ(client.receive(response({0x60, 0x01, 0x20, 0x00, 0, 0, 0, 0}), 0, request), SdoProgress::send);
  EXPECT_EQ(bytes_of(request), (Bytes{0x00, 1, 2, 3, 4, 5, 6, 7}));
  EXPECT_EQ(client.receive(response({0x30, 0, 0, 0, 0, 0, 0, 0}), 0, request), SdoProgress::failed);
  EXPECT_EQ(client.abort_code(), SdoAbort::toggle_bit);
}

TEST(SdoClient, ASegmentedUploadLongerOrShorterThanIndicatedIsAborted) {
  SdoClient client(kNode);
  std::array<std::uint8_t, 64> text{};
  protocol::CanFrame request;
  client.start_upload(0x1008, 0, text, 0, request);
  client.receive(response({0x41, 0x08, 0x10, 0x00, 5, 0, 0, 0}), 0, request);
  EXPECT_EQ(client.receive(response({0x00, 'a', 'b', 'c', 'd', 'e', 'f', 'g'}), 0, request), SdoProgress::failed);
  EXPECT_EQ(client.abort_code(), SdoAbort::length_mismatch);
  client.start_upload(0x1008, 0, text, 0, request);
  client.receive(response({0x41, 0x08, 0x10, 0x00, 9, 0, 0, 0}), 0, request);
  EXPECT_EQ(client.receive(response({0x0D, 'a', 0, 0, 0, 0, 0, 0}), 0, request), SdoProgress::failed);  // 1 byte, last
  EXPECT_EQ(bytes_of(request), (Bytes{0x80, 0x08, 0x10, 0x00, 0x10, 0x00, 0x07, 0x06}));
}

TEST(SdoClient, WhatIsNotAResponseToTheTransferIsRefused) {
  SdoClient client(kNode);
  std::array<std::uint8_t, 4> value{};
  protocol::CanFrame request;
  client.start_upload(0x1000, 0, value, 0, request);
  // Other identifiers and extended frames: not ours.
  EXPECT_EQ(client.receive(frame(0x586, {0x43, 0x00, 0x10, 0x00, 1, 2, 3, 4}), 0, request), SdoProgress::ignored);
  EXPECT_EQ(client.receive(frame(0x585, {0x43, 0x00, 0x10, 0x00, 1, 2, 3, 4}, true), 0, request), SdoProgress::ignored);
  EXPECT_TRUE(client.busy());
  // The answer to another object: refused with a general error.
  EXPECT_EQ(client.receive(response({0x43, 0x01, 0x10, 0x00, 1, 0, 0, 0}), 0, request), SdoProgress::failed);
  EXPECT_EQ(client.abort_code(), SdoAbort::general);
  // A download's answer to an upload: an unknown command specifier for this state.
  client.start_upload(0x1000, 0, value, 0, request);
  EXPECT_EQ(client.receive(response({0x60, 0x00, 0x10, 0x00, 0, 0, 0, 0}), 0, request), SdoProgress::failed);
  EXPECT_EQ(bytes_of(request), (Bytes{0x80, 0x00, 0x10, 0x00, 0x01, 0x00, 0x04, 0x05}));
  // A response shorter than 8 bytes.
  client.start_upload(0x1000, 0, value, 0, request);
  EXPECT_EQ(client.receive(response({0x43, 0x00, 0x10, 0x00}), 0, request), SdoProgress::failed);
  EXPECT_EQ(client.abort_code(), SdoAbort::general);
  // Nothing under way: every frame is ignored.
  EXPECT_EQ(client.receive(response({0x43, 0x00, 0x10, 0x00, 1, 2, 3, 4}), 0, request), SdoProgress::ignored);
  // No data: no download.
  EXPECT_FALSE(client.start_download(0x6040, 0, {}, 0, request));
}

TEST(SdoClient, ASilentServerTimesOutWithTheTimeoutAbort) {
  Wire wire;
  std::array<std::uint8_t, 64> text{};
  protocol::CanFrame request;
  wire.client.start_upload(0x1008, 0, text, 0, request);
  protocol::CanFrame answer;
  ASSERT_TRUE(wire.server.receive(request, 0, answer));
  ASSERT_EQ(wire.client.receive(answer, 0, request), SdoProgress::send);
  // The segment request is lost: the client waits its timeout, then aborts.
  EXPECT_EQ(wire.client.poll(kTimeoutNs, request), SdoProgress::ignored);
  EXPECT_EQ(wire.client.poll(kTimeoutNs + 400'000'000, request), SdoProgress::failed);
  EXPECT_EQ(bytes_of(request), (Bytes{0x80, 0x08, 0x10, 0x00, 0x00, 0x00, 0x04, 0x05}));
  EXPECT_EQ(wire.client.abort_code(), SdoAbort::timeout);
  EXPECT_FALSE(wire.server.receive(request, kTimeoutNs / 2, answer));
  EXPECT_FALSE(wire.server.transfer_in_progress());
  EXPECT_EQ(wire.client.poll(10 * kTimeoutNs, request), SdoProgress::ignored) << "nothing under way";
}

TEST(SdoClient, TransfersAllocateNothing) {
  Wire wire;
  wire.frames.reserve(64);
  std::array<std::uint8_t, 128> text{};
  const Bytes mode{0xFF};
  const long before = swum::test::allocation_count();
  const SdoProgress name = wire.upload(0x1008, 0, text);
  const SdoProgress written = wire.download(0x6060, 0, mode);
  const SdoProgress refused = wire.upload(0x1234, 0, text);
  const long after = swum::test::allocation_count();
  EXPECT_EQ(after, before);
  EXPECT_EQ(name, SdoProgress::done);
  EXPECT_EQ(written, SdoProgress::done);
  EXPECT_EQ(refused, SdoProgress::aborted);
}

TEST(SdoClient, RefusesABadNodeOrTimeout) {
  EXPECT_THROW(SdoClient(0), std::invalid_argument);
  EXPECT_THROW(SdoClient(128), std::invalid_argument);
  EXPECT_THROW(SdoClient(1, 0), std::invalid_argument);
}

}  // namespace
}  // namespace swum::canopen
