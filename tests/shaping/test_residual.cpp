// Residual vibration V(ω, ζ) (Eq. 2.19), sensitivity curves and insensitivity bands against
// closed forms and the reference note's tables ((c1), (c3), (c4)).
#include <chrono>
#include <cmath>
#include <complex>
#include <numbers>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "clearshape/core/error.hpp"
#include "clearshape/shaping/design.hpp"
#include "clearshape/shaping/residual.hpp"

namespace cs = clearshape::shaping;

namespace {

const cs::Mode k10Hz0 = cs::Mode::from_hz(10.0, 0.0);
const cs::Mode k10Hz1 = cs::Mode::from_hz(10.0, 0.1);

double v_at(const cs::Shaper& s, const cs::Mode& design, double r, double actual_zeta) {
  return cs::residual_vibration(s, cs::Mode{r * design.natural_frequency_rad_s, actual_zeta});
}

// Singhose's damped EI curve fit (as published in Klipper's shaper_defs.py and Vaughan's
// InputShaping.py) — the shaper behind the "EI (fit)" rows of the reference tables.
cs::Shaper fitted_ei(double f_hz, double zeta, double v) {
  const double a1 = 0.24968 + 0.24961 * v + (0.80008 + 1.23328 * v) * zeta + (0.49599 + 3.17316 * v) * zeta * zeta;
  const double a3 = 0.25149 + 0.21474 * v + (-0.83249 + 1.41498 * v) * zeta + (0.85181 - 4.90094 * v) * zeta * zeta;
  const double td = 1.0 / (f_hz * std::sqrt(1 - zeta * zeta));
  const double t2 = (0.4999 + (0.46159 * v + 8.57843 * v * v) * zeta + (4.26169 * v - 108.644 * v * v) * zeta * zeta +
                     (1.75601 * v + 336.989 * v * v) * zeta * zeta * zeta) * td;
  return cs::Shaper("ei-fit", {{0, a1}, {t2, 1 - a1 - a3}, {td, a3}}, cs::Shaper::Normalize::no);
}

}  // namespace

TEST(Residual, ThesisEquationDirectly) {
  // Eq. 2.19 as printed (growing exponentials), for an arbitrary impulse set and mode.
  const cs::Shaper s("x", {{0.0, 0.3}, {0.021, 0.5}, {0.047, -0.1}, {0.06, 0.3}}, cs::Shaper::Normalize::no);
  for (double w : {5.0, 40.0, 130.0}) {
    for (double zeta : {0.0, 0.07, 0.4}) {
      const double wd = w * std::sqrt(1 - zeta * zeta);
      double c = 0;
      double sn = 0;
      for (const auto& p : s.impulses()) {
        c += p.amplitude * std::exp(zeta * w * p.time_s) * std::cos(wd * p.time_s);
        sn += p.amplitude * std::exp(zeta * w * p.time_s) * std::sin(wd * p.time_s);
      }
      const double expected = std::exp(-zeta * w * 0.06) * std::sqrt(c * c + sn * sn) / 1.0;  // ΣA = 1
      EXPECT_NEAR(cs::residual_vibration(s, cs::Mode{w, zeta}), expected, 1e-14);
    }
  }
}

TEST(Residual, NormalisedByAmplitudeSum) {
  const cs::Shaper raw("raw", {{0, 1}, {0.05, 1}}, cs::Shaper::Normalize::no);  // ΣA = 2
  EXPECT_NEAR(cs::residual_vibration(raw, cs::Mode::from_hz(9.0, 0.0)), std::abs(std::cos(0.45 * std::numbers::pi)), 1e-14);
  EXPECT_NEAR(cs::residual_vibration(raw, cs::Mode{0.0, 0.0}), 1.0, 1e-15);  // ω = 0: the step itself
}

TEST(Residual, UndampedAnalyticForms) {  // (c1)
  const cs::Shaper zv = cs::design_zv(k10Hz0);
  const cs::Shaper zvd = cs::design_zvd(k10Hz0);
  const cs::Shaper zvdd = cs::design_zvdd(k10Hz0);
  const cs::Shaper ei = cs::design_ei(k10Hz0, 0.05);
  for (double r = 0.0; r <= 3.0; r += 0.01) {
    const double c = std::cos(std::numbers::pi * r / 2);
    EXPECT_NEAR(v_at(zv, k10Hz0, r, 0), std::abs(c), 1e-13);
    EXPECT_NEAR(v_at(zvd, k10Hz0, r, 0), c * c, 1e-13);
    EXPECT_NEAR(v_at(zvdd, k10Hz0, r, 0), std::abs(c * c * c), 1e-13);
    EXPECT_NEAR(v_at(ei, k10Hz0, r, 0), std::abs(0.95 / 2 + 1.05 / 2 * std::cos(std::numbers::pi * r)), 1e-13);
  }
  EXPECT_NEAR(v_at(zv, k10Hz0, 0.9, 0), 0.156434, 1e-6);
  EXPECT_NEAR(v_at(zvd, k10Hz0, 0.9, 0), 0.024472, 1e-6);
  EXPECT_NEAR(v_at(zvdd, k10Hz0, 0.9, 0), 0.003828, 1e-6);  // the note prints 0.003827; cos³(0.45π) = 0.0038282
}

// (c4): V(r) in percent, design f = 10 Hz, design ζ = actual ζ; tables rounded to 3 decimals.
TEST(Residual, ReferenceCurveTables) {
  const std::vector<double> r{0.70, 0.80, 0.90, 0.95, 1.00, 1.05, 1.10, 1.20, 1.30};
  struct Row {
    std::string name;
    std::vector<double> pct0;
    std::vector<double> pct1;
  };
  const std::vector<Row> rows{
      {"zv", {45.399, 30.902, 15.643, 7.846, 0, 7.846, 15.643, 30.902, 45.399},
       {40.366, 27.040, 13.472, 6.704, 0, 6.599, 13.053, 25.385, 36.718}},
      {"mzv", {36.825, 23.320, 10.814, 5.156, 0, 4.581, 8.525, 14.290, 16.977},
       {30.878, 19.087, 8.641, 4.071, 0, 3.533, 6.497, 10.646, 12.385}},
      {"zvd", {20.611, 9.549, 2.447, 0.616, 0, 0.616, 2.447, 9.549, 20.611},
       {16.294, 7.311, 1.815, 0.449, 0, 0.435, 1.704, 6.444, 13.482}},
      {"zvdd", {9.357, 2.951, 0.383, 0.048, 0, 0.048, 0.383, 2.951, 9.357},
       {6.577, 1.977, 0.245, 0.030, 0, 0.029, 0.222, 1.636, 4.950}},
      {"ei-fit", {16.739, 5.137, 2.311, 4.232, 4.878, 4.232, 2.311, 5.138, 16.739},
       {11.883, 2.439, 3.279, 4.660, 5.062, 4.517, 3.082, 2.145, 9.829}}};
  for (const Row& row : rows) {
    for (int damped = 0; damped < 2; ++damped) {
      const cs::Mode m = damped ? k10Hz1 : k10Hz0;
      cs::DesignRequest req;
      req.mode = m;
      const cs::Shaper s = row.name == "ei-fit" ? fitted_ei(10.0, m.damping_ratio, 0.05)
                                                : (req.method = cs::method_from_string(row.name), cs::design(req));
      const auto& pct = damped ? row.pct1 : row.pct0;
      for (std::size_t i = 0; i < r.size(); ++i) {
        EXPECT_NEAR(100 * v_at(s, m, r[i], m.damping_ratio), pct[i], 6e-4) << row.name << " r=" << r[i] << " ζ=" << m.damping_ratio;
      }
    }
  }
}

TEST(Residual, DampingMismatchTable) {  // (c4): design ζ = 0.1, r = 1, actual ζ varies
  const std::vector<double> actual{0.0, 0.05, 0.15, 0.20};
  const std::vector<std::pair<cs::Shaper, std::vector<double>>> rows{
      {cs::design_zv(k10Hz1), {15.677, 7.232, 6.207, 11.548}},
      {cs::design_mzv(k10Hz1), {9.763, 4.297, 3.448, 6.284}},
      {cs::design_zvd(k10Hz1), {2.458, 0.523, 0.385, 1.334}},
      {cs::design_zvdd(k10Hz1), {0.385, 0.038, 0.024, 0.154}},
      {fitted_ei(10.0, 0.1, 0.05), {9.549, 6.481, 4.738, 5.121}}};
  for (const auto& [s, pct] : rows) {
    for (std::size_t i = 0; i < actual.size(); ++i) {
      EXPECT_NEAR(100 * v_at(s, k10Hz1, 1.0, actual[i]), pct[i], 6e-4) << s.method() << " ζ=" << actual[i];
    }
    const auto curve = cs::sensitivity_curve(s, k10Hz1, 0.0, 0.9, 1.1, 3);
    EXPECT_NEAR(100 * curve[1].residual, pct[0], 6e-4);
  }
}

TEST(Residual, InsensitivityTable) {  // (c3): widths and edges to 4 decimals
  struct Row {
    cs::Shaper shaper;
    double i5, i10;
  };
  const std::vector<Row> undamped{{cs::design_zv(k10Hz0), 0.0637, 0.1275},  {cs::design_mzv(k10Hz0), 0.1035, 0.2148},
                                  {cs::design_zvd(k10Hz0), 0.2871, 0.4097}, {cs::design_zvdd(k10Hz0), 0.4804, 0.6146},
                                  {cs::design_zvddd(k10Hz0), 0.6271, 0.7604}, {cs::design_ei(k10Hz0), 0.3995, 0.4938},
                                  {cs::design_ei2(k10Hz0), 0.7245, 0.8062}, {cs::design_ei3(k10Hz0), 0.9639, 1.0316}};
  // The note's 10 % column for MZV and the EI family is resolved to about 5e-4 only (the
  // closed forms below give e.g. EI 0.49350, MZV 0.21434); its 5 % column to 1e-4.
  for (const Row& row : undamped) {
    EXPECT_NEAR(cs::insensitivity(row.shaper, k10Hz0, 0.05).width(), row.i5, 1e-4) << row.shaper.method();
    EXPECT_NEAR(cs::insensitivity(row.shaper, k10Hz0, 0.10).width(), row.i10, 5e-4) << row.shaper.method();
  }
  // Closed forms at ζ = 0: MZV V = |(√2−1) + (2−√2)cos(0.75πr)|, EI V = |(1−V)/2 + (1+V)/2·cos πr|.
  const double s2 = std::sqrt(2.0);
  const double mzv_lo = std::acos((0.1 - (s2 - 1)) / (2 - s2)) / (0.75 * std::numbers::pi);
  const double mzv_hi = std::acos((-0.1 - (s2 - 1)) / (2 - s2)) / (0.75 * std::numbers::pi);
  EXPECT_NEAR(cs::insensitivity(cs::design_mzv(k10Hz0), k10Hz0, 0.10).width(), mzv_hi - mzv_lo, 1e-9);
  const double ei_lo = std::acos((0.1 - 0.475) / 0.525) / std::numbers::pi;
  EXPECT_NEAR(cs::insensitivity(cs::design_ei(k10Hz0), k10Hz0, 0.10).width(), 2 * (1 - ei_lo), 1e-9);
  const std::vector<std::pair<cs::Shaper, double>> damped{{cs::design_zv(k10Hz1), 0.0751}, {cs::design_mzv(k10Hz1), 0.1341},
                                                          {cs::design_zvd(k10Hz1), 0.3402}, {cs::design_zvdd(k10Hz1), 0.5744},
                                                          {cs::design_zvddd(k10Hz1), 0.7587}};
  for (const auto& [s, i5] : damped) EXPECT_NEAR(cs::insensitivity(s, k10Hz1, 0.05).width(), i5, 1e-4) << s.method();
  const std::vector<std::tuple<cs::Shaper, double, double>> edges{
      {cs::design_zv(k10Hz0), 0.9682, 1.0318},  {cs::design_mzv(k10Hz0), 0.9514, 1.0549},
      {cs::design_zvd(k10Hz0), 0.8564, 1.1436}, {cs::design_zvdd(k10Hz0), 0.7598, 1.2402},
      {cs::design_ei(k10Hz0), 0.8003, 1.1997},  {cs::design_ei2(k10Hz0), 0.6377, 1.3623},
      {cs::design_ei3(k10Hz0), 0.5181, 1.4819}};
  for (const auto& [s, lo, hi] : edges) {
    const cs::InsensitivityBand b = cs::insensitivity(s, k10Hz0, 0.05);
    EXPECT_NEAR(b.ratio_low, lo, 1e-4) << s.method();
    EXPECT_NEAR(b.ratio_high, hi, 1e-4) << s.method();
  }
}

TEST(Residual, InsensitivityAnalyticZvFamily) {  // (c3): I = 2(1 − (2/π)acos(Vtol^(1/n)))
  for (int n = 1; n <= 4; ++n) {
    const cs::Shaper s = cs::design_zv_derivatives(k10Hz0, n - 1);
    for (double vtol : {0.01, 0.05, 0.1, 0.3}) {
      const double expected = 2 * (1 - 2 / std::numbers::pi * std::acos(std::pow(vtol, 1.0 / n)));
      EXPECT_NEAR(cs::insensitivity(s, k10Hz0, vtol).width(), expected, 1e-9) << n << " " << vtol;
    }
  }
}

TEST(Residual, LiteratureInsensitivities) {  // ZV ≈ 0.06, ZVD ≈ 0.29, EI ≈ 0.40 at 5 %
  EXPECT_NEAR(cs::insensitivity(cs::design_zv(k10Hz0), k10Hz0, 0.05).width(), 0.06, 0.005);
  EXPECT_NEAR(cs::insensitivity(cs::design_zvd(k10Hz0), k10Hz0, 0.05).width(), 0.29, 0.005);
  EXPECT_NEAR(cs::insensitivity(cs::design_ei(k10Hz0), k10Hz0, 0.05).width(), 0.40, 0.005);
  EXPECT_NEAR(cs::insensitivity(cs::design_ei(k10Hz0), k10Hz0, 0.05).width(), 0.3992, 5e-4);  // Vaughan
  EXPECT_NEAR(cs::insensitivity(cs::design_ei2(k10Hz0), k10Hz0, 0.05).width(), 0.7262, 2e-3);
  EXPECT_NEAR(cs::insensitivity(cs::design_ei3(k10Hz0), k10Hz0, 0.05).width(), 0.9654, 2e-3);
}

// Fitted EI-family shapers have interior humps above Vtol: a naive band breaks, the hump
// tolerance does not ((c3) notes; fitted impulses from (c2)).
TEST(Residual, HumpToleranceForFittedShapers) {
  const cs::Shaper hump2("2hump-fit", {{0, 0.160458}, {0.049890, 0.338937}, {0.099748, 0.340716}, {0.149920, 0.159888}});
  // The naive edge sits where a nearly flat hump crosses 5 %: sensitive to the table's 6-digit
  // rounding of the impulses, hence 2e-3.
  EXPECT_NEAR(cs::insensitivity(hump2, k10Hz0, 0.05).width(), 0.4976, 2e-3);
  EXPECT_NEAR(cs::insensitivity(hump2, k10Hz0, 0.05, 0.1).width(), 0.7281, 1e-3);
  EXPECT_NEAR(cs::insensitivity(hump2, k10Hz0, 0.10, 0.1).width(), 0.8095, 1e-3);
  const cs::Shaper hump3("3hump-fit", {{0, 0.11275}, {0.049974, 0.23698}, {0.099849, 0.30008}, {0.149870, 0.23775}, {0.199960, 0.11244}});
  EXPECT_NEAR(cs::insensitivity(hump3, k10Hz0, 0.05, 0.1).width(), 0.9657, 1e-3);
  const cs::Shaper ei = fitted_ei(10.0, 0.1, 0.05);  // V(1) = 5.06 % > 5 %
  EXPECT_EQ(cs::insensitivity(ei, k10Hz1, 0.05).width(), 0.0);
  EXPECT_NEAR(cs::insensitivity(ei, k10Hz1, 0.05, 0.1).width(), 0.4715, 1e-3);
  EXPECT_NEAR(cs::insensitivity(fitted_ei(10.0, 0.0, 0.05), k10Hz0, 0.05).width(), 0.3972, 1e-3);
}

TEST(Residual, OpenBandIsCapped) {
  // Heavily damped ZVDD: the last impulse is tiny, so V stays below 5 % at high ratios.
  const cs::Mode m = cs::Mode::from_hz(2.0, 0.6);
  const cs::InsensitivityBand b = cs::insensitivity(cs::design_zvdd(m), m, 0.05);
  EXPECT_EQ(b.ratio_high, 10.0);
  EXPECT_GT(b.ratio_low, 0.0);
  EXPECT_LT(b.ratio_low, 1.0);
}

TEST(Residual, SensitivityCurveGridAndValidation) {
  const cs::Shaper s = cs::design_zvd(k10Hz1);
  const auto curve = cs::sensitivity_curve(s, k10Hz1, 0.5, 1.5, 11);
  ASSERT_EQ(curve.size(), 11u);
  EXPECT_DOUBLE_EQ(curve.front().frequency_ratio, 0.5);
  EXPECT_DOUBLE_EQ(curve.back().frequency_ratio, 1.5);
  EXPECT_NEAR(curve[5].frequency_ratio, 1.0, 1e-15);
  EXPECT_LT(curve[5].residual, 1e-14);
  for (const auto& p : curve) EXPECT_NEAR(p.residual, v_at(s, k10Hz1, p.frequency_ratio, 0.1), 1e-15);
  EXPECT_THROW(cs::sensitivity_curve(s, k10Hz1, 0.5, 1.5, 1), clearshape::InvalidArgument);
  EXPECT_THROW(cs::sensitivity_curve(s, k10Hz1, 1.5, 0.5, 10), clearshape::InvalidArgument);
  EXPECT_THROW(cs::sensitivity_curve(s, k10Hz1, -0.1, 0.5, 10), clearshape::InvalidArgument);
  EXPECT_THROW(cs::sensitivity_curve(s, k10Hz1, 1.0, 0.5, 1.5, 10), clearshape::InvalidArgument);
  EXPECT_THROW(cs::residual_vibration(s, cs::Mode{10.0, 1.0}), clearshape::InvalidArgument);
  EXPECT_THROW(cs::residual_vibration(s, cs::Mode{-1.0, 0.1}), clearshape::InvalidArgument);
  EXPECT_THROW(cs::insensitivity(s, k10Hz1, 0.0), clearshape::InvalidArgument);
  EXPECT_THROW(cs::insensitivity(s, k10Hz1, 0.05, -1.0), clearshape::InvalidArgument);
  EXPECT_THROW(cs::insensitivity(s, cs::Mode::from_hz(10.0, 1.5), 0.05), clearshape::InvalidArgument);
  // V(1) above vtol: width 0.
  EXPECT_EQ(cs::insensitivity(cs::design_zv(k10Hz1), cs::Mode::from_hz(13.0, 0.1), 0.05).width(), 0.0);
}

// A long shaper whose last impulse is small: V stays below vtol from r = 1 up (the band is open
// above, capped at 10) and the lower edge lies where the first impulse's decayed term grows back
// above vtol. Reference: V of two impulses in closed form, |a0 e^{−σT} + a1 e^{iω_d T}|/(a0 + a1)
// (σ = ζrωn, ω_d = rωn√(1−ζ²); Eq. 2.19), scanned down from r = 1 and bisected. Found by
// fuzz_impulses: the walk took a sample per 10⁻³/(duration in periods) to r = 10 (minutes for
// long shapers); it now skips where the envelope bound is below vtol.
TEST(Residual, LongShaperWithASmallLastImpulseHasItsBandQuickly) {
  const cs::Mode design = cs::Mode::from_hz(10.0, 0.05);
  for (const double t_last : {30.0, 900.0}) {
    const double a0 = 1.0;
    const double a1 = 0.01;
    const cs::Shaper s("long", {{0.0, a0}, {t_last, a1}}, cs::Shaper::Normalize::no);
    const auto v = [&](double r) {
      const double wn = r * design.natural_frequency_rad_s;
      const double z = design.damping_ratio;
      const std::complex<double> sum = a0 * std::exp(-z * wn * t_last) +
                                       a1 * std::polar(1.0, wn * std::sqrt(1 - z * z) * t_last);
      return std::abs(sum) / (a0 + a1);
    };
    const double vtol = 0.05;
    // Independent lower edge: scan down with a step far below the ratio period 1/(periods).
    const double periods = t_last * design.natural_frequency_hz();
    const double scan = 0.05 / periods;
    double inside = 1.0;
    while (v(inside - scan) <= vtol) inside -= scan;
    double outside = inside - scan;
    for (int i = 0; i < 200; ++i) {
      const double mid = 0.5 * (inside + outside);
      (v(mid) <= vtol ? inside : outside) = mid;
    }
    const auto start = std::chrono::steady_clock::now();
    const cs::InsensitivityBand band = cs::insensitivity(s, design, vtol);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_EQ(band.ratio_high, 10.0) << t_last;
    EXPECT_NEAR(band.ratio_low, inside, 1e-9 * inside) << t_last;
    EXPECT_LT(seconds, 1.0) << t_last;  // was ~10⁸ samples up to r = 10 at 900 s
  }
  // Found by fuzz_impulses: at 7e52 s the step fell below the spacing of doubles and the walk
  // never ended; beyond 10⁴ design periods the band is refused by name.
  const cs::Shaper absurd("long", {{0.0, 4.0}, {7e52, 1e-4}}, cs::Shaper::Normalize::no);
  try {
    (void)cs::insensitivity(absurd, design, 0.05);
    ADD_FAILURE();
  } catch (const clearshape::InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("design periods"), std::string::npos) << e.what();
  }
}
