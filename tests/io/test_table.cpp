#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "clearshape/core/error.hpp"
#include "clearshape/io/atomic_file.hpp"
#include "clearshape/io/json.hpp"
#include "clearshape/io/table.hpp"
#include "support/paths.hpp"

namespace cs = clearshape;
namespace io = clearshape::io;

TEST(Table, ParsesHeaderAndCommas) {
  const auto t = io::parse_table("time_s,command_deg\n0,1\n0.001,2.5\n", "x.csv");
  EXPECT_TRUE(t.had_header);
  ASSERT_EQ(t.rows(), 2u);
  EXPECT_EQ(t.column("command_deg")[1], 2.5);
  EXPECT_EQ(t.column("2")[0], 1.0);  // 1-based index
}

TEST(Table, ParsesWhitespaceWithoutHeader) {
  const auto t = io::parse_table("  2.2e-01\t -1.7e-01\t\n 3.9e-02  -1.1e-01 \n", "a.dat");
  EXPECT_FALSE(t.had_header);
  ASSERT_EQ(t.columns.size(), 2u);
  EXPECT_EQ(t.names[1], "col2");
  EXPECT_DOUBLE_EQ(t.column("col2")[1], -1.1e-01);
}

TEST(Table, ErrorsNameFileLineAndField) {
  try {
    io::parse_table("t,y\n0,1\n1,abc\n", "bad.csv");
    FAIL();
  } catch (const cs::InputError& e) {
    EXPECT_EQ(e.line(), 3u);
    EXPECT_EQ(e.field(), "y");
    EXPECT_NE(std::string(e.what()).find("bad.csv:3"), std::string::npos);
  }
  EXPECT_THROW(io::parse_table("t,y\n0,1\n1\n", "ragged.csv"), cs::InputError);
  EXPECT_THROW(io::parse_table("t,y\n0,nan\n", "nan.csv"), cs::InputError);
  EXPECT_THROW(io::parse_table("t,y\n", "empty.csv"), cs::InputError);
  EXPECT_THROW(io::parse_table("", "empty.csv"), cs::InputError);
  const auto t = io::parse_table("t,y\n0,1\n", "x.csv");
  EXPECT_THROW((void)t.column("z"), cs::InputError);
}

TEST(Table, UniformTimeIsChecked) {
  const auto ok = io::parse_table("t,y\n0,1\n0.001,2\n0.002,3\n", "ok.csv");
  EXPECT_NEAR(io::uniform_sample_time(ok, "t"), 0.001, 1e-15);
  const auto s = io::series_from_table(ok, "t", "y");
  EXPECT_EQ(s.values.size(), 3u);
  const auto unsorted = io::parse_table("t,y\n0,1\n0.002,2\n0.001,3\n", "u.csv");
  try {
    (void)io::uniform_sample_time(unsorted, "t");
    FAIL();
  } catch (const cs::InputError& e) {
    EXPECT_EQ(e.line(), 4u);
  }
  const auto irregular = io::parse_table("t,y\n0,1\n0.001,2\n0.003,3\n0.004,3\n", "i.csv");
  EXPECT_THROW((void)io::uniform_sample_time(irregular, "t"), cs::InputError);
}

TEST(Table, CsvRoundTripsExactly) {
  const std::vector<double> t{0.0, 0.1, 1.0 / 3.0};
  const std::vector<double> y{-1e-300, 2.5, 123456789.123456789};
  const std::string text = io::format_csv({"time_s", "y_deg"}, {&t, &y});
  const auto back = io::parse_table(text, "mem");
  EXPECT_EQ(back.column("time_s"), t);
  EXPECT_EQ(back.column("y_deg"), y);
}

TEST(AtomicFile, WritesAndReplacesWithoutLeavingTemporaries) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / "clearshape_atomic_test";
  fs::remove_all(dir);
  const fs::path file = dir / "sub" / "out.json";
  io::write_json(file, io::make_document());
  io::write_text_atomic(file, "second\n");
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "second");
  std::size_t entries = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(file.parent_path())) ++entries;
  EXPECT_EQ(entries, 1u);
  fs::remove_all(dir);
}

TEST(Table, ReadsTheDaisyRobotArmData) {
  const auto path = clearshape::testing::shared_path("data/daisy_robot_arm.dat");
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "third-party data absent: " << path;
  const auto t = io::read_table(path);
  EXPECT_EQ(t.rows(), 1024u);
  EXPECT_EQ(t.columns.size(), 2u);
}
