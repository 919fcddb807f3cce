// Fuzz target: the host's SDO client (canopen/sdo_client.h, node 5) fed any frames as a node's
// answers, with time passing between them (timeouts). Input: byte 0 chooses the transfers (bit 0:
// download instead of upload, bit 1: segmented download, bits 2-4: the upload buffer's size, 0 to
// 64 bytes, bits 5-7: the download's length, 1 to 64 bytes); then records of 9 bytes: byte 0 =
// flags (bits 0-3: DLC 0..15, bit 4: identifier 0x586 instead of the server's 0x585, bit 5: 29-bit
// identifier, bits 6-7: time step before the frame: 0, 1 ms, 0.6 s or 2 s), bytes 1-8 = payload.
// After each frame the client is polled; a transfer that ends is started again.
// Invariants: a frame that is not the server's changes nothing; what the client asks to send is
// an 8-byte standard frame on 0x605: a segment request of CiA 301 (upload: 0x60/0x70 with bytes
// 1-7 zero; download: its toggle, never more bytes than the data has) or, when it fails the
// transfer, an abort naming the transfer's object with a code the client uses; an upload never
// holds more bytes than its buffer, an expedited one at most 4; a server's abort is taken with its
// code; after any end the client is idle.
#include <array>
#include <cstddef>
#include <cstdint>

#include "fuzz_check.h"
#include "sdo_client.h"
#include "sdo_frame_record.h"

namespace {

using swum::canopen::SdoAbort;
using swum::canopen::SdoClient;
using swum::canopen::SdoProgress;
using swum::protocol::CanFrame;

constexpr std::uint8_t kNode = 5;
constexpr std::int64_t kTimeoutNs = 1'000'000'000;
constexpr std::size_t kBufferSizes[] = {0, 1, 2, 4, 7, 8, 16, 64};
constexpr std::size_t kDownloadSizes[] = {1, 2, 3, 4, 5, 7, 8, 64};
constexpr std::uint16_t kIndex = 0x2001;
constexpr std::uint8_t kSub = 0;

std::uint32_t u32_at(const CanFrame& frame, std::size_t at) {
  return static_cast<std::uint32_t>(frame.data[at] | (frame.data[at + 1] << 8) | (frame.data[at + 2] << 16) |
                                    (static_cast<std::uint32_t>(frame.data[at + 3]) << 24));
}

bool client_code(SdoAbort code) {
  return code == SdoAbort::toggle_bit || code == SdoAbort::timeout || code == SdoAbort::bad_command ||
         code == SdoAbort::out_of_memory || code == SdoAbort::length_mismatch || code == SdoAbort::general;
}

struct Transfer {
  bool download;
  bool segmented;
  std::size_t buffer_size;
  std::size_t download_size;
  std::array<std::uint8_t, 64> buffer{};
  std::array<std::uint8_t, 64> data{};
  std::size_t sent = 0;  // download bytes in the requests so far
  bool expedited = false;

  void start(SdoClient& client, std::int64_t now_ns) {
    CanFrame request;
    sent = 0;
    if (download) {
      FUZZ_CHECK(client.start_download(kIndex, kSub, std::span<const std::uint8_t>(data.data(), download_size), now_ns,
                                       request, segmented),
                 "a download of %zu bytes refused", download_size);
      expedited = (request.data[0] & 0x02) != 0;
      if (expedited) sent = download_size;
    } else {
      client.start_upload(kIndex, kSub, std::span<std::uint8_t>(buffer.data(), buffer_size), now_ns, request);
    }
    FUZZ_CHECK(request.id == 0x605 && request.dlc == 8 && !request.extended, "initiate on 0x%X", request.id);
    FUZZ_CHECK(client.busy(), "not busy after a start");
  }
};

void check_request(const CanFrame& request, SdoProgress progress, const SdoClient& client, Transfer& t) {
  FUZZ_CHECK(request.id == 0x605 && request.dlc == 8 && !request.extended, "request on 0x%X dlc %u", request.id,
             request.dlc);
  const std::uint8_t command = request.data[0];
  if (progress == SdoProgress::failed) {
    FUZZ_CHECK(command == 0x80, "a failure sends 0x%02X", command);
    FUZZ_CHECK((request.data[1] | (request.data[2] << 8)) == kIndex && request.data[3] == kSub, "abort names another");
    FUZZ_CHECK(u32_at(request, 4) == static_cast<std::uint32_t>(client.abort_code()), "abort code");
    FUZZ_CHECK(client_code(client.abort_code()), "client abort 0x%08X", u32_at(request, 4));
    return;
  }
  if (t.download) {
    FUZZ_CHECK((command >> 5) == 0, "download segment request 0x%02X", command);
    t.sent += 7 - ((command >> 1) & 0x07);
    FUZZ_CHECK(t.sent <= t.download_size, "%zu of %zu bytes sent", t.sent, t.download_size);
  } else {
    FUZZ_CHECK(command == 0x60 || command == 0x70, "upload segment request 0x%02X", command);
    for (std::size_t i = 1; i < 8; ++i) FUZZ_CHECK(request.data[i] == 0, "upload segment request byte %zu", i);
  }
}

void check_progress(SdoProgress progress, const CanFrame& response, const CanFrame& request, SdoClient& client,
                    Transfer& t, bool ours) {
  switch (progress) {
    case SdoProgress::ignored: return;
    case SdoProgress::send:
      FUZZ_CHECK(client.busy(), "a segment to send, idle");
      check_request(request, progress, client, t);
      return;
    case SdoProgress::failed:
      FUZZ_CHECK(!client.busy(), "busy after failing");
      check_request(request, progress, client, t);
      return;
    case SdoProgress::aborted:
      FUZZ_CHECK(ours && response.dlc == 8 && response.data[0] >> 5 == 4, "aborted without the server's abort");
      FUZZ_CHECK(static_cast<std::uint32_t>(client.abort_code()) == u32_at(response, 4), "abort code taken");
      FUZZ_CHECK(!client.busy(), "busy after an abort");
      return;
    case SdoProgress::done:
      FUZZ_CHECK(ours, "done without a frame of the server");
      FUZZ_CHECK(!client.busy(), "busy when done");
      if (t.download) {
        FUZZ_CHECK(t.sent == t.download_size, "done after %zu of %zu bytes", t.sent, t.download_size);
      } else {
        FUZZ_CHECK(client.uploaded().size() <= t.buffer_size, "%zu bytes in a buffer of %zu", client.uploaded().size(),
                   t.buffer_size);
        FUZZ_CHECK(client.uploaded().data() == t.buffer.data() || client.uploaded().empty(), "upload elsewhere");
      }
      return;
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  Transfer t{(data[0] & 0x01) != 0, (data[0] & 0x02) != 0, kBufferSizes[(data[0] >> 2) & 0x07],
             kDownloadSizes[(data[0] >> 5) & 0x07]};
  for (std::size_t i = 0; i < t.data.size(); ++i) t.data[i] = static_cast<std::uint8_t>(i * 37 + 1);
  SdoClient client(kNode, kTimeoutNs);
  std::int64_t now_ns = 0;
  t.start(client, now_ns);
  for (std::size_t at = 1; at + swum::fuzz::kSdoRecordBytes <= size; at += swum::fuzz::kSdoRecordBytes) {
    const CanFrame response = swum::fuzz::sdo_record_frame(data + at, 0x585, 0x586, now_ns);
    const bool ours = response.id == 0x585 && !response.extended;

    const bool busy = client.busy();
    CanFrame request;
    SdoProgress progress = client.poll(now_ns, request);
    FUZZ_CHECK(progress == SdoProgress::ignored || progress == SdoProgress::failed, "poll gave %d",
               static_cast<int>(progress));
    if (progress == SdoProgress::failed) {
      FUZZ_CHECK(busy && client.abort_code() == SdoAbort::timeout, "poll failed with 0x%08X",
                 static_cast<unsigned>(client.abort_code()));
      check_progress(progress, response, request, client, t, ours);
    } else {
      progress = client.receive(response, now_ns, request);
      if (!ours || !busy) FUZZ_CHECK(progress == SdoProgress::ignored, "took a frame that is not the server's");
      check_progress(progress, response, request, client, t, ours);
    }
    if (!client.busy()) t.start(client, now_ns);
  }
  return 0;
}
