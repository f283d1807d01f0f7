#include "clearshape/export/firmware_shapers.hpp"

#include <array>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "clearshape/core/error.hpp"
#include "clearshape/shaping/residual.hpp"

namespace clearshape::exports {

namespace sh = clearshape::shaping;

namespace {

// Singhose's damped two- and three-hump EI curve fits at Vtol = 5 % (Singhose, Seering &
// Singer 1997; the tables both firmwares use): value(ζ) = c0 + c1·ζ + c2·ζ² + c3·ζ³, times in
// periods. Row i is impulse i (the first time is 0).
using Cubic = std::array<double, 4>;
constexpr std::array<Cubic, 4> kEi2Amplitude{{{0.16054, 0.76699, 2.26560, -1.22750},
                                              {0.33911, 0.45081, -2.58080, 1.73650},
                                              {0.34089, -0.61533, -0.68765, 0.42261},
                                              {0.15997, -0.60246, 1.00280, -0.93145}}};
constexpr std::array<Cubic, 4> kEi2Time{{{0.0, 0.0, 0.0, 0.0},
                                         {0.49890, 0.16270, -0.54262, 6.16180},
                                         {0.99748, 0.18382, -1.58270, 8.17120},
                                         {1.49920, -0.09297, -0.28338, 1.85710}}};
constexpr std::array<Cubic, 5> kEi3Amplitude{{{0.11275, 0.76632, 3.29160, -1.44380},
                                              {0.23698, 0.61164, -2.57850, 4.85220},
                                              {0.30008, -0.19062, -2.14560, 0.13744},
                                              {0.23775, -0.73297, 0.46885, -2.08650},
                                              {0.11244, -0.45439, 0.96382, -1.46000}}};
constexpr std::array<Cubic, 5> kEi3Time{{{0.0, 0.0, 0.0, 0.0},
                                         {0.49974, 0.23834, 0.44559, 12.4720},
                                         {0.99849, 0.29808, -2.36460, 23.3990},
                                         {1.49870, 0.10306, -2.01390, 17.0320},
                                         {1.99960, -0.28231, 0.61536, 5.40450}}};

double cubic(const Cubic& c, double z) { return c[0] + z * (c[1] + z * (c[2] + z * c[3])); }

template <std::size_t N>
sh::Shaper curve_fit(std::string name, const std::array<Cubic, N>& amplitude, const std::array<Cubic, N>& time,
                     double zeta, double period_s) {
  std::vector<sh::Impulse> impulses;
  for (std::size_t i = 0; i < N; ++i) impulses.push_back({cubic(time[i], zeta) * period_s, cubic(amplitude[i], zeta)});
  return sh::Shaper(std::move(name), std::move(impulses));
}

struct Damped {
  double df;        // √(1−ζ²)
  double period_s;  // damped period Td = 1/(f·√(1−ζ²))
  double k;         // exp(−ζπ/√(1−ζ²)): the decay over half a damped period
};

Damped damped(double frequency_hz, double zeta) {
  require_positive("frequency_hz", frequency_hz);
  require_in_half_open("damping ratio", zeta, 0.0, 1.0);
  const double df = std::sqrt(1.0 - zeta * zeta);
  return {df, 1.0 / (frequency_hz * df), std::exp(-zeta * std::numbers::pi / df)};
}

// ZV family with n+1 impulses (binomial C(n,i)·K^i at i·Td/2; Singer & Seering 1990).
sh::Shaper zv_family(std::string name, int n, const Damped& d) {
  std::vector<sh::Impulse> impulses;
  double binomial = 1.0;
  for (int i = 0; i <= n; ++i) {
    impulses.push_back({0.5 * i * d.period_s, binomial * std::pow(d.k, i)});
    binomial = binomial * (n - i) / (i + 1);
  }
  return sh::Shaper(std::move(name), std::move(impulses));
}

// MZV amplitudes 1 − 1/√2, (√2 − 1)·Km, (1 − 1/√2)·Km² at 0, 0.375·Td, 0.75·Td with
// Km = exp(−0.75·ζπ/√(1−ζ²)); `reversed` puts them in RRF's order.
sh::Shaper mzv(std::string name, const Damped& d, double zeta, bool reversed) {
  const double km = std::exp(-0.75 * zeta * std::numbers::pi / d.df);
  std::array<double, 3> a{1.0 - std::numbers::sqrt2 / 2.0, (std::numbers::sqrt2 - 1.0) * km,
                          (1.0 - std::numbers::sqrt2 / 2.0) * km * km};
  if (reversed) std::swap(a[0], a[2]);
  return sh::Shaper(std::move(name), {{0.0, a[0]}, {0.375 * d.period_s, a[1]}, {0.75 * d.period_s, a[2]}});
}

}  // namespace

std::vector<std::string_view> klipper_types() { return {"zv", "mzv", "zvd", "ei", "2hump_ei", "3hump_ei"}; }

std::vector<std::string_view> rrf_types() { return {"mzv", "zvd", "zvdd", "zvddd", "ei2", "ei3"}; }

std::optional<sh::Shaper> klipper_shaper(std::string_view type, double frequency_hz, double zeta) {
  const Damped d = damped(frequency_hz, zeta);
  const std::string name = fmt::format("klipper:{}", type);
  if (type == "zv") return zv_family(name, 1, d);
  if (type == "zvd") return zv_family(name, 2, d);
  if (type == "mzv") return mzv(name, d, zeta, false);
  if (type == "ei") {
    // Singhose's damped EI fit (Singhose, Seering & Singer 1994) at Vtol = 1/20, times on Td.
    constexpr double v = 1.0 / 20.0;
    const double z = zeta;
    const double a1 = (0.24968 + 0.24961 * v) + ((0.80008 + 1.23328 * v) + (0.49599 + 3.17316 * v) * z) * z;
    const double a3 = (0.25149 + 0.21474 * v) + ((-0.83249 + 1.41498 * v) + (0.85181 - 4.90094 * v) * z) * z;
    const double t2 = 0.4999 + (((0.46159 + 8.57843 * v) * v) +
                                (((4.26169 - 108.644 * v) * v) + ((1.75601 + 336.989 * v) * v) * z) * z) * z;
    return sh::Shaper(name, {{0.0, a1}, {t2 * d.period_s, 1.0 - a1 - a3}, {d.period_s, a3}});
  }
  if (type == "2hump_ei") return curve_fit(name, kEi2Amplitude, kEi2Time, zeta, 1.0 / frequency_hz);
  if (type == "3hump_ei") return curve_fit(name, kEi3Amplitude, kEi3Time, zeta, 1.0 / frequency_hz);
  return std::nullopt;
}

std::optional<sh::Shaper> rrf_shaper(std::string_view type, double frequency_hz, double zeta) {
  const Damped d = damped(frequency_hz, zeta);
  const std::string name = fmt::format("rrf:{}", type);
  if (type == "zvd") return zv_family(name, 2, d);
  if (type == "zvdd") return zv_family(name, 3, d);
  if (type == "zvddd") return zv_family(name, 4, d);
  if (type == "mzv") return mzv(name, d, zeta, true);
  // RRF's EI2/EI3: the last amplitude is 1 − (sum of the others), times on the damped period.
  if (type == "ei2" || type == "ei3") {
    sh::Shaper fit = type == "ei2" ? curve_fit(name, kEi2Amplitude, kEi2Time, zeta, d.period_s)
                                   : curve_fit(name, kEi3Amplitude, kEi3Time, zeta, d.period_s);
    std::vector<sh::Impulse> impulses(fit.impulses().begin(), fit.impulses().end());
    double others = 0.0;
    for (std::size_t i = 0; i + 1 < impulses.size(); ++i) others += impulses[i].amplitude;
    impulses.back().amplitude = 1.0 - others;
    return sh::Shaper(name, std::move(impulses));
  }
  return std::nullopt;
}

sh::Shaper rrf_custom_shaper(const std::vector<double>& h, const std::vector<double>& t_s) {
  if (h.size() != t_s.size()) {
    throw InvalidArgument(fmt::format("RRF custom shaper: {} amplitudes (H) but {} durations (T); they must match",
                                      h.size(), t_s.size()));
  }
  std::vector<sh::Impulse> impulses;
  double time_s = 0.0;
  double previous = 0.0;
  for (std::size_t i = 0; i < h.size(); ++i) {
    impulses.push_back({time_s, h[i] - previous});
    previous = h[i];
    require_positive("RRF custom duration T", t_s[i]);
    time_s += t_s[i];
  }
  impulses.push_back({time_s, 1.0 - previous});
  return sh::Shaper("rrf:custom", std::move(impulses), sh::Shaper::Normalize::no);
}

ResidualDifference residual_difference(const sh::Shaper& a, const sh::Shaper& b, const sh::Mode& mode,
                                       double ratio_low, double ratio_high, std::size_t points) {
  ResidualDifference out;
  for (std::size_t i = 0; i < points; ++i) {
    const double r = points == 1 ? ratio_low
                                 : ratio_low + (ratio_high - ratio_low) * static_cast<double>(i) /
                                                   static_cast<double>(points - 1);
    const sh::Mode actual{r * mode.natural_frequency_rad_s, mode.damping_ratio};
    const double dv = std::abs(sh::residual_vibration(a, actual) - sh::residual_vibration(b, actual));
    if (dv > out.max_abs) {
      out.max_abs = dv;
      out.at_ratio = r;
    }
  }
  return out;
}

}  // namespace clearshape::exports
