#include "sdo_client.h"

#include <algorithm>
#include <stdexcept>

#include "sdo_frame.h"

namespace swum::canopen {

namespace {

// CiA 301 7.2.4.3: the server's command specifier in bits 5-7 of byte 0.
enum class ServerCommand : std::uint8_t {
  upload_segment = 0,
  download_segment = 1,
  initiate_upload = 2,
  initiate_download = 3,
  abort = 4,
};

ServerCommand command_of(const protocol::CanFrame& frame) { return static_cast<ServerCommand>(frame.data[0] >> 5); }
constexpr std::uint8_t kToggleBit = 0x10;
constexpr std::uint8_t kLastSegmentBit = 0x01;  // c: no more segments
constexpr std::uint8_t kExpeditedBit = 0x02;    // e
constexpr std::uint8_t kSizeBit = 0x01;         // s: the size is indicated
constexpr std::size_t kSegmentBytes = 7;
constexpr std::size_t kExpeditedBytes = 4;

}  // namespace

SdoClient::SdoClient(std::uint8_t node_id, std::int64_t timeout_ns)
    : request_id_(0x600u + node_id), response_id_(0x580u + node_id), timeout_ns_(timeout_ns) {
  if (node_id < 1 || node_id > 127) throw std::invalid_argument("SDO client: node id outside 1..127");
  if (timeout_ns <= 0) throw std::invalid_argument("SDO client: the timeout must be > 0");
}

protocol::CanFrame SdoClient::blank_request() const { return sdo_frame(request_id_); }

void SdoClient::begin(State state, std::uint16_t index, std::uint8_t sub, std::int64_t now_ns) {
  state_ = state;
  index_ = index;
  sub_ = sub;
  toggle_ = false;  // the first segment carries toggle 0
  sent_ns_ = now_ns;
  abort_ = SdoAbort::none;
}

void SdoClient::start_upload(std::uint16_t index, std::uint8_t sub, std::span<std::uint8_t> destination,
                             std::int64_t now_ns, protocol::CanFrame& request) {
  begin(State::initiating_upload, index, sub, now_ns);
  destination_ = destination;
  length_ = 0;
  indicated_ = 0;
  request = blank_request();
  request.data[0] = 0x40;  // ccs 2: initiate upload
  request.data[1] = static_cast<std::uint8_t>(index);
  request.data[2] = static_cast<std::uint8_t>(index >> 8);
  request.data[3] = sub;
}

bool SdoClient::start_download(std::uint16_t index, std::uint8_t sub, std::span<const std::uint8_t> data,
                               std::int64_t now_ns, protocol::CanFrame& request, bool segmented) {
  if (data.empty()) return false;
  begin(State::initiating_download, index, sub, now_ns);
  source_ = data;
  request = blank_request();
  request.data[1] = static_cast<std::uint8_t>(index);
  request.data[2] = static_cast<std::uint8_t>(index >> 8);
  request.data[3] = sub;
  if (!segmented && data.size() <= kExpeditedBytes) {
    // ccs 1, e = 1, s = 1, n = the bytes of 4-7 that hold no data.
    request.data[0] = static_cast<std::uint8_t>(0x23 | ((kExpeditedBytes - data.size()) << 2));
    std::copy(data.begin(), data.end(), request.data.begin() + 4);
    sent_ = data.size();
    last_segment_sent_ = true;
  } else {
    request.data[0] = 0x21;  // ccs 1, e = 0, s = 1: the size in bytes 4-7, then segments
    put_u32(request, 4, static_cast<std::uint32_t>(data.size()));
    sent_ = 0;
    last_segment_sent_ = false;
  }
  return true;
}

SdoProgress SdoClient::fail(SdoAbort code, protocol::CanFrame& request) {
  request = sdo_abort_frame(request_id_, index_, sub_, code);
  state_ = State::idle;
  abort_ = code;
  return SdoProgress::failed;
}

bool SdoClient::names_transfer(const protocol::CanFrame& response) const {
  return (response.data[1] | (response.data[2] << 8)) == index_ && response.data[3] == sub_;
}

SdoProgress SdoClient::receive(const protocol::CanFrame& response, std::int64_t now_ns, protocol::CanFrame& request) {
  if (response.extended || response.id != response_id_ || state_ == State::idle) return SdoProgress::ignored;
  // CiA 301 fixes an SDO frame at 8 bytes: anything else is not a response we can read.
  if (response.dlc != 8) return fail(SdoAbort::general, request);
  if (command_of(response) == ServerCommand::abort) {
    // The server's abort ends the transfer on both sides without an answer (7.2.4.3.17). Taken
    // whatever object it names: a server that lost the transfer names none (0, 0).
    state_ = State::idle;
    abort_ = static_cast<SdoAbort>(u32_at(response, 4));
    return SdoProgress::aborted;
  }
  switch (state_) {
    case State::initiating_upload: return on_upload_initiated(response, now_ns, request);
    case State::uploading: return on_upload_segment(response, now_ns, request);
    case State::initiating_download:
    case State::downloading: return on_download_answer(response, now_ns, request);
    case State::idle: break;
  }
  return SdoProgress::ignored;
}

SdoProgress SdoClient::on_upload_initiated(const protocol::CanFrame& response, std::int64_t now_ns,
                                           protocol::CanFrame& request) {
  if (command_of(response) != ServerCommand::initiate_upload) return fail(SdoAbort::bad_command, request);
  if (!names_transfer(response)) return fail(SdoAbort::general, request);
  const std::uint8_t command = response.data[0];
  const bool size_indicated = (command & kSizeBit) != 0;
  if ((command & kExpeditedBit) != 0) {
    // e = 1: the data is in bytes 4-7, 4 - n of them when s = 1 (all four when the size is not given).
    const std::size_t length = size_indicated ? kExpeditedBytes - ((command >> 2) & 0x03) : kExpeditedBytes;
    if (length > destination_.size()) return fail(SdoAbort::out_of_memory, request);
    std::copy_n(response.data.begin() + 4, length, destination_.begin());
    length_ = length;
    state_ = State::idle;
    return SdoProgress::done;
  }
  // e = 0: segmented; s = 1 gives the total size in bytes 4-7 (7.2.4.3.5).
  indicated_ = size_indicated ? u32_at(response, 4) : 0;
  if (indicated_ > destination_.size()) return fail(SdoAbort::out_of_memory, request);
  state_ = State::uploading;
  toggle_ = false;
  sent_ns_ = now_ns;
  upload_segment_request(request);
  return SdoProgress::send;
}

void SdoClient::upload_segment_request(protocol::CanFrame& request) const {
  request = blank_request();
  request.data[0] = static_cast<std::uint8_t>(0x60 | (toggle_ ? kToggleBit : 0));  // ccs 3
}

SdoProgress SdoClient::on_upload_segment(const protocol::CanFrame& response, std::int64_t now_ns,
                                         protocol::CanFrame& request) {
  const std::uint8_t command = response.data[0];
  if (command_of(response) != ServerCommand::upload_segment) return fail(SdoAbort::bad_command, request);
  if (((command & kToggleBit) != 0) != toggle_) return fail(SdoAbort::toggle_bit, request);
  const std::size_t length = kSegmentBytes - ((command >> 1) & 0x07);
  if (length_ + length > destination_.size()) return fail(SdoAbort::out_of_memory, request);
  if (indicated_ != 0 && length_ + length > indicated_) return fail(SdoAbort::length_mismatch, request);
  std::copy_n(response.data.begin() + 1, length, destination_.begin() + static_cast<std::ptrdiff_t>(length_));
  length_ += length;
  if ((command & kLastSegmentBit) != 0) {
    if (indicated_ != 0 && length_ != indicated_) return fail(SdoAbort::length_mismatch, request);
    state_ = State::idle;
    return SdoProgress::done;
  }
  toggle_ = !toggle_;
  sent_ns_ = now_ns;
  upload_segment_request(request);
  return SdoProgress::send;
}

void SdoClient::next_download_segment(protocol::CanFrame& request) {
  const std::size_t length = std::min(kSegmentBytes, source_.size() - sent_);
  last_segment_sent_ = sent_ + length == source_.size();
  request = blank_request();
  // ccs 0, t, n = the bytes of 1-7 that hold no data, c = no more segments.
  request.data[0] = static_cast<std::uint8_t>((toggle_ ? kToggleBit : 0) | ((kSegmentBytes - length) << 1) |
                                              (last_segment_sent_ ? kLastSegmentBit : 0));
  std::copy_n(source_.begin() + static_cast<std::ptrdiff_t>(sent_), length, request.data.begin() + 1);
  sent_ += length;
}

SdoProgress SdoClient::on_download_answer(const protocol::CanFrame& response, std::int64_t now_ns,
                                          protocol::CanFrame& request) {
  if (state_ == State::initiating_download) {
    if (command_of(response) != ServerCommand::initiate_download) return fail(SdoAbort::bad_command, request);
    if (!names_transfer(response)) return fail(SdoAbort::general, request);
    if (last_segment_sent_) {  // expedited: the data went with the request
      state_ = State::idle;
      return SdoProgress::done;
    }
    state_ = State::downloading;
    toggle_ = false;
  } else {
    if (command_of(response) != ServerCommand::download_segment) return fail(SdoAbort::bad_command, request);
    if (((response.data[0] & kToggleBit) != 0) != toggle_) return fail(SdoAbort::toggle_bit, request);
    if (last_segment_sent_) {
      state_ = State::idle;
      return SdoProgress::done;
    }
    toggle_ = !toggle_;
  }
  sent_ns_ = now_ns;
  next_download_segment(request);
  return SdoProgress::send;
}

SdoProgress SdoClient::poll(std::int64_t now_ns, protocol::CanFrame& request) {
  if (state_ == State::idle || now_ns - sent_ns_ <= timeout_ns_) return SdoProgress::ignored;
  return fail(SdoAbort::timeout, request);
}

}  // namespace swum::canopen
