// The client side of CiA 301's SDO protocol (7.2.4) for one server (request 0x600 + node, response
// 0x580 + node): expedited and segmented upload and download, one transfer at a time, every bad
// response answered with the abort CiA 301 names. A pure state machine: the caller sends the
// frames it returns, feeds it the frames it receives and the time, and owns the bytes (an upload
// lands in the caller's buffer, a download is read from the caller's bytes until it ends). No
// sockets, clocks, threads, allocation or exceptions after construction.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "can_frame.h"
#include "object_dictionary.h"

namespace swum::canopen {

// What a call did to the transfer.
enum class SdoProgress : std::uint8_t {
  ignored,  // not this transfer's frame (another identifier, or no transfer under way): nothing changed
  send,     // send `request` (the next segment's request); the transfer goes on
  done,     // complete: an upload's bytes are uploaded()
  aborted,  // the server aborted it (abort_code()); nothing to send
  failed,   // the client aborts it: send `request` (the abort frame, abort_code())
};

class SdoClient {
 public:
  // Throws std::invalid_argument for a node id outside 1..127 or a timeout <= 0.
  explicit SdoClient(std::uint8_t node_id, std::int64_t timeout_ns = 1'000'000'000);

  // Starts an upload of (index, sub) into `destination` (which must outlive the transfer):
  // `request` is the initiate request to send. A transfer under way is replaced (CiA 301 lets a
  // new initiate end the old one on the server too).
  void start_upload(std::uint16_t index, std::uint8_t sub, std::span<std::uint8_t> destination, std::int64_t now_ns,
                    protocol::CanFrame& request);
  // Starts a download of `data` (1 byte at least; it must outlive the transfer): expedited when it
  // fits in 4 bytes unless `segmented`, which forces the segmented protocol (size indicated).
  // Returns false, sending nothing, for empty data.
  bool start_download(std::uint16_t index, std::uint8_t sub, std::span<const std::uint8_t> data, std::int64_t now_ns,
                      protocol::CanFrame& request, bool segmented = false);

  // A received frame; only 0x580 + node is looked at.
  SdoProgress receive(const protocol::CanFrame& response, std::int64_t now_ns, protocol::CanFrame& request);
  // A transfer that has waited longer than the timeout for its response fails with the timeout
  // abort (0x05040000), to send; otherwise ignored.
  SdoProgress poll(std::int64_t now_ns, protocol::CanFrame& request);

  [[nodiscard]] bool busy() const { return state_ != State::idle; }
  [[nodiscard]] SdoAbort abort_code() const { return abort_; }  // of the last transfer that ended badly
  // The bytes of the last upload that ended `done` (a view of the caller's destination).
  [[nodiscard]] std::span<const std::uint8_t> uploaded() const { return destination_.first(length_); }
  [[nodiscard]] std::uint32_t request_id() const { return request_id_; }
  [[nodiscard]] std::uint32_t response_id() const { return response_id_; }

 private:
  enum class State : std::uint8_t { idle, initiating_upload, uploading, initiating_download, downloading };

  [[nodiscard]] protocol::CanFrame blank_request() const;
  void begin(State state, std::uint16_t index, std::uint8_t sub, std::int64_t now_ns);
  SdoProgress fail(SdoAbort code, protocol::CanFrame& request);
  SdoProgress on_upload_initiated(const protocol::CanFrame& response, std::int64_t now_ns, protocol::CanFrame& request);
  SdoProgress on_upload_segment(const protocol::CanFrame& response, std::int64_t now_ns, protocol::CanFrame& request);
  SdoProgress on_download_answer(const protocol::CanFrame& response, std::int64_t now_ns, protocol::CanFrame& request);
  void next_download_segment(protocol::CanFrame& request);
  void upload_segment_request(protocol::CanFrame& request) const;
  [[nodiscard]] bool names_transfer(const protocol::CanFrame& response) const;

  std::uint32_t request_id_;
  std::uint32_t response_id_;
  std::int64_t timeout_ns_;

  State state_ = State::idle;
  std::uint16_t index_ = 0;
  std::uint8_t sub_ = 0;
  bool toggle_ = false;  // the toggle bit of the segment under way
  std::int64_t sent_ns_ = 0;
  SdoAbort abort_ = SdoAbort::none;
  // Upload: where the bytes go, how many arrived, the size the server indicated (0: none).
  std::span<std::uint8_t> destination_;
  std::size_t length_ = 0;
  std::size_t indicated_ = 0;
  // Download: the bytes and how many are sent.
  std::span<const std::uint8_t> source_;
  std::size_t sent_ = 0;
  bool last_segment_sent_ = false;
};

}  // namespace swum::canopen
