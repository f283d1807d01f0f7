#include "clearshape/signal/parameters.hpp"

#include <array>
#include <cmath>
#include <string>
#include <type_traits>

#include <fmt/format.h>

#include "clearshape/core/error.hpp"
#include "clearshape/signal/prbs.hpp"

namespace clearshape::signal {

namespace {

using Names = std::span<const std::string_view>;

constexpr std::array<std::string_view, 9> kTypes = {
    "step", "ramp", "sine", "prbs", "double-step", "stacked-steps", "parabolic", "trapezoid", "chirp"};

constexpr std::array<std::string_view, 4> kStep = {"amplitude", "start_s", "rise_s", "rise_shape"};
constexpr std::array<std::string_view, 3> kRamp = {"slope_per_s", "start_s", "limit"};
constexpr std::array<std::string_view, 5> kSine = {"amplitude", "frequency_hz", "phase_rad",
                                                   "offset", "start_s"};
constexpr std::array<std::string_view, 6> kPrbs = {"order", "bit_period_s", "amplitude",
                                                   "offset", "seed", "start_s"};
constexpr std::array<std::string_view, 6> kDoubleStep = {
    "amplitude", "start_s", "second_amplitude", "second_start_s", "rise_s", "rise_shape"};
constexpr std::array<std::string_view, 6> kStacked = {"levels", "dwell_s", "start_s",
                                                      "rise_s", "rise_shape", "repeat"};
constexpr std::array<std::string_view, 2> kParabolic = {"acceleration_per_s2", "start_s"};
constexpr std::array<std::string_view, 8> kChirp = {"amplitude", "f0_hz", "f1_hz", "sweep_s",
                                                    "sweep", "phase_rad", "offset", "start_s"};
constexpr std::array<std::string_view, 6> kTrapezoid = {"amplitude", "start_s", "rise_s",
                                                        "hold_s", "fall_s", "rise_shape"};

std::string joined(Names names) {
  std::string out;
  for (const auto name : names) {
    if (!out.empty()) out += ", ";
    out += name;
  }
  return out;
}

// Typed access to the parameters of one type, defaults for the missing ones.
class Reader {
 public:
  explicit Reader(const SignalParameters& p) : p_(p) {}

  double number(std::string_view key, double fallback) const {
    const auto* v = find(key);
    if (!v) return fallback;
    if (const auto* d = std::get_if<double>(v)) return *d;
    throw InvalidArgument(fmt::format("parameter '{}' must be a number", key));
  }
  std::optional<double> optional_number(std::string_view key) const {
    if (!find(key)) return std::nullopt;
    return number(key, 0.0);
  }
  // An integer given as a number: must be integral and within [lo, hi].
  double integer(std::string_view key, double fallback, double lo, double hi) const {
    const double v = number(key, fallback);
    if (!(std::isfinite(v) && v == std::floor(v) && v >= lo && v <= hi)) {
      throw_invalid(key, v, fmt::format("an integer in [{}, {}]", lo, hi));
    }
    return v;
  }
  bool flag(std::string_view key, bool fallback) const {
    const auto* v = find(key);
    if (!v) return fallback;
    if (const auto* b = std::get_if<bool>(v)) return *b;
    throw InvalidArgument(fmt::format("parameter '{}' must be true or false", key));
  }
  RiseShape shape(std::string_view key, RiseShape fallback) const {
    const auto* v = find(key);
    if (!v) return fallback;
    if (const auto* s = std::get_if<std::string>(v)) return rise_shape_from_string(*s, key);
    throw InvalidArgument(fmt::format("parameter '{}' must be a name: linear or s-curve", key));
  }
  ChirpSweep sweep(std::string_view key, ChirpSweep fallback) const {
    const auto* v = find(key);
    if (!v) return fallback;
    if (const auto* s = std::get_if<std::string>(v)) return chirp_sweep_from_string(*s, key);
    throw InvalidArgument(fmt::format("parameter '{}' must be a name: linear or logarithmic", key));
  }
  std::vector<double> list(std::string_view key, const std::vector<double>& fallback) const {
    const auto* v = find(key);
    if (!v) return fallback;
    if (const auto* l = std::get_if<std::vector<double>>(v)) return *l;
    if (const auto* d = std::get_if<double>(v)) return {*d};
    throw InvalidArgument(fmt::format("parameter '{}' must be a list of numbers", key));
  }

 private:
  const ParameterValue* find(std::string_view key) const {
    const auto it = p_.find(key);
    return it == p_.end() ? nullptr : &it->second;
  }
  const SignalParameters& p_;
};

Signal build(std::string_view type, const Reader& r) {
  if (type == "step") {
    const Step d;
    return Step{r.number("amplitude", d.amplitude), r.number("start_s", d.start_s),
                r.number("rise_s", d.rise_s), r.shape("rise_shape", d.rise_shape)};
  }
  if (type == "ramp") {
    const Ramp d;
    return Ramp{r.number("slope_per_s", d.slope_per_s), r.number("start_s", d.start_s),
                r.optional_number("limit")};
  }
  if (type == "sine") {
    const Sine d;
    return Sine{r.number("amplitude", d.amplitude), r.number("frequency_hz", d.frequency_hz),
                r.number("phase_rad", d.phase_rad), r.number("offset", d.offset),
                r.number("start_s", d.start_s)};
  }
  if (type == "prbs") {
    const Prbs d;
    const int order = static_cast<int>(
        r.integer("order", d.order, kPrbsMinOrder, kPrbsMaxOrder));
    const double max_seed = std::ldexp(1.0, order) - 1.0;
    return Prbs{order, r.number("bit_period_s", d.bit_period_s), r.number("amplitude", d.amplitude),
                r.number("offset", d.offset),
                static_cast<std::uint32_t>(r.integer("seed", d.seed, 1.0, max_seed)),
                r.number("start_s", d.start_s)};
  }
  if (type == "double-step") {
    const DoubleStep d;
    return DoubleStep{r.number("amplitude", d.amplitude), r.number("start_s", d.start_s),
                      r.number("second_amplitude", d.second_amplitude),
                      r.number("second_start_s", d.second_start_s), r.number("rise_s", d.rise_s),
                      r.shape("rise_shape", d.rise_shape)};
  }
  if (type == "stacked-steps") {
    const StackedSteps d;
    return StackedSteps{r.list("levels", d.levels), r.number("dwell_s", d.dwell_s),
                        r.number("start_s", d.start_s), r.number("rise_s", d.rise_s),
                        r.shape("rise_shape", d.rise_shape), r.flag("repeat", d.repeat)};
  }
  if (type == "parabolic") {
    const Parabolic d;
    return Parabolic{r.number("acceleration_per_s2", d.acceleration_per_s2),
                     r.number("start_s", d.start_s)};
  }
  if (type == "chirp") {
    const Chirp d;
    return Chirp{r.number("amplitude", d.amplitude), r.number("f0_hz", d.f0_hz),     r.number("f1_hz", d.f1_hz),
                 r.number("sweep_s", d.sweep_s),     r.sweep("sweep", d.sweep),     r.number("phase_rad", d.phase_rad),
                 r.number("offset", d.offset),       r.number("start_s", d.start_s)};
  }
  const Trapezoid d;  // "trapezoid" (the type was checked by the caller)
  return Trapezoid{r.number("amplitude", d.amplitude), r.number("start_s", d.start_s),
                   r.number("rise_s", d.rise_s),       r.number("hold_s", d.hold_s),
                   r.number("fall_s", d.fall_s),       r.shape("rise_shape", d.rise_shape)};
}

}  // namespace

std::span<const std::string_view> signal_types() { return kTypes; }

std::span<const std::string_view> parameter_names(std::string_view type) {
  if (type == "step") return kStep;
  if (type == "ramp") return kRamp;
  if (type == "sine") return kSine;
  if (type == "prbs") return kPrbs;
  if (type == "double-step") return kDoubleStep;
  if (type == "stacked-steps") return kStacked;
  if (type == "parabolic") return kParabolic;
  if (type == "trapezoid") return kTrapezoid;
  if (type == "chirp") return kChirp;
  throw InvalidArgument(fmt::format("signal type '{}' is unknown; allowed: {}", type, joined(kTypes)));
}

Signal make_signal(std::string_view type, const SignalParameters& parameters) {
  const Names names = parameter_names(type);
  for (const auto& [key, value] : parameters) {
    bool known = false;
    for (const auto name : names) known = known || name == key;
    if (!known) {
      throw InvalidArgument(fmt::format("parameter '{}' does not apply to signal type '{}'; it takes: {}",
                                        key, type, joined(names)));
    }
  }
  return build(type, Reader(parameters));
}

SignalParameters parameters_of(const Signal& signal) {
  const auto shape = [](RiseShape r) { return ParameterValue(std::string(to_string(r))); };
  return std::visit(
      [&](const auto& s) -> SignalParameters {
        using T = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<T, Step>) {
          return {{"amplitude", s.amplitude}, {"start_s", s.start_s}, {"rise_s", s.rise_s},
                  {"rise_shape", shape(s.rise_shape)}};
        } else if constexpr (std::is_same_v<T, Ramp>) {
          SignalParameters p{{"slope_per_s", s.slope_per_s}, {"start_s", s.start_s}};
          if (s.limit) p["limit"] = *s.limit;
          return p;
        } else if constexpr (std::is_same_v<T, Sine>) {
          return {{"amplitude", s.amplitude}, {"frequency_hz", s.frequency_hz},
                  {"phase_rad", s.phase_rad}, {"offset", s.offset}, {"start_s", s.start_s}};
        } else if constexpr (std::is_same_v<T, Prbs>) {
          return {{"order", static_cast<double>(s.order)}, {"bit_period_s", s.bit_period_s},
                  {"amplitude", s.amplitude}, {"offset", s.offset},
                  {"seed", static_cast<double>(s.seed)}, {"start_s", s.start_s}};
        } else if constexpr (std::is_same_v<T, DoubleStep>) {
          return {{"amplitude", s.amplitude}, {"start_s", s.start_s},
                  {"second_amplitude", s.second_amplitude}, {"second_start_s", s.second_start_s},
                  {"rise_s", s.rise_s}, {"rise_shape", shape(s.rise_shape)}};
        } else if constexpr (std::is_same_v<T, StackedSteps>) {
          return {{"levels", s.levels}, {"dwell_s", s.dwell_s}, {"start_s", s.start_s},
                  {"rise_s", s.rise_s}, {"rise_shape", shape(s.rise_shape)}, {"repeat", s.repeat}};
        } else if constexpr (std::is_same_v<T, Parabolic>) {
          return {{"acceleration_per_s2", s.acceleration_per_s2}, {"start_s", s.start_s}};
        } else if constexpr (std::is_same_v<T, Chirp>) {
          return {{"amplitude", s.amplitude}, {"f0_hz", s.f0_hz},         {"f1_hz", s.f1_hz},
                  {"sweep_s", s.sweep_s},     {"sweep", ParameterValue(std::string(to_string(s.sweep)))},
                  {"phase_rad", s.phase_rad}, {"offset", s.offset},       {"start_s", s.start_s}};
        } else {
          static_assert(std::is_same_v<T, Trapezoid>);
          return {{"amplitude", s.amplitude}, {"start_s", s.start_s}, {"rise_s", s.rise_s},
                  {"hold_s", s.hold_s},       {"fall_s", s.fall_s},   {"rise_shape", shape(s.rise_shape)}};
        }
      },
      signal.spec());
}

}  // namespace clearshape::signal
