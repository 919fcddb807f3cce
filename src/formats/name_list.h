// Comma lists on a command line: the one splitter of the name and number lists (swum's --free,
// --candidates, --effects, --quantities; swum-emu's --gpio line list; the items of the number
// lists of host/output/value_lists.h). The key=value lists of --effect and --inject keep their
// own parsers (candidate_effects.cpp, scenario.cpp): their items are assignments, not names.
//
// Whitespace rule: an entry is what lies between two commas with the blanks (spaces and tabs)
// around it removed; blanks inside an entry are kept. A name list refuses an empty entry ("a,,b",
// "a,", ",a", " ", and the empty text itself) with one message, "empty name in 'LIST'", which the
// command line prefixes with its option ("--effects: empty name in 'thermal,,wear'").
#pragma once

#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace swum {

/// `text` cut at every comma, each entry trimmed of blanks: "a, b,,c" -> {"a", "b", "", "c"};
/// the empty text is one empty entry. Views into `text`.
[[nodiscard]] inline std::vector<std::string_view> split_comma_list(std::string_view text) {
  auto trim = [](std::string_view s) {
    while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
    while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
    return s;
  };
  std::vector<std::string_view> entries;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = text.find(',', start);
    entries.push_back(trim(text.substr(start, comma == std::string_view::npos ? comma : comma - start)));
    if (comma == std::string_view::npos) return entries;
    start = comma + 1;
  }
}

/// The names of `text` (split_comma_list) into `names`: "" when fine, else what is wrong
/// ("empty name in 'a,,b'") for the caller to prefix with its option or spec. Never throws.
[[nodiscard]] inline std::string split_name_list(std::string_view text, std::vector<std::string>& names) {
  std::vector<std::string> out;
  for (const std::string_view entry : split_comma_list(text)) {
    if (entry.empty()) {
      std::string problem = "empty name in '";
      problem.append(text).append(1, '\'');
      return problem;
    }
    out.emplace_back(entry);
  }
  names = std::move(out);
  return {};
}

/// A command-line option's name list: split_name_list, its problem thrown as
/// std::invalid_argument "OPTION: empty name in 'LIST'".
[[nodiscard]] inline std::vector<std::string> parse_name_list(std::string_view text, std::string_view option) {
  std::vector<std::string> names;
  if (std::string problem = split_name_list(text, names); !problem.empty()) {
    throw std::invalid_argument(std::string(option) + ": " + problem);
  }
  return names;
}

}  // namespace swum
