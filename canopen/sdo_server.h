// The SDO server of a CiA 301 slave (CiA 301 7.2.4): expedited and segmented upload and download
// on the default SDO channel (request 0x600 + node, response 0x580 + node), answering each bad
// request with the abort code CiA 301 names. Block transfer is not offered (its command
// specifiers 5 and 6 are aborted with bad_command). Pure and per-frame: no sockets, clocks,
// threads, allocation or exceptions after construction; the caller passes the time.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "can_frame.h"
#include "object_dictionary.h"

namespace swum::canopen {

class SdoServer {
 public:
  // Throws std::invalid_argument for a node id outside 1..127 or a timeout <= 0.
  SdoServer(ObjectDictionary& od, std::uint8_t node_id, std::int64_t timeout_ns = 1'000'000'000);

  // A frame whose id is 0x600 + node: true with `response` (id 0x580 + node, DLC 8) to send.
  // Other frames, and a client's abort (which ends a transfer silently), give false. A request
  // with a DLC other than 8 is answered with the abort general (0x08000000): CiA 301 7.2.4.3
  // fixes every SDO frame at 8 bytes, and an answer tells the client what went wrong where
  // silence would only time it out.
  bool receive(const protocol::CanFrame& request, std::int64_t now_ns, protocol::CanFrame& response);
  // A segmented transfer idle longer than the timeout: true once with the timeout abort to send.
  bool poll(std::int64_t now_ns, protocol::CanFrame& abort);
  void reset();  // NMT reset communication: a transfer under way is dropped

  [[nodiscard]] std::uint64_t aborts_sent() const { return aborts_sent_; }
  [[nodiscard]] SdoAbort last_abort() const { return last_abort_; }
  [[nodiscard]] bool transfer_in_progress() const { return state_ != State::idle; }

 private:
  enum class State : std::uint8_t { idle, downloading, uploading };

  void begin(State state, std::size_t slot, std::uint16_t index, std::uint8_t sub, std::int64_t now_ns);
  [[nodiscard]] SdoAbort check_segment(State expected, std::uint8_t command) const;
  bool abort_segment(SdoAbort problem, protocol::CanFrame& response);
  bool answer_abort(std::uint16_t index, std::uint8_t sub, SdoAbort code, protocol::CanFrame& response);
  bool initiate_download(const protocol::CanFrame& request, std::int64_t now_ns, protocol::CanFrame& response);
  bool download_segment(const protocol::CanFrame& request, std::int64_t now_ns, protocol::CanFrame& response);
  bool initiate_upload(const protocol::CanFrame& request, std::int64_t now_ns, protocol::CanFrame& response);
  bool upload_segment(const protocol::CanFrame& request, std::int64_t now_ns, protocol::CanFrame& response);
  [[nodiscard]] protocol::CanFrame blank_response() const;

  ObjectDictionary& od_;
  std::uint32_t request_id_;
  std::uint32_t response_id_;
  std::int64_t timeout_ns_;

  State state_ = State::idle;
  std::size_t slot_ = 0;  // the object of the transfer under way
  std::uint16_t index_ = 0;
  std::uint8_t sub_ = 0;
  bool toggle_ = false;  // the toggle bit the next segment must carry
  std::int64_t last_frame_ns_ = 0;
  // A download's bytes so far (every writable object is a number of at most 4 bytes) and the
  // size the client indicated (0: none).
  std::array<std::uint8_t, 4> download_{};
  std::size_t download_length_ = 0;
  std::size_t download_indicated_ = 0;
  // An upload's source: a string's text or a number's bytes, and how far it has been sent.
  std::array<std::uint8_t, 4> upload_number_{};
  std::string_view upload_text_;
  std::size_t upload_offset_ = 0;

  std::uint64_t aborts_sent_ = 0;
  SdoAbort last_abort_ = SdoAbort::none;
};

}  // namespace swum::canopen
