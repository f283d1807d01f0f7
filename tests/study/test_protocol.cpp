// Protocol files: the committed thesis protocols parse and carry the published numbers; bad
// files fail with the file, line and key; the quick variant and the hash behave.
#include <gtest/gtest.h>

#include <string>

#include "clearshape/core/error.hpp"
#include "clearshape/study/protocol.hpp"
#include "protocol_fixtures.hpp"
#include "study_paths.hpp"

namespace cs = clearshape;
namespace st = clearshape::study;
using clearshape::testing::studies_path;

namespace {

const char* const kMinimal = clearshape::testing::kMiniProtocol;

std::string error_of(const std::string& text) { return clearshape::testing::protocol_error_of(text); }

}  // namespace

TEST(Protocol, ThesisPositionCarriesThePublishedTables) {
  const st::Protocol p = st::load_protocol(studies_path("thesis-position.toml"));
  EXPECT_EQ(p.mode, cs::rig::CommandMode::position);
  EXPECT_EQ(p.repetitions, 10);
  EXPECT_DOUBLE_EQ(p.record_s, 5.0);
  ASSERT_EQ(p.rig_tests.tables.size(), 5u);
  const auto& b1 = p.table("B.1");
  EXPECT_EQ(b1.input, "step-20");
  ASSERT_GE(b1.columns.size(), 2u);
  EXPECT_EQ(b1.columns[0].key(), "none");
  EXPECT_EQ(b1.columns[1].key(), "zvdd@link-mode");
  EXPECT_DOUBLE_EQ(*b1.columns[0].thesis.mean, 0.303);
  EXPECT_EQ(b1.columns[0].thesis.values.size(), 10u);
  // The published means are the means of the published trials (to the printed rounding).
  for (const auto& t : p.rig_tests.tables) {
    for (const auto& c : t.columns) {
      if (c.thesis.values.empty()) continue;
      double sum = 0.0;
      for (double v : c.thesis.values) sum += v;
      EXPECT_NEAR(sum / 10.0, *c.thesis.mean, 0.0011) << t.id << " " << c.key();
    }
  }
  EXPECT_DOUBLE_EQ(p.identification.thesis.zeta, 0.9968);
  EXPECT_DOUBLE_EQ(p.clearance.thesis_agreement.value_or(0.0), 0.0042);
  EXPECT_DOUBLE_EQ(p.input("step-20").last_move_start_s, 0.5);
  EXPECT_DOUBLE_EQ(p.input("double-step-16").last_move_start_s, 1.0);
  ASSERT_EQ(p.rig_tests.summaries.size(), 2u);
  EXPECT_EQ(p.rig_tests.summaries[1].thesis.size(), 5u);
}

TEST(Protocol, ThesisSpeedCarriesTable51AndEq42) {
  const st::Protocol p = st::load_protocol(studies_path("thesis-speed.toml"));
  EXPECT_EQ(p.mode, cs::rig::CommandMode::speed);
  EXPECT_EQ(p.measure.md_signal, st::MdSignal::link_rate_deg_s);
  const auto& t = p.table("5.1");
  ASSERT_EQ(t.columns.size(), 5u);
  EXPECT_DOUBLE_EQ(*t.columns[0].thesis.mean, 0.392);
  EXPECT_DOUBLE_EQ(*t.columns[3].thesis.mean, 0.191);
  EXPECT_DOUBLE_EQ(p.identification.thesis.kp, 25.47);
  EXPECT_DOUBLE_EQ(p.identification.thesis.tz_s, -0.0398);
  EXPECT_EQ(p.consistency.thesis.size(), 4u);
  EXPECT_DOUBLE_EQ(*p.consistency.thesis.at("prbs").mean, 0.0035);
}

TEST(Protocol, MinimalFileTakesDefaults) {
  const st::Protocol p = st::parse_protocol(kMinimal, "mini.toml");
  EXPECT_EQ(p.name, "mini");
  EXPECT_EQ(p.seed, 1u);
  EXPECT_EQ(p.measure.md_signal, st::MdSignal::link_angle_deg);
  EXPECT_DOUBLE_EQ(p.input("step").signal.value_at(1.0), 10.0);
}

TEST(Protocol, UnknownKeyNamesFileLineAndKey) {
  // Appended after [[input]], the key belongs to that input (TOML), line 10.
  const std::string e = error_of(std::string(kMinimal) + "bogus_key = 3\n");
  EXPECT_NE(e.find("mini.toml:10"), std::string::npos) << e;
  EXPECT_NE(e.find("input[0].bogus_key"), std::string::npos) << e;
  const std::string e0 = error_of("bogus_top = 1\n" + std::string(kMinimal));
  EXPECT_NE(e0.find("mini.toml:1"), std::string::npos) << e0;
  EXPECT_NE(e0.find("bogus_top"), std::string::npos) << e0;
  const std::string e2 = error_of(std::string(kMinimal) + "[measure]\nmd_signal = \"link_angle_deg\"\nbias_s = 1\n");
  EXPECT_NE(e2.find("measure.bias_s"), std::string::npos) << e2;
  EXPECT_NE(e2.find("mini.toml:12"), std::string::npos) << e2;
}

// Issue 11, case 8: a rate or record length that no run accepts was found by the first run, after
// the study had created its folders, and reported without file, line or key.
TEST(Protocol, RunLimitsAreCheckedWhenTheProtocolIsRead) {
  const auto with = [](const std::string& lines) {
    std::string text = kMinimal;
    text.insert(text.find("[[input]]"), lines);
    return text;
  };
  const std::string e = error_of(with("sample_rate_hz = 0.001\n"));
  EXPECT_NE(e.find("mini.toml:5"), std::string::npos) << e;
  EXPECT_NE(e.find("study.sample_rate_hz"), std::string::npos) << e;
  EXPECT_NE(e.find("[1, 100000]"), std::string::npos) << e;
  EXPECT_NE(error_of(with("sample_rate_hz = 1e12\n")).find("study.sample_rate_hz"), std::string::npos);
  const std::string e2 = error_of(with("sample_rate_hz = 100000.0\nrecord_s = 20000.0\n"));
  EXPECT_NE(e2.find("study.record_s"), std::string::npos) << e2;
  EXPECT_NE(e2.find("at most 1e9"), std::string::npos) << e2;
  EXPECT_EQ(error_of(with("sample_rate_hz = 100000.0\nrecord_s = 10000.0\n")), "");  // exactly 1e9: accepted
}

TEST(Protocol, UnitSuffixMustMatchTheMode) {
  std::string text = kMinimal;
  text.replace(text.find("amplitude_deg"), 13, "amplitude_v");
  const std::string e = error_of(text);
  EXPECT_NE(e.find("amplitude_v"), std::string::npos) << e;
  EXPECT_NE(e.find("amplitude_deg"), std::string::npos) << e;  // lists the allowed keys
}

TEST(Protocol, ReferencesAreChecked) {
  const std::string e = error_of(std::string(kMinimal) + "[consistency]\ninputs = [\"nope\"]\n");
  EXPECT_NE(e.find("nope"), std::string::npos) << e;
  const std::string e2 = error_of(std::string(kMinimal) +
                                  "[[rig_tests.table]]\nid = \"T\"\ninput = \"step\"\n[[rig_tests.table.column]]\n"
                                  "shaper = \"zvdd\"\nmode_source = \"elsewhere\"\n");
  EXPECT_NE(e2.find("elsewhere"), std::string::npos) << e2;
  const std::string e3 = error_of(std::string(kMinimal) + "[simulation]\nshapers = [\"zzz\"]\n");
  EXPECT_NE(e3.find("zzz"), std::string::npos) << e3;
}

TEST(Protocol, MoveBeforeTheBiasWindowIsRejected) {
  std::string text = kMinimal;
  text.replace(text.find("start_s = 0.5"), 13, "start_s = 0.1");
  EXPECT_NE(error_of(text).find("bias"), std::string::npos);
}

TEST(Protocol, WrongTypesAndFormat) {
  std::string text = kMinimal;
  text.replace(text.find("amplitude_deg = 10.0"), 20, "amplitude_deg = \"ten\"");
  EXPECT_FALSE(error_of(text).empty());
  std::string text2 = kMinimal;
  text2.replace(text2.find("protocol/1"), 10, "protocol/9");
  EXPECT_NE(error_of(text2).find("format"), std::string::npos);
  EXPECT_NE(error_of("format = \"clearshape-study-protocol/1\"\n[study\n").find("mini.toml"), std::string::npos);
  EXPECT_THROW(st::load_protocol("/nonexistent/protocol.toml"), cs::InputError);
}

TEST(Protocol, QuickVariantReducesAndHashTracksContent) {
  const st::Protocol p = st::load_protocol(studies_path("thesis-position.toml"));
  const st::Protocol q = st::quick_variant(p);
  EXPECT_TRUE(q.quick);
  EXPECT_EQ(q.repetitions, p.quick_reduction.repetitions);
  EXPECT_LT(q.record_s, p.record_s);
  EXPECT_LE(q.clearance.max_evaluations, p.quick_reduction.clearance_max_evaluations);
  EXPECT_EQ(st::protocol_hash(p, "sim"), st::protocol_hash(p, "sim"));
  EXPECT_NE(st::protocol_hash(p, "sim"), st::protocol_hash(q, "sim"));
  EXPECT_NE(st::protocol_hash(p, "sim"), st::protocol_hash(p, "another rig"));
  st::Protocol p2 = p;
  p2.seed += 1;
  EXPECT_NE(st::protocol_hash(p, "sim"), st::protocol_hash(p2, "sim"));
  EXPECT_EQ(st::protocol_hash(p, "sim").size(), 16u);
}
