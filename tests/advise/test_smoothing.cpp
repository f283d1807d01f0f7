// advise::smoothing_mm / max_accel_mm_s2 against Klipper's own functions run unchanged
// (tests/golden/gen_smoothing.py → smoothing_klipper.csv: _get_shaper_smoothing and
// find_shaper_max_accel of Klipper 84104bb on its ZV, MZV, EI, 2HUMP_EI and 3HUMP_EI shapers).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "clearshape/advise/smoothing.hpp"
#include "clearshape/core/error.hpp"
#include "clearshape/shaping/design.hpp"
#include "support/paths.hpp"

namespace ad = clearshape::advise;
namespace sh = clearshape::shaping;

namespace {

std::vector<std::string> split(const std::string& text, char sep) {
  std::vector<std::string> out;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, sep);) out.push_back(item);
  return out;
}

struct Row {
  std::string name;
  double frequency_hz = 0.0, damping_ratio = 0.0;
  sh::Shaper shaper{"none", {{0.0, 1.0}}};
  std::vector<double> smoothing_mm, max_accel_mm_s2;
};

std::vector<Row> golden() {
  std::ifstream in(clearshape::testing::golden_path("smoothing_klipper.csv"));
  std::string line;
  std::getline(in, line);
  std::vector<Row> rows;
  while (std::getline(in, line)) {
    const auto f = split(line, ',');
    Row r;
    r.name = f.at(0);
    r.frequency_hz = std::stod(f.at(1));
    r.damping_ratio = std::stod(f.at(2));
    const auto a = split(f.at(3), ';'), t = split(f.at(4), ';');
    std::vector<sh::Impulse> impulses;
    for (std::size_t i = 0; i < a.size(); ++i) impulses.push_back({std::stod(t.at(i)), std::stod(a[i])});
    r.shaper = sh::Shaper("klipper-" + r.name, impulses, sh::Shaper::Normalize::no);  // Klipper's raw amplitudes
    for (std::size_t k = 5; k < 8; ++k) r.smoothing_mm.push_back(std::stod(f.at(k)));
    for (std::size_t k = 8; k < 11; ++k) r.max_accel_mm_s2.push_back(std::stod(f.at(k)));
    rows.push_back(std::move(r));
  }
  return rows;
}

void expect_relative(double got, double want, double tol, const std::string& what) {
  EXPECT_LE(std::abs(got - want), tol * std::abs(want)) << what << ": " << got << " vs Klipper " << want;
}

const double kAccel[3] = {5000.0, 2000.0, 10000.0}, kScv[3] = {5.0, 0.0, 10.0};

}  // namespace

TEST(Smoothing, EqualsKlippersOwnFunctions) {
  const auto rows = golden();
  ASSERT_EQ(rows.size(), 40u);
  for (const auto& r : rows) {
    const std::string id = r.name + " " + std::to_string(r.frequency_hz) + " Hz ζ " + std::to_string(r.damping_ratio);
    for (int k = 0; k < 3; ++k) {
      expect_relative(ad::smoothing_mm(r.shaper, kAccel[k], kScv[k]), r.smoothing_mm[k], 1e-12, id + " smoothing");
      // Klipper bisects to 1e-8 mm/s²; ours is the exact root of the linear offsets.
      expect_relative(ad::max_accel_mm_s2(r.shaper, kScv[k]), r.max_accel_mm_s2[k], 1e-9, id + " max_accel");
    }
  }
}

TEST(Smoothing, ClearshapesZvAndMzvDesignsGiveKlippersFigures) {
  // clearshape's ZV and MZV are the same closed forms as Klipper's (docs/recommend.md).
  int compared = 0;
  for (const auto& r : golden()) {
    if (r.name != "zv" && r.name != "mzv") continue;
    sh::DesignRequest q;
    q.method = sh::method_from_string(r.name);
    q.mode = sh::Mode::from_hz(r.frequency_hz, r.damping_ratio);
    const sh::Shaper ours = sh::design(q);
    expect_relative(ad::smoothing_mm(ours), r.smoothing_mm[0], 1e-9, r.name + " design smoothing");
    expect_relative(ad::max_accel_mm_s2(ours), r.max_accel_mm_s2[0], 1e-9, r.name + " design max_accel");
    ++compared;
  }
  EXPECT_EQ(compared, 20);
}

TEST(Smoothing, LongerShaperSmoothsMoreAndScoreFollowsKlipper) {
  const sh::Shaper one("identity", {{0.0, 1.0}});
  EXPECT_EQ(ad::smoothing_mm(one), 0.0);
  EXPECT_TRUE(std::isinf(ad::max_accel_mm_s2(one)));
  // The score of a shaper leaving v: smoothing·(v^1.5 + 0.2 v + 0.01) (Klipper's fit_shaper).
  EXPECT_DOUBLE_EQ(ad::klipper_score(0.1, 0.04), 0.1 * (0.008 + 0.008 + 0.01));
  // A corner velocity so high that the 90° offset exceeds the target at any acceleration.
  const sh::Shaper zv("zv", {{0.0, 0.5}, {0.05, 0.5}});
  EXPECT_EQ(ad::max_accel_mm_s2(zv, 100.0), 0.0);
  EXPECT_THROW((void)ad::smoothing_mm(zv, -1.0), clearshape::InvalidArgument);
  EXPECT_THROW((void)ad::max_accel_mm_s2(zv, 5.0, 0.0), clearshape::InvalidArgument);
}
