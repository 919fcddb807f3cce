// Golden codec vectors: every case of tests/golden/codec_vectors.json is run on the current code
// and must give the stored output — Modbus register words and PDUs/ADUs, CAN frame bytes (id,
// DLC, data, CRC, alive counter), the decoded values and the host clients' encodings. Integers,
// strings and bytes must match exactly; decoded floating-point values within 1e-12 relative.
//
// The vectors were generated once from the code of the commit that added them
// (codec_golden_generate.cpp; how: tests/golden/README.md). Regenerate them ONLY for a
// deliberate protocol change. A restructuring that moves the codecs updates the ADAPTER section
// of codec_golden.cpp, not the vectors.
#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>

#include "codec_golden.h"
#include "test_paths.h"

namespace {

using nlohmann::json;

constexpr double kRelative = 1e-12;

const json& vectors() {
  static const json document = [] {
    std::ifstream in(swum::test::source_path("tests/golden/codec_vectors.json"));
    if (!in) throw std::runtime_error("cannot read " + swum::test::source_path("tests/golden/codec_vectors.json"));
    return json::parse(in);
  }();
  return document;
}

class CodecGolden : public ::testing::TestWithParam<std::string> {};

TEST_P(CodecGolden, MatchesTheStoredVectors) {
  const std::string kind = GetParam();
  int checked = 0;
  for (const json& c : vectors().at("cases")) {
    if (c.at("kind") != kind) continue;
    ++checked;
    const std::string name = c.at("name").get<std::string>();
    json actual;
    try {
      actual = swum::golden::run_codec_case(kind, c.at("input"));
    } catch (const std::exception& e) {
      ADD_FAILURE() << kind << " / " << name << ": threw " << e.what();
      continue;
    }
    std::string where;
    EXPECT_TRUE(swum::golden::json_matches(c.at("expect"), actual, kRelative, where))
        << kind << " / " << name << "\n  first difference at " << where << "\n  input:    " << c.at("input").dump()
        << "\n  expected: " << c.at("expect").dump() << "\n  actual:   " << actual.dump();
  }
  EXPECT_GT(checked, 0) << "no vectors of kind " << kind;
}

std::string test_name(const ::testing::TestParamInfo<std::string>& info) {
  std::string name = info.param;
  for (char& ch : name)
    if (ch == '.') ch = '_';
  return name;
}

INSTANTIATE_TEST_SUITE_P(Kinds, CodecGolden, ::testing::ValuesIn(swum::golden::codec_kinds()), test_name);

// The file holds only kinds the runner knows (a renamed kind would otherwise go unchecked).
TEST(CodecGoldenFile, EveryCaseHasAKnownKind) {
  const auto& kinds = swum::golden::codec_kinds();
  const std::set<std::string> known(kinds.begin(), kinds.end());
  std::map<std::string, int> unknown;
  for (const json& c : vectors().at("cases")) {
    if (!known.count(c.at("kind").get<std::string>())) ++unknown[c.at("kind").get<std::string>()];
  }
  EXPECT_TRUE(unknown.empty()) << "unknown kind " << (unknown.empty() ? "" : unknown.begin()->first);
}

// The comparison itself: a tolerance for decoded values only, never for bytes.
TEST(CodecGoldenFile, ComparisonIsExactForIntegersAndTextAndTightForFloats) {
  std::string where;
  EXPECT_TRUE(swum::golden::json_matches(json(0.1), json(0.1 + 1e-17), kRelative, where));
  EXPECT_FALSE(swum::golden::json_matches(json(0.1), json(0.1000001), kRelative, where));
  EXPECT_FALSE(swum::golden::json_matches(json(513), json(514), kRelative, where));
  EXPECT_FALSE(swum::golden::json_matches(json("201#00"), json("201#01"), kRelative, where));
  EXPECT_FALSE(
      swum::golden::json_matches(json::parse(R"({"a":1})"), json::parse(R"({"a":1,"b":2})"), kRelative, where));
  EXPECT_FALSE(swum::golden::json_matches(json::parse("[1,2]"), json::parse("[1,2,3]"), kRelative, where));
  EXPECT_FALSE(swum::golden::json_matches(json(nullptr), json(0), kRelative, where));
}

}  // namespace
