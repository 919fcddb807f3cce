// The one comma-list splitter (src/formats/name_list.h): the whitespace rule and the refusal of
// empty names, as every option that takes a name list sees them.
#include "formats/name_list.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace swum {
namespace {

using Views = std::vector<std::string_view>;
using Names = std::vector<std::string>;

TEST(NameList, BlanksAroundEntriesAreDroppedAndInsideKept) {
  EXPECT_EQ(split_comma_list(" a ,\tb c\t,d"), (Views{"a", "b c", "d"}));
  EXPECT_EQ(split_comma_list("a,,b,"), (Views{"a", "", "b", ""}));
  EXPECT_EQ(split_comma_list(""), (Views{""}));
}

TEST(NameList, NamesInOrderDuplicatesKept) {
  Names names;
  EXPECT_EQ(split_name_list("thermal, wear,thermal", names), "");
  EXPECT_EQ(names, (Names{"thermal", "wear", "thermal"}));
  EXPECT_EQ(parse_name_list("speed", "--quantities"), (Names{"speed"}));
}

TEST(NameList, EveryEmptyNameIsRefusedWithOneMessage) {
  for (const std::string text : {"a,,b", "a,", ",a", "", " ", "a, ,b", ","}) {
    SCOPED_TRACE(text);
    Names names{"untouched"};
    EXPECT_EQ(split_name_list(text, names), "empty name in '" + text + "'");
    EXPECT_EQ(names, (Names{"untouched"}));  // nothing written on failure
  }
  try {
    (void)parse_name_list("thermal,,wear", "--effects");
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "--effects: empty name in 'thermal,,wear'");
  }
}

}  // namespace
}  // namespace swum
