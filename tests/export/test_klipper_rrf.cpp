// --export klipper / rrf: the lines follow the documented syntax (Klipper's Config_Reference
// [input_shaper]; RRF's M593), the firmware's own shaper built from the printed numbers matches
// the design, and what a firmware lacks is refused with what to use instead.
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "clearshape/core/error.hpp"
#include "clearshape/export/firmware_shapers.hpp"
#include "clearshape/export/klipper.hpp"
#include "clearshape/export/numbers.hpp"
#include "clearshape/export/rrf.hpp"
#include "clearshape/shaping/design.hpp"

namespace ex = clearshape::exports;
namespace sh = clearshape::shaping;

namespace {

ex::ShaperDesign design(sh::Method m, double f_hz, double zeta, std::optional<double> vtol = std::nullopt) {
  sh::DesignRequest r;
  r.method = m;
  r.mode = sh::Mode::from_hz(f_hz, zeta);
  if (vtol) r.vtol = *vtol;
  ex::ShaperDesign d{sh::design(r), m, r.mode, std::nullopt, std::nullopt, std::nullopt, ""};
  if (m == sh::Method::ei || m == sh::Method::ei2 || m == sh::Method::ei3) d.vtol = r.vtol;
  return d;
}

std::vector<std::string> setting_lines(const std::string& text, char comment) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    if (!line.empty() && line[0] != comment) out.push_back(line);
  }
  return out;
}

std::string error_of(const ex::ShaperDesign& d, ex::Format f) {
  try {
    ex::export_shaper(d, f, {});
  } catch (const clearshape::InvalidArgument& e) {
    return e.what();
  }
  return "";
}

const std::string kNumber = R"(-?[0-9]+(\.[0-9]+)?)";  // fixed notation, no exponent

}  // namespace

TEST(KlipperExport, SectionForEachTypeKlipperHas) {
  const std::regex type_line("shaper_type_([xy]): (zv|mzv|zvd|ei|2hump_ei|3hump_ei)");
  const std::regex freq_line("shaper_freq_([xy]): " + kNumber);
  const std::regex damping_line("damping_ratio_([xy]): " + kNumber);
  const std::vector<std::pair<sh::Method, std::string>> cases{{sh::Method::zv, "zv"},   {sh::Method::mzv, "mzv"},
                                                              {sh::Method::zvd, "zvd"}, {sh::Method::ei, "ei"},
                                                              {sh::Method::ei2, "2hump_ei"}, {sh::Method::ei3, "3hump_ei"}};
  for (const auto& [method, type] : cases) {
    const ex::ExportText out = ex::to_klipper(design(method, 14.955, 0.1), {});
    const auto lines = setting_lines(out.text, '#');
    ASSERT_EQ(lines.size(), 7u) << out.text;
    EXPECT_EQ(lines[0], "[input_shaper]");
    for (std::size_t i = 1; i < 7; i += 3) {
      EXPECT_TRUE(std::regex_match(lines[i], type_line)) << lines[i];
      EXPECT_TRUE(std::regex_match(lines[i + 1], freq_line)) << lines[i + 1];
      EXPECT_TRUE(std::regex_match(lines[i + 2], damping_line)) << lines[i + 2];
    }
    EXPECT_EQ(lines[1], "shaper_type_x: " + type);
    EXPECT_EQ(lines[2], "shaper_freq_x: 14.955");  // 6 significant digits, no 2π noise
    EXPECT_EQ(lines[3], "damping_ratio_x: 0.1");
    EXPECT_EQ(lines[4], "shaper_type_y: " + type);
  }
  ex::ExportOptions only_y;
  only_y.klipper_axes = "y";
  const auto lines = setting_lines(ex::to_klipper(design(sh::Method::zvd, 40.0, 0.05), only_y).text, '#');
  EXPECT_EQ(lines, (std::vector<std::string>{"[input_shaper]", "shaper_type_y: zvd", "shaper_freq_y: 40", "damping_ratio_y: 0.05"}));
}

TEST(KlipperExport, RefusesWhatKlipperLacks) {
  EXPECT_NE(error_of(design(sh::Method::zvdd, 40, 0.1), ex::Format::klipper).find("Klipper has no zvdd shaper"), std::string::npos);
  EXPECT_NE(error_of(design(sh::Method::zvdd, 40, 0.1), ex::Format::klipper).find("use zvd"), std::string::npos);
  EXPECT_NE(error_of(design(sh::Method::um_zv, 40, 0.1), ex::Format::klipper).find("zv or mzv"), std::string::npos);
  // Klipper's EI is the 5 % design only.
  EXPECT_NE(error_of(design(sh::Method::ei, 40, 0.1, 0.02), ex::Format::klipper).find("fixes the tolerable vibration at 5 %"),
            std::string::npos);
  // Beyond its fit's damping range, Klipper's 3hump_ei is not our EI3: refused with the difference.
  const std::string far = error_of(design(sh::Method::ei3, 40, 0.2), ex::Format::klipper);
  EXPECT_NE(far.find("differs from the designed ei3"), std::string::npos) << far;
  ex::ShaperDesign two = design(sh::Method::zv, 40, 0.1);
  two.second_mode = sh::Mode::from_hz(90, 0.05);
  EXPECT_NE(error_of(two, ex::Format::klipper).find("one mode per axis"), std::string::npos);
  ex::ExportOptions bad_axis;
  bad_axis.klipper_axes = "z";
  EXPECT_THROW(ex::to_klipper(design(sh::Method::zv, 40, 0.1), bad_axis), clearshape::InvalidArgument);
}

TEST(RrfExport, NamedTypeWhenRrfBuildsTheSameShaper) {
  const std::regex named(R"re(M593 P"(zvd|zvdd|zvddd|mzv|ei2|ei3)" F)re" + kNumber + " S" + kNumber);
  for (sh::Method m : {sh::Method::zvd, sh::Method::zvdd, sh::Method::zvddd, sh::Method::ei2, sh::Method::ei3}) {
    const auto lines = setting_lines(ex::to_rrf(design(m, 40.5, 0.1), {}).text, ';');
    ASSERT_EQ(lines.size(), 1u);
    EXPECT_TRUE(std::regex_match(lines[0], named)) << lines[0];
  }
  EXPECT_EQ(setting_lines(ex::to_rrf(design(sh::Method::zvd, 40.5, 0.1), {}).text, ';')[0], "M593 P\"zvd\" F40.5 S0.1");
  // Undamped MZV: RRF's reversed amplitudes are the same shaper.
  EXPECT_EQ(setting_lines(ex::to_rrf(design(sh::Method::mzv, 40.5, 0.0), {}).text, ';')[0], "M593 P\"mzv\" F40.5 S0");
}

TEST(RrfExport, CustomFormCarriesTheDesignItself) {
  const std::regex custom(R"re(M593 P"custom" H)re" + kNumber + "(:" + kNumber + ")* T" + kNumber + "(:" + kNumber + ")*");
  // zv and ei have no RRF type; RRF's MZV at ζ > 0 is reversed; a 2-mode shaper is one shaper.
  ex::ShaperDesign two = design(sh::Method::zv, 40, 0.1);
  two.shaper = sh::convolve(two.shaper, sh::design_zv(sh::Mode::from_hz(90, 0.05)));
  two.second_mode = sh::Mode::from_hz(90, 0.05);
  for (const ex::ShaperDesign& d : {design(sh::Method::zv, 40, 0.1), design(sh::Method::ei, 40, 0.1),
                                     design(sh::Method::mzv, 40, 0.1), two}) {
    const ex::ExportText out = ex::to_rrf(d, {});
    const auto lines = setting_lines(out.text, ';');
    ASSERT_EQ(lines.size(), 1u);
    EXPECT_TRUE(std::regex_match(lines[0], custom)) << lines[0];
    ASSERT_EQ(out.notes.size(), 1u);
    // Parse H and T back and rebuild the shaper RRF runs: the design to 6 significant digits
    // (each duration within 5e-6 of itself, so every time within 5e-6 of the duration).
    std::smatch m;
    ASSERT_TRUE(std::regex_search(lines[0], m, std::regex(R"(H([^ ]+) T([^ ]+))")));
    auto split = [](const std::string& s) {
      std::vector<double> v;
      std::istringstream in(s);
      for (std::string x; std::getline(in, x, ':');) v.push_back(std::stod(x));
      return v;
    };
    const sh::Shaper theirs = ex::rrf_custom_shaper(split(m[1]), split(m[2]));
    ASSERT_EQ(theirs.size(), d.shaper.size());
    for (std::size_t i = 0; i < theirs.size(); ++i) {
      EXPECT_NEAR(theirs.impulses()[i].time_s, d.shaper.impulses()[i].time_s, 5e-6 * d.shaper.duration_s());
      EXPECT_NEAR(theirs.impulses()[i].amplitude, d.shaper.impulses()[i].amplitude, 2e-6);
    }
  }
  EXPECT_NE(ex::to_rrf(design(sh::Method::mzv, 40, 0.1), {}).notes[0].find("differs from the design"), std::string::npos);
}

TEST(RrfExport, RefusesNegativeAndLongShapers) {
  EXPECT_NE(error_of(design(sh::Method::um_zv, 40, 0.1), ex::Format::rrf).find("negative impulses"), std::string::npos);
  ex::ShaperDesign long_one = design(sh::Method::zvd, 40, 0.1);
  long_one.shaper = sh::convolve(long_one.shaper, sh::design_zvd(sh::Mode::from_hz(95, 0.1)));
  long_one.second_mode = sh::Mode::from_hz(95, 0.1);
  EXPECT_NE(error_of(long_one, ex::Format::rrf).find("at most 5"), std::string::npos);
  // Below RRF's lowest F for named types (the thesis's 3.3 Hz link mode): the custom form.
  const ex::ExportText low = ex::to_rrf(design(sh::Method::zvd, 3.32, 0.288), {});
  EXPECT_NE(low.text.find("P\"custom\""), std::string::npos);
  EXPECT_NE(low.notes[0].find("outside RRF's range"), std::string::npos);
}
