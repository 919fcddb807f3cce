// The retired option spellings (host/commands/retired_options.h): found alone or as --old=VALUE,
// not in the spellings that replaced them, and answered with one line naming the new spelling.
// That swum answers them so on its command line, and that no command offers one, is
// tests/host/cli_vocabulary.py's (host.cli_vocabulary.help).
#include "commands/retired_options.h"

#include <gtest/gtest.h>

#include <set>
#include <string>
#include <utility>
#include <vector>

namespace swum::host {
namespace {

TEST(RetiredOptions, FoundAloneOrWithAValue) {
  const std::vector<std::string> alone{"--config", "a.toml", "--frequency", "40000"};
  const RetiredOption* found = find_retired_option(alone);
  ASSERT_NE(found, nullptr);
  EXPECT_EQ(found->old_spelling, "--frequency");
  EXPECT_EQ(found->new_spelling, "--frequency-hz");
  const std::vector<std::string> with_value{"--threads=4"};
  found = find_retired_option(with_value);
  ASSERT_NE(found, nullptr);
  EXPECT_EQ(found->new_spelling, "--jobs");
}

TEST(RetiredOptions, NewSpellingsAndLongerNamesAreNotRetired) {
  const std::vector<std::string> args{
      "--frequency-hz", "40000", "--duration-s=1", "--drive-phase-deg", "90", "--frequencyx", "--plot-dir", "p"};
  EXPECT_EQ(find_retired_option(args), nullptr);
  EXPECT_EQ(retired_option_message("swum sweep", args), "");
}

TEST(RetiredOptions, TheFirstRetiredSpellingIsNamedInOneLine) {
  const std::vector<std::string> args{"--out", "x.csv", "--duration", "5", "--threads", "2"};
  const std::string message = retired_option_message("swum log", args);
  EXPECT_EQ(message.rfind("swum log: --duration was renamed --duration-s (", 0), 0u) << message;
  EXPECT_EQ(message.back(), ')');
  EXPECT_EQ(message.find('\n'), std::string::npos);
}

TEST(RetiredOptions, ARowWithoutANewSpellingSaysRemoved) {
  const RetiredOption table[] = {{"--voltage-convention", "", "the drive's objects are terminal amplitudes"}};
  const std::vector<std::string> args{"--voltage-convention=amplitude"};
  EXPECT_EQ(retired_option_message("swum log", args, table),
            "swum log: --voltage-convention was removed (the drive's objects are terminal amplitudes)");
}

TEST(RetiredOptions, ACommandsOwnRowWinsOverTheEveryCommandRow) {
  const std::vector<std::string> args{"--phase", "b"};
  EXPECT_EQ(
      retired_option_message("swum admittance", args).rfind("swum admittance: --phase was renamed --driven-phase (", 0),
      0u);
  EXPECT_EQ(retired_option_message("swum sweep", args).rfind("swum sweep: --phase was renamed --drive-phase-deg (", 0),
            0u);
}

TEST(RetiredOptions, EveryRowIsARenameWithAReason) {
  std::set<std::pair<std::string_view, std::string_view>> olds;
  for (const RetiredOption& r : retired_options()) {
    EXPECT_TRUE(r.old_spelling.starts_with("--")) << r.old_spelling;
    EXPECT_TRUE(r.new_spelling.empty() || r.new_spelling.starts_with("--")) << r.new_spelling;
    EXPECT_NE(r.old_spelling, r.new_spelling);
    EXPECT_FALSE(r.why.empty()) << r.old_spelling;
    EXPECT_TRUE(olds.insert({r.old_spelling, r.program}).second) << r.old_spelling << " twice";
  }
  for (const RetiredOption& r : retired_options()) {
    for (const auto& old : olds) EXPECT_NE(old.first, r.new_spelling) << r.new_spelling;
  }
}

}  // namespace
}  // namespace swum::host
