// A recording with a unit mistake is refused with the file, the column and the likely fix
// (study/recording_checks.hpp, docs/recordings.md "Unit mistakes the reader catches"): the link's
// travel against the motor's, the gyroscope's full scale and a time column in ms.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <initializer_list>
#include <string>

#include <fmt/format.h>

#include "support/paths.hpp"
#include "clearshape/core/error.hpp"
#include "clearshape/core/units.hpp"
#include "clearshape/study/protocol.hpp"
#include "clearshape/study/recordings.hpp"
#include "clearshape/study/run_source.hpp"

namespace st = clearshape::study;
using clearshape::InputError;

namespace {

constexpr double kRecordS = 1.0;
constexpr double kRad = 180.0 / clearshape::kPi;

// A 10° smooth step of the motor between 0.2 s and 0.4 s, the link following it (the rate is the
// motor angle's exact derivative): `link_scale` and `motor_scale` multiply the written columns,
// `time_scale` the time column; `spike_row` puts `spike` deg/s in the link column there.
struct Writer {
  double link_scale = 1.0;
  double link_offset = 0.0;  ///< deg/s added to every link rate (a gyro's zero-rate offset)
  double motor_scale = 1.0;
  double time_scale = 1.0;
  std::size_t spike_row = 0;
  double spike = 0.0;
  std::string write(const std::filesystem::path& path) const {
    std::ofstream out(path);
    out << "time_s,command_deg,motor_angle_deg,link_rate_deg_s\n";  // the command steps at 0.2 s
    for (std::size_t k = 0; k < 1200; ++k) {
      const double t = 1e-3 * static_cast<double>(k);
      const double u = std::clamp((t - 0.2) / 0.2, 0.0, 1.0);
      const double angle = 10.0 * 0.5 * (1.0 - std::cos(clearshape::kPi * u));
      const double rate = (u > 0.0 && u < 1.0) ? 10.0 * 0.5 * clearshape::kPi / 0.2 * std::sin(clearshape::kPi * u) : 0.0;
      out << fmt::format("{},{},{},{}\n", t * time_scale, t >= 0.2 ? 10.0 : 0.0, angle * motor_scale,
                         k == spike_row && spike != 0.0 ? spike : rate * link_scale + link_offset);
    }
    return path.string();
  }
};

st::RecordingEntry entry(const std::filesystem::path& file) {
  st::RecordingEntry e;
  e.id = "unshaped/step/r01";
  e.file = file;
  e.columns.time = "time_s";
  e.columns.command = "command_deg";
  e.columns.command_unit = "deg";
  return e;
}

const st::Protocol& protocol() {
  // The thesis's position protocol (1 kHz); read_recording cuts each record to kRecordS.
  static const st::Protocol p = st::load_protocol(clearshape::testing::studies_path("thesis-position.toml"));
  return p;
}

// The InputError of reading `e` (fails the test when there is none).
InputError read_error(const st::RecordingEntry& e) {
  try {
    (void)st::read_recording(e, protocol(), kRecordS);
  } catch (const InputError& err) {
    return err;
  }
  ADD_FAILURE() << "read_recording accepted " << e.file;
  return InputError("", 0, "", "");
}

std::filesystem::path dir();

// A recording written by a Writer that `edit` changed, as dir()/name.
std::filesystem::path written(const std::string& name, const std::function<void(Writer&)>& edit) {
  Writer w;
  edit(w);
  const auto f = dir() / name;
  w.write(f);
  return f;
}

// Reading `e` is refused naming `field`, with every one of `parts` in the message.
void expect_refused(const st::RecordingEntry& e, const std::string& field, std::initializer_list<std::string> parts) {
  const InputError err = read_error(e);
  EXPECT_EQ(err.field(), field) << err.what();
  for (const auto& part : parts) EXPECT_NE(std::string(err.what()).find(part), std::string::npos) << err.what();
}

std::filesystem::path dir() {
  static const auto d = clearshape::testing::fresh_temp_dir("clearshape_recording_units");
  return d;
}

}  // namespace

TEST(RecordingUnits, AConsistentRecordingReads) {
  const auto f = dir() / "good.csv";
  Writer{}.write(f);
  const st::Record r = st::read_recording(entry(f), protocol(), kRecordS);
  ASSERT_EQ(r.time_s.size(), 1001u);  // 1 s at 1 kHz, both ends
  EXPECT_NEAR(r.motor_angle_deg.back(), 10.0, 1e-12);
  // Declared in rad/s and in rad, both columns in radians: consistent, read.
  const auto g = dir() / "rad.csv";
  Writer w;
  w.link_scale = 1.0 / kRad;
  w.motor_scale = 1.0 / kRad;
  w.write(g);
  auto e = entry(g);
  e.columns.link_rate_unit = "rad/s";
  e.columns.motor_angle_unit = "rad";
  EXPECT_NEAR(st::read_recording(e, protocol(), kRecordS).motor_angle_deg.back(), 10.0, 1e-9);
}

TEST(RecordingUnits, GyroInDegPerSecondDeclaredRadPerSecondIsRefused) {
  // The audit's case: the gyro column in deg/s, the manifest says rad/s — the link "travels" 573°
  // for the motor's 10°. Through a manifest, as a user meets it.
  const auto d = dir() / "audit";
  std::filesystem::create_directories(d);
  Writer{}.write(d / "step-1.csv");
  const std::string id = st::distinct_runs(protocol()).front().id;
  std::ofstream(d / "manifest.toml") << "format = \"clearshape-recordings/1\"\n[columns]\ntime = \"time_s\"\n"
                                        "link_rate_unit = \"rad/s\"\n[[run]]\nid = \"" << id << "\"\n"
                                        "file = \"step-1.csv\"\n";
  const st::RecordingsManifest m = st::load_recordings_manifest(d, protocol());
  expect_refused(m.runs.at(id), "link_rate_deg_s",
                 {"step-1.csv", "declared rad/s, looks like deg/s", "link_rate_unit = \"deg/s\""});
}

TEST(RecordingUnits, GyroInRadPerSecondDeclaredDegPerSecondIsRefused) {
  const auto f = written("gyro-rad.csv", [](Writer& w) { w.link_scale = 1.0 / kRad; });
  expect_refused(entry(f), "link_rate_deg_s", {"declared deg/s, looks like rad/s"});
}

TEST(RecordingUnits, MotorInRadiansDeclaredDegreesIsRefused) {
  const auto f = written("motor-rad.csv", [](Writer& w) { w.motor_scale = 1.0 / kRad; });
  expect_refused(entry(f), "motor_angle_deg", {"declared deg, looks like rad", "motor_angle_unit = \"rad\""});
}

TEST(RecordingUnits, LinkTravelFarFromMotorTravelIsRefused) {
  // Not a deg/rad factor: the link rate 3× the motor's (another axis, a wrong scale) — 30° for
  // 10°, more than a play of a few degrees explains.
  const auto f = dir() / "times3.csv";
  Writer w;
  w.link_scale = 3.0;
  w.write(f);
  expect_refused(entry(f), "link_rate_deg_s", {"ratio 3", "allowed: within 10°"});
  // 1.4× (the link 4° beyond the motor's 10°) is what a few degrees of play can do: read.
  const auto g = dir() / "times1_4.csv";
  w.link_scale = 1.4;
  w.write(g);
  EXPECT_NO_THROW((void)st::read_recording(entry(g), protocol(), kRecordS));
}

TEST(RecordingUnits, RawGyroWordsDeclaredDegPerSecondAreRefused) {
  // The gyro's words (14.375 LSB per °/s) in a column declared deg/s, and deg/s declared lsb.
  const auto f = written("lsb.csv", [](Writer& w) { w.link_scale = 14.375; });
  expect_refused(entry(f), "link_rate_deg_s", {"looks like the gyro's raw words", "link_rate_unit = \"lsb\""});
  auto as_lsb = entry(f);
  as_lsb.columns.link_rate_unit = "lsb";
  EXPECT_NO_THROW((void)st::read_recording(as_lsb, protocol(), kRecordS));
  const auto g = dir() / "degs-as-lsb.csv";
  Writer{}.write(g);
  auto wrong = entry(g);
  wrong.columns.link_rate_unit = "lsb";
  EXPECT_NE(std::string(read_error(wrong).what()).find("declared lsb, looks like deg/s"), std::string::npos);
}

TEST(RecordingUnits, TheGyroRestOffsetIsNotTravel) {
  // A 6 deg/s zero-rate offset would integrate to 6° over the 1 s record (16° for the motor's
  // 10°, beyond 10° + 25 %); measured before the command moves and removed, as the study does.
  const auto f = written("offset.csv", [](Writer& w) { w.link_offset = 6.0; });
  EXPECT_NO_THROW((void)st::read_recording(entry(f), protocol(), kRecordS));
  // Declared rad/s with the same offset in deg/s: still the deg/rad factor.
  auto e = entry(f);
  e.columns.link_rate_unit = "rad/s";
  EXPECT_NE(std::string(read_error(e).what()).find("declared rad/s, looks like deg/s"), std::string::npos);
}

TEST(RecordingUnits, RateBeyondTheGyroFullScaleIsRefusedWithItsLine) {
  const auto f = dir() / "spike.csv";
  Writer w;
  w.spike_row = 300;
  w.spike = 2500.0;
  w.write(f);
  const InputError e = read_error(entry(f));
  EXPECT_EQ(e.field(), "link_rate_deg_s");
  EXPECT_EQ(e.line(), 302u);  // the header is line 1, row 0 line 2
  EXPECT_NE(std::string(e.what()).find("±2000 deg/s"), std::string::npos) << e.what();
  // At the full scale (a saturated sample) it reads; a manifest's own full scale counts.
  w.spike = -2000.0;
  w.write(f);
  EXPECT_NO_THROW((void)st::read_recording(entry(f), protocol(), kRecordS));
  auto narrow = entry(f);
  narrow.columns.gyro_full_scale_deg_s = 250.0;
  const InputError n = read_error(narrow);
  EXPECT_EQ(n.line(), 302u);
  EXPECT_NE(std::string(n.what()).find("±250 deg/s"), std::string::npos) << n.what();
}

TEST(RecordingUnits, TimeInMillisecondsGetsTheHint) {
  const auto f = written("ms.csv", [](Writer& w) { w.time_scale = 1e3; });
  expect_refused(entry(f), "time_s", {"declared s, looks like ms", "time_unit = \"ms\""});
  // With time_unit = "ms" the same file reads, its time in seconds.
  auto ms = entry(f);
  ms.columns.time_unit = "ms";
  const st::Record r = st::read_recording(ms, protocol(), kRecordS);
  EXPECT_NEAR(r.time_s.back(), 1.0, 1e-12);
}
