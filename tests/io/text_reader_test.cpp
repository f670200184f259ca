#include "slamkit/io/text_reader.h"

#include <gtest/gtest.h>

#include <sstream>

#include "slamkit/core/error.h"

namespace slamkit {
namespace {

TEST(TextReader, SkipsBlankAndCommentLinesAndCountsLines) {
  std::istringstream in("# header\n\n  A 1 2.5\r\n\t# indented comment\nB -3e2\n");
  TextReader r(in, "mem.txt");
  ASSERT_TRUE(r.next_line());
  EXPECT_EQ(r.line_number(), 3);
  EXPECT_EQ(r.num_fields(), 3u);
  EXPECT_EQ(r.integer(1, "a"), 1);
  EXPECT_DOUBLE_EQ(r.number(2, "b"), 2.5);
  ASSERT_TRUE(r.next_line());
  EXPECT_EQ(r.line_number(), 5);
  EXPECT_DOUBLE_EQ(r.number(1, "c"), -300.0);
  EXPECT_FALSE(r.next_line());
}

TEST(TextReader, StrictNumbersNameFileLineAndField) {
  std::istringstream in("X 1.0abc nan 1e999 3.5\n");
  TextReader r(in, "bad.g2o");
  ASSERT_TRUE(r.next_line());
  try {
    r.number(1, "x");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 1);
    EXPECT_EQ(e.field(), "x");
    EXPECT_STREQ(e.what(), "bad.g2o:1: field 'x': not a number: '1.0abc'");
  }
  EXPECT_THROW(r.number(2, "y"), InputError);   // NaN
  EXPECT_THROW(r.number(3, "z"), InputError);   // out of range
  EXPECT_THROW(r.integer(4, "id"), InputError);  // not an integer
  EXPECT_THROW(r.number(9, "w"), InputError);   // missing
  EXPECT_THROW(r.expect_fields(4, "X"), InputError);
}

TEST(TextReader, SplitsOnDelimiter) {
  TextReader::Options o;
  o.delimiter = ',';
  std::istringstream in("1403636579758555392, 1.0 ,2,\n");
  TextReader r(in, "gt.csv", o);
  ASSERT_TRUE(r.next_line());
  ASSERT_EQ(r.num_fields(), 4u);
  EXPECT_EQ(r.integer(0, "t"), 1403636579758555392LL);
  EXPECT_DOUBLE_EQ(r.number(1, "x"), 1.0);
  EXPECT_EQ(r.field(3), "");
}

TEST(TextReader, MissingFileIsAnInputError) {
  EXPECT_THROW(TextReader::open("/nonexistent/file.g2o"), InputError);
}

}  // namespace
}  // namespace slamkit
