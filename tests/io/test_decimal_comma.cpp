// A CSV written with decimal commas ("0,125" with ';' between the fields, as a German or French
// spreadsheet exports it) is refused with that hint, not read with its numbers split in two nor
// with a bare "expected 2 columns, found 4" (io/table.cpp, docs/recordings.md).
#include <gtest/gtest.h>

#include <string>

#include "clearshape/core/error.hpp"
#include "clearshape/io/table.hpp"

namespace io = clearshape::io;
using clearshape::InputError;

namespace {

InputError parse_error(const std::string& text) {
  try {
    (void)io::parse_table(text, "axis.csv");
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "parsed: " << text;
  return InputError("", 0, "", "");
}

}  // namespace

TEST(DecimalComma, SemicolonSeparatedDecimalCommasGetTheHint) {
  const InputError e = parse_error("time_s;link_rate_deg_s\n0;0\n0,001;1,25\n");
  EXPECT_EQ(e.line(), 3u);
  EXPECT_EQ(e.field(), "time_s");
  EXPECT_EQ(parse_error("time_s;link_rate_deg_s\n0;1,25\n").field(), "link_rate_deg_s");
  EXPECT_NE(std::string(e.what()).find("axis.csv"), std::string::npos) << e.what();
  EXPECT_NE(std::string(e.what()).find("'0,001' uses a decimal comma"), std::string::npos) << e.what();
  EXPECT_NE(std::string(e.what()).find("decimal points"), std::string::npos) << e.what();
}

TEST(DecimalComma, HeaderlessFileIsNotReadWithTwiceItsColumns) {
  // Without a header every line splits the same way: today this would read as 4 columns.
  const InputError e = parse_error("0,000;0,5\n0,001;0,75\n");
  EXPECT_EQ(e.line(), 1u);
  EXPECT_EQ(e.field(), "column 1");
  EXPECT_NE(std::string(e.what()).find("'0,000' uses a decimal comma"), std::string::npos) << e.what();
}

TEST(DecimalComma, CommaSeparatedFieldCountMismatchNamesTheLikelyCause) {
  const InputError e = parse_error("time_s,link_rate_deg_s\n0,0\n0,001,1,25\n");
  EXPECT_EQ(e.line(), 3u);
  EXPECT_NE(std::string(e.what()).find("expected 2 columns, found 4"), std::string::npos) << e.what();
  EXPECT_NE(std::string(e.what()).find("decimal comma (0,125)"), std::string::npos) << e.what();
}

TEST(DecimalComma, SemicolonsWithDecimalPointsStillRead) {
  const io::Table t = io::parse_table("time_s;x\n0;0.5\n0.001;1.25\n", "ok.csv");
  ASSERT_EQ(t.rows(), 2u);
  EXPECT_DOUBLE_EQ(t.column("x")[1], 1.25);
  // A ragged row with fewer fields is the plain count error, no decimal-comma hint.
  const InputError e = parse_error("a,b,c\n1,2,3\n1,2\n");
  EXPECT_EQ(std::string(e.what()).find("decimal comma"), std::string::npos) << e.what();
}
