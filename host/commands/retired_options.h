// Option spellings swum no longer accepts (issue 34, "One name per idea"; the vocabulary in
// docs/host.md, "Option names"). They are not aliases: when CLI11 refuses a command line that
// holds one, main() prints one line naming the new spelling and exits with the usage status.
// To retire a spelling, add a row to the table in retired_options.cpp; the CLI vocabulary test
// (tests/host/cli_vocabulary.py) then also checks that no command offers it any more.
#pragma once

#include <span>
#include <string>
#include <string_view>

namespace swum::host {

struct RetiredOption {
  std::string_view old_spelling;  // e.g. "--frequency"
  std::string_view new_spelling;  // e.g. "--frequency-hz"; empty: removed without a successor
  std::string_view why;           // one line: why the name changed
  // Empty: every command; else the one command the row is for (e.g. "swum admittance"), which
  // then answers with it instead of an every-command row of the same old spelling.
  std::string_view program{};
};

// Every retired spelling of every swum command, in the table's order.
std::span<const RetiredOption> retired_options();

// The first of args (the command line without the program name) that is a retired spelling of
// table (default: retired_options()), alone or as --old=VALUE, in the row for PROGRAM if the
// table has one, else in an every-command row; nullptr when none is.
const RetiredOption* find_retired_option(std::span<const std::string> args,
                                         std::span<const RetiredOption> table = retired_options(),
                                         std::string_view program = {});

// "PROGRAM: --old was renamed --new (why)" (or "PROGRAM: --old was removed (why)") for the first
// retired spelling in args; empty when args hold none. PROGRAM names the command, e.g. "swum sweep".
std::string retired_option_message(std::string_view program, std::span<const std::string> args,
                                   std::span<const RetiredOption> table = retired_options());

}  // namespace swum::host
