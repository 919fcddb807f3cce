// firmware_sim/http/http_range.h: the one byte range a recording's download serves (RFC 9110, section 14),
// resolved against the file's size; several ranges and other units are the whole file.
#include "http/http_range.h"

#include <gtest/gtest.h>

#include <cstdint>

namespace swum::emu {
namespace {

using Kind = ByteRange::Kind;

void expect_partial(const char* header, std::uint64_t size, std::uint64_t first, std::uint64_t last) {
  const ByteRange r = resolve_byte_range(header, size);
  EXPECT_EQ(r.kind, Kind::partial) << header;
  EXPECT_EQ(r.first, first) << header;
  EXPECT_EQ(r.last, last) << header;
}

TEST(HttpRange, NoHeaderIsTheWholeFile) { EXPECT_EQ(resolve_byte_range("", 100).kind, Kind::whole); }

TEST(HttpRange, FirstAndLast) {
  expect_partial("bytes=0-9", 100, 0, 9);
  expect_partial("bytes=5-5", 100, 5, 5);
  expect_partial("bytes=99-99", 100, 99, 99);
  expect_partial(" bytes = 10 - 19 ", 100, 10, 19);
  expect_partial("BYTES=0-0", 100, 0, 0);  // the unit is case-insensitive
}

TEST(HttpRange, LastPastTheEndIsCutAtTheEnd) {
  expect_partial("bytes=90-200", 100, 90, 99);
  expect_partial("bytes=0-18446744073709551615", 100, 0, 99);
}

TEST(HttpRange, OpenEnded) {
  expect_partial("bytes=10-", 100, 10, 99);
  expect_partial("bytes=0-", 1, 0, 0);
}

TEST(HttpRange, Suffix) {
  expect_partial("bytes=-20", 100, 80, 99);
  expect_partial("bytes=-100", 100, 0, 99);
  expect_partial("bytes=-1000", 100, 0, 99);  // more than the file: all of it
}

TEST(HttpRange, NoByteOfTheFileIsUnsatisfiable) {
  for (const char* header : {"bytes=100-", "bytes=100-200", "bytes=999999-", "bytes=-0"})
    EXPECT_EQ(resolve_byte_range(header, 100).kind, Kind::unsatisfiable) << header;
  EXPECT_EQ(resolve_byte_range("bytes=0-", 0).kind, Kind::unsatisfiable);
  EXPECT_EQ(resolve_byte_range("bytes=-5", 0).kind, Kind::unsatisfiable);
}

TEST(HttpRange, MalformedSingleRangeIsUnsatisfiable) {
  for (const char* header : {"bytes=5-2", "bytes=x-y", "bytes=", "bytes=-", "bytes=5", "bytes=+1-2", "bytes=1-+2",
                             "bytes=-+5", "bytes=99999999999999999999-", "bytes=0x1-2"})
    EXPECT_EQ(resolve_byte_range(header, 100).kind, Kind::unsatisfiable) << header;
}

TEST(HttpRange, SeveralRangesAndOtherUnitsAreTheWholeFile) {
  for (const char* header : {"bytes=0-3,10-19", "bytes=0-3, -5", "items=0-5", "foo", "bytesx=0-5"})
    EXPECT_EQ(resolve_byte_range(header, 100).kind, Kind::whole) << header;
}

}  // namespace
}  // namespace swum::emu
