// split_list: comma-separated option values as their items, empty items dropped.
#include "slamkit/core/string_list.h"

#include <gtest/gtest.h>

namespace slamkit {
namespace {

using List = std::vector<std::string>;

TEST(SplitList, ItemsInOrder) { EXPECT_EQ(split_list("gn,lm,dogleg"), (List{"gn", "lm", "dogleg"})); }

TEST(SplitList, EmptyItemsAreDropped) {
  EXPECT_EQ(split_list(""), List{});
  EXPECT_EQ(split_list(","), List{});
  EXPECT_EQ(split_list(",a,,b,"), (List{"a", "b"}));
}

TEST(SplitList, OneItemAndOtherSeparator) {
  EXPECT_EQ(split_list("sgd"), List{"sgd"});
  EXPECT_EQ(split_list("1:2:3", ':'), (List{"1", "2", "3"}));
  EXPECT_EQ(split_list("a b", ','), List{"a b"});
}

}  // namespace
}  // namespace slamkit
