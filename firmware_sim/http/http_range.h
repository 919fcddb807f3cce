// The byte range a recording's download serves (RFC 9110, section 14.1.2): one range, "bytes=A-B",
// "bytes=A-" or "bytes=-N", resolved against the file's size. The API parses Range itself and
// hides it from cpp-httplib, whose 0.11 slices error bodies with it, answers several ranges with
// "Content-Range: .../0" and checks no range against the size (docs/http-api.md, "Recording").
// cpp-httplib still checks the header's form first: it answers 416 itself, before any handler,
// to anything but "bytes=" and digits (another unit, "Bytes=", spaces). This resolves those
// too (another unit: whole; spaces: ignored), as the RFC would, for a server that lets them by.
#pragma once

#include <cstdint>
#include <string_view>

namespace swum::emu {

struct ByteRange {
  enum class Kind {
    whole,          // serve the whole file, 200: no Range, or several ranges (RFC 9110 allows ignoring)
    partial,        // serve [first, last], 206 with Content-Range "bytes first-last/size"
    unsatisfiable,  // 416 with Content-Range "bytes */size": no byte of the file in the range
  };
  Kind kind = Kind::whole;
  std::uint64_t first = 0;
  std::uint64_t last = 0;  // inclusive
};

// `header` is the Range header's value ("" when absent). A malformed single range of the bytes
// unit is unsatisfiable; the caller answers 416.
ByteRange resolve_byte_range(std::string_view header, std::uint64_t size);

}  // namespace swum::emu
