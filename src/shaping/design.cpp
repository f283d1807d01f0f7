// Method names, validation shared by the design functions, custom impulse lists, convolution
// of shapers and the dispatcher.
#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "clearshape/core/error.hpp"
#include "clearshape/shaping/design.hpp"
#include "design_detail.hpp"

namespace clearshape::shaping {

namespace {

struct MethodName {
  Method method;
  std::string_view name;
};
constexpr std::array<MethodName, 11> kMethods{{{Method::zv, "zv"},
                                               {Method::zvd, "zvd"},
                                               {Method::zvdd, "zvdd"},
                                               {Method::zvddd, "zvddd"},
                                               {Method::mzv, "mzv"},
                                               {Method::ei, "ei"},
                                               {Method::ei2, "ei2"},
                                               {Method::ei3, "ei3"},
                                               {Method::si, "si"},
                                               {Method::um_zv, "um-zv"},
                                               {Method::custom, "custom"}}};

std::string joined_names() {
  std::string out;
  for (const auto& m : kMethods) {
    if (!out.empty()) out += ", ";
    out += m.name;
  }
  return out;
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

double parse_number(std::string_view text, std::string_view what, std::size_t entry,
                    std::string_view whole) {
  const std::string_view t = trim(text);
  double value = 0.0;
  const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), value);
  if (t.empty() || ec != std::errc() || end != t.data() + t.size() || !std::isfinite(value)) {
    throw InvalidArgument(fmt::format("impulses: entry {} ('{}'): {} '{}' is not a finite number; "
                                      "expected \"t1:a1,t2:a2,...\" with t in seconds",
                                      entry, trim(whole), what, t));
  }
  return value;
}

}  // namespace

namespace detail {

void validate_mode(const Mode& mode, std::string_view method) {
  require_positive(fmt::format("{}: natural_frequency_rad_s", method), mode.natural_frequency_rad_s,
                   "give the undamped natural frequency of the mode to cancel");
  const double zeta = mode.damping_ratio;
  if (std::isfinite(zeta) && zeta >= 1.0) {
    throw_invalid(fmt::format("{}: damping_ratio", method), zeta, "[0, 1)",
                  "A mode with damping ratio >= 1 is not oscillatory, so the shaper would be the "
                  "identity (a single impulse). Identify the oscillatory (residual) mode of the "
                  "link instead, e.g. with `clearshape modes`, and design the shaper for it");
  }
  require_in_half_open(fmt::format("{}: damping_ratio", method), zeta, 0.0, 1.0,
                       "the damping ratio of an oscillatory, stable mode");
}

void validate_vtol(double vtol, std::string_view method) {
  require_in_open(fmt::format("{}: vtol", method), vtol, 0.0, 1.0,
                  "vtol is the tolerable residual vibration as a fraction, e.g. 0.05 for 5 %");
}

// Eq. 2.24.
double half_period_decay(double damping_ratio) noexcept {
  return std::exp(-damping_ratio * std::numbers::pi / std::sqrt(1.0 - damping_ratio * damping_ratio));
}

}  // namespace detail

std::string_view to_string(Method method) noexcept {
  for (const auto& m : kMethods) {
    if (m.method == method) return m.name;
  }
  return "unknown";
}

Method method_from_string(std::string_view name) {
  for (const auto& m : kMethods) {
    if (m.name == name) return m.method;
  }
  throw InvalidArgument(fmt::format("method = '{}' is not a shaper method; allowed: {}", name,
                                    joined_names()));
}

std::vector<std::string_view> method_names() {
  std::vector<std::string_view> names;
  for (const auto& m : kMethods) names.push_back(m.name);
  return names;
}

std::vector<Impulse> parse_impulses(std::string_view text) {
  std::vector<Impulse> impulses;
  std::size_t entry = 0;
  std::string_view rest = text;
  while (true) {
    const std::size_t comma = rest.find(',');
    const std::string_view item = rest.substr(0, comma);
    ++entry;
    const std::size_t colon = item.find(':');
    if (colon == std::string_view::npos) {
      throw InvalidArgument(fmt::format("impulses: entry {} ('{}') has no ':'; expected "
                                        "\"t1:a1,t2:a2,...\" with t in seconds", entry, trim(item)));
    }
    const double time_s = parse_number(item.substr(0, colon), "time", entry, item);
    const double amplitude = parse_number(item.substr(colon + 1), "amplitude", entry, item);
    // An impulse of amplitude 0 is no impulse: it would only move t_N, the time at which Eq. 2.19
    // measures the residual, and let the decay e^{−ζω(t_N−tᵢ)} fake a small V.
    if (amplitude == 0.0) {
      throw InvalidArgument(fmt::format("impulses: entry {} ('{}') has amplitude 0; every impulse needs a "
                                        "non-zero amplitude", entry, trim(item)));
    }
    impulses.push_back({time_s, amplitude});
    if (comma == std::string_view::npos) break;
    rest.remove_prefix(comma + 1);
  }
  return impulses;
}

// Convolution of two impulse trains (Crain, Singhose & Seering 1996): V of the result is the
// product of the two V's, so each factor cancels its own mode.
Shaper convolve(const Shaper& a, const Shaper& b, double tolerance_s) {
  require_non_negative("convolve: tolerance_s", tolerance_s);
  std::vector<Impulse> all;
  all.reserve(a.size() * b.size());
  for (const Impulse& p : a.impulses()) {
    for (const Impulse& q : b.impulses()) all.push_back({p.time_s + q.time_s, p.amplitude * q.amplitude});
  }
  std::stable_sort(all.begin(), all.end(),
                   [](const Impulse& x, const Impulse& y) { return x.time_s < y.time_s; });
  std::vector<Impulse> merged;
  for (const Impulse& p : all) {
    if (!merged.empty() && p.time_s - merged.back().time_s <= tolerance_s) {
      merged.back().amplitude += p.amplitude;
    } else {
      merged.push_back(p);
    }
  }
  // Drop impulses that cancelled exactly (possible with negative shapers), keeping the first.
  double largest = 0.0;
  for (const Impulse& p : merged) largest = std::max(largest, std::abs(p.amplitude));
  std::vector<Impulse> kept;
  for (std::size_t i = 0; i < merged.size(); ++i) {
    if (i == 0 || std::abs(merged[i].amplitude) > 1e-14 * largest) kept.push_back(merged[i]);
  }
  return Shaper(a.method() + "*" + b.method(), std::move(kept), Shaper::Normalize::no);
}

namespace {

Shaper design_one(const DesignRequest& request, const Mode& mode) {
  switch (request.method) {
    case Method::zv: return design_zv(mode);
    case Method::zvd: return design_zvd(mode);
    case Method::zvdd: return design_zvdd(mode);
    case Method::zvddd: return design_zvddd(mode);
    case Method::mzv: return design_mzv(mode);
    case Method::ei: return design_ei(mode, request.vtol);
    case Method::ei2: return design_ei2(mode, request.vtol);
    case Method::ei3: return design_ei3(mode, request.vtol);
    case Method::um_zv: return design_um_zv(mode);
    case Method::si: {
      if (!request.si) {
        throw InvalidArgument("si: the frequency band is missing; give the band over which "
                              "V <= vtol must hold (CLI: --band-low-hz and --band-high-hz)");
      }
      SiOptions options = *request.si;
      options.vtol = request.vtol;
      return design_si(mode, options);
    }
    case Method::custom: {
      if (request.impulses.empty()) {
        throw InvalidArgument("custom: no impulses given; give them as \"t1:a1,t2:a2,...\" "
                              "(CLI: --impulses)");
      }
      return Shaper("custom", request.impulses, Shaper::Normalize::yes);
    }
  }
  throw InvalidArgument("design: unknown method");
}

}  // namespace

Shaper design(const DesignRequest& request) {
  Shaper first = design_one(request, request.mode);
  if (!request.second_mode) return first;
  if (request.method == Method::si || request.method == Method::custom) {
    throw InvalidArgument(fmt::format(
        "{}: a second mode cannot be added by convolution; for si give one band covering both "
        "modes, for custom list the convolved impulses", to_string(request.method)));
  }
  const Shaper second = design_one(request, *request.second_mode);
  return convolve(first, second);
}

}  // namespace clearshape::shaping
