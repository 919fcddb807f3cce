#include "sdo_server.h"

#include <algorithm>
#include <stdexcept>

#include "sdo_frame.h"

namespace swum::canopen {

namespace {

// CiA 301 7.2.4.3: the command specifier in bits 5-7 of byte 0.
// Block upload (5) and block download (6) are not offered; 7 is no command.
enum class ClientCommand : std::uint8_t { download_segment, initiate_download, initiate_upload, upload_segment, abort };

ClientCommand command_of(const protocol::CanFrame& frame) { return static_cast<ClientCommand>(frame.data[0] >> 5); }
constexpr std::uint8_t kToggleBit = 0x10;
constexpr std::uint8_t kLastSegmentBit = 0x01;
constexpr std::size_t kSegmentBytes = 7;

std::uint16_t index_of(const protocol::CanFrame& frame) {
  return static_cast<std::uint16_t>(frame.data[1] | (frame.data[2] << 8));
}

}  // namespace

SdoServer::SdoServer(ObjectDictionary& od, std::uint8_t node_id, std::int64_t timeout_ns)
    : od_(od), request_id_(0x600u + node_id), response_id_(0x580u + node_id), timeout_ns_(timeout_ns) {
  if (node_id < 1 || node_id > 127) throw std::invalid_argument("SDO server: node id outside 1..127");
  if (timeout_ns <= 0) throw std::invalid_argument("SDO server: the timeout must be > 0");
}

protocol::CanFrame SdoServer::blank_response() const { return sdo_frame(response_id_); }

bool SdoServer::answer_abort(std::uint16_t index, std::uint8_t sub, SdoAbort code, protocol::CanFrame& response) {
  response = sdo_abort_frame(response_id_, index, sub, code);
  state_ = State::idle;  // an abort ends the transfer on both sides
  ++aborts_sent_;
  last_abort_ = code;
  return true;
}

void SdoServer::begin(State state, std::size_t slot, std::uint16_t index, std::uint8_t sub, std::int64_t now_ns) {
  state_ = state;
  slot_ = slot;
  index_ = index;
  sub_ = sub;
  toggle_ = false;  // the first segment carries toggle 0
  last_frame_ns_ = now_ns;
}

bool SdoServer::abort_segment(SdoAbort problem, protocol::CanFrame& response) {
  const bool under_way = state_ != State::idle;  // a segment of no transfer names no object
  return answer_abort(under_way ? index_ : 0, under_way ? sub_ : 0, problem, response);
}

SdoAbort SdoServer::check_segment(State expected, std::uint8_t command) const {
  if (state_ != expected) return SdoAbort::bad_command;  // no transfer, or one of the other direction
  if (((command & kToggleBit) != 0) != toggle_) return SdoAbort::toggle_bit;
  return SdoAbort::none;
}

bool SdoServer::receive(const protocol::CanFrame& request, std::int64_t now_ns, protocol::CanFrame& response) {
  if (request.extended || request.id != request_id_) return false;
  // A client's abort ends the transfer without an answer (CiA 301 7.2.4.3.17), whatever its length.
  if (request.dlc >= 1 && command_of(request) == ClientCommand::abort) {
    state_ = State::idle;
    return false;
  }
  if (request.dlc != 8) {
    const std::uint16_t index = request.dlc >= 3 ? index_of(request) : 0;
    const std::uint8_t sub = request.dlc >= 4 ? request.data[3] : 0;
    return answer_abort(index, sub, SdoAbort::general, response);
  }
  switch (command_of(request)) {
    case ClientCommand::initiate_download: return initiate_download(request, now_ns, response);
    case ClientCommand::download_segment: return download_segment(request, now_ns, response);
    case ClientCommand::initiate_upload: return initiate_upload(request, now_ns, response);
    case ClientCommand::upload_segment: return upload_segment(request, now_ns, response);
    default: break;  // block transfer (5, 6) is not offered; 7 is no command
  }
  return answer_abort(index_of(request), request.data[3], SdoAbort::bad_command, response);
}

bool SdoServer::initiate_download(const protocol::CanFrame& request, std::int64_t now_ns,
                                  protocol::CanFrame& response) {
  state_ = State::idle;  // a new initiate replaces a transfer under way
  const std::uint16_t index = index_of(request);
  const std::uint8_t sub = request.data[3];
  const auto slot = od_.find(index, sub);
  if (!slot)
    return answer_abort(index, sub, od_.has_index(index) ? SdoAbort::no_sub_index : SdoAbort::no_object, response);
  const ObjectDescription& d = od_.description(*slot);
  if (d.access == Access::ro || d.access == Access::const_)
    return answer_abort(index, sub, SdoAbort::read_only, response);
  const std::uint8_t command = request.data[0];
  const bool expedited = (command & 0x02) != 0;
  const bool size_indicated = (command & 0x01) != 0;
  const std::size_t object_size = size_of(d.type);
  if (expedited) {
    // e = 1: the data is in bytes 4-7; with s = 1 its length is 4 - n, otherwise unspecified
    // (then the object's own size is taken).
    const std::size_t length = size_indicated ? 4 - ((command >> 2) & 0x03) : std::min<std::size_t>(object_size, 4);
    const SdoAbort result = od_.write(*slot, std::span<const std::uint8_t>(request.data.data() + 4, length));
    if (result != SdoAbort::none) return answer_abort(index, sub, result, response);
  } else {
    // e = 0: segmented; with s = 1 bytes 4-7 hold the total size, checked against the object now.
    std::uint32_t indicated = 0;
    for (std::size_t i = 0; i < 4; ++i) indicated |= std::uint32_t{request.data[4 + i]} << (8 * i);
    if (size_indicated && indicated > object_size) return answer_abort(index, sub, SdoAbort::length_too_high, response);
    if (size_indicated && indicated < object_size) return answer_abort(index, sub, SdoAbort::length_too_low, response);
    begin(State::downloading, *slot, index, sub, now_ns);
    download_length_ = 0;
    download_indicated_ = size_indicated ? indicated : 0;
  }
  response = blank_response();
  response.data[0] = 0x60;  // scs 3: initiate download response
  response.data[1] = request.data[1];
  response.data[2] = request.data[2];
  response.data[3] = sub;
  return true;
}

bool SdoServer::download_segment(const protocol::CanFrame& request, std::int64_t now_ns, protocol::CanFrame& response) {
  const std::uint8_t command = request.data[0];
  if (const SdoAbort problem = check_segment(State::downloading, command); problem != SdoAbort::none)
    return abort_segment(problem, response);
  const std::size_t length = kSegmentBytes - ((command >> 1) & 0x07);
  if (download_length_ + length > download_.size())
    return answer_abort(index_, sub_, SdoAbort::length_too_high, response);
  std::copy_n(request.data.begin() + 1, length, download_.begin() + static_cast<std::ptrdiff_t>(download_length_));
  download_length_ += length;
  if ((command & kLastSegmentBit) != 0) {
    if (download_indicated_ != 0 && download_length_ != download_indicated_)
      return answer_abort(index_, sub_, SdoAbort::length_mismatch, response);
    const SdoAbort result = od_.write(slot_, std::span<const std::uint8_t>(download_.data(), download_length_));
    if (result != SdoAbort::none) return answer_abort(index_, sub_, result, response);
    state_ = State::idle;
  }
  response = blank_response();
  response.data[0] = static_cast<std::uint8_t>(0x20 | (toggle_ ? kToggleBit : 0));  // scs 1
  toggle_ = !toggle_;
  last_frame_ns_ = now_ns;
  return true;
}

bool SdoServer::initiate_upload(const protocol::CanFrame& request, std::int64_t now_ns, protocol::CanFrame& response) {
  state_ = State::idle;
  const std::uint16_t index = index_of(request);
  const std::uint8_t sub = request.data[3];
  const auto slot = od_.find(index, sub);
  if (!slot)
    return answer_abort(index, sub, od_.has_index(index) ? SdoAbort::no_sub_index : SdoAbort::no_object, response);
  response = blank_response();
  response.data[1] = request.data[1];
  response.data[2] = request.data[2];
  response.data[3] = sub;
  if (od_.description(*slot).type == DataType::visible_string) {
    std::string_view text;
    if (const SdoAbort result = od_.read_string(*slot, text); result != SdoAbort::none)
      return answer_abort(index, sub, result, response);
    if (!text.empty() && text.size() <= 4) {
      response.data[0] = static_cast<std::uint8_t>(0x43 | ((4 - text.size()) << 2));  // scs 2, e = 1, s = 1
      std::copy(text.begin(), text.end(), response.data.begin() + 4);
      return true;
    }
    // Segmented (CiA 301 7.2.4.3.5): s = 1 with the size in bytes 4-7, then segments of 7.
    response.data[0] = 0x41;
    put_u32(response, 4, static_cast<std::uint32_t>(text.size()));
    begin(State::uploading, *slot, index, sub, now_ns);
    upload_text_ = text;
    upload_offset_ = 0;
    return true;
  }
  std::size_t length = 0;
  if (const SdoAbort result = od_.read(*slot, upload_number_, length); result != SdoAbort::none)
    return answer_abort(index, sub, result, response);
  response.data[0] = static_cast<std::uint8_t>(0x43 | ((4 - length) << 2));
  std::copy_n(upload_number_.begin(), length, response.data.begin() + 4);
  return true;
}

bool SdoServer::upload_segment(const protocol::CanFrame& request, std::int64_t now_ns, protocol::CanFrame& response) {
  const std::uint8_t command = request.data[0];
  if (const SdoAbort problem = check_segment(State::uploading, command); problem != SdoAbort::none)
    return abort_segment(problem, response);
  const std::size_t length = std::min(kSegmentBytes, upload_text_.size() - upload_offset_);
  const bool last = upload_offset_ + length == upload_text_.size();
  response = blank_response();
  response.data[0] = static_cast<std::uint8_t>((toggle_ ? kToggleBit : 0) | ((kSegmentBytes - length) << 1) |
                                               (last ? kLastSegmentBit : 0));  // scs 0
  std::copy_n(upload_text_.begin() + static_cast<std::ptrdiff_t>(upload_offset_), length, response.data.begin() + 1);
  upload_offset_ += length;
  toggle_ = !toggle_;
  last_frame_ns_ = now_ns;
  if (last) state_ = State::idle;
  return true;
}

bool SdoServer::poll(std::int64_t now_ns, protocol::CanFrame& abort) {
  if (state_ == State::idle || now_ns - last_frame_ns_ <= timeout_ns_) return false;
  return answer_abort(index_, sub_, SdoAbort::timeout, abort);
}

void SdoServer::reset() { state_ = State::idle; }

}  // namespace swum::canopen
