// Golden codec vectors (tests/golden/README.md): one JSON case = a kind, an input and the
// output today's code produced for it. run_codec_case() is what both the test and the
// generator call, so the two can never disagree on how an input is fed to the code.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace swum::golden {

// Every kind the vector file may hold, in file order.
const std::vector<std::string>& codec_kinds();

// Runs one case of `kind` on the current code. Throws std::invalid_argument for an unknown kind
// or an input that lacks a field (the vector file is strict: every input field is written out).
nlohmann::json run_codec_case(const std::string& kind, const nlohmann::json& input);

// True when `actual` equals `expected`: same structure and keys, integers, strings and booleans
// exactly, other numbers within `relative` (relative to the larger magnitude). `where` gets the
// JSON path of the first difference.
bool json_matches(const nlohmann::json& expected, const nlohmann::json& actual, double relative, std::string& where);

}  // namespace swum::golden
