// A whole decimal number read strictly: the entire text, digits with an optional leading '-',
// no blanks, no '+', no fraction or exponent, no trailing characters, within [min, max]. What
// every integer from a command line or a spec string goes through, so "15x" or "1502.9" is
// refused instead of being read as its prefix (std::stoi's behaviour).
#pragma once

#include <optional>
#include <string_view>

namespace swum::protocol {

std::optional<long long> parse_whole_number(std::string_view text, long long min, long long max);

}  // namespace swum::protocol
