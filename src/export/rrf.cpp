#include "clearshape/export/rrf.hpp"

#include <cmath>
#include <string>

#include <fmt/format.h>

#include "clearshape/core/error.hpp"
#include "clearshape/core/version.hpp"
#include "clearshape/export/firmware_shapers.hpp"
#include "clearshape/export/numbers.hpp"

namespace clearshape::exports {

namespace sh = clearshape::shaping;

namespace {

constexpr int kRrfDigits = 6;         // significant digits of F, S, H and T (RRF keeps binary32)
constexpr double kRrfVtol = 0.05;     // the curve fits behind ei2/ei3 are for Vtol = 5 %

std::string join(const std::vector<std::string>& parts) {
  std::string out;
  for (const std::string& p : parts) out += (out.empty() ? "" : ":") + p;
  return out;
}

}  // namespace

std::optional<std::string_view> rrf_type_for(sh::Method method) {
  switch (method) {
    case sh::Method::zvd: return "zvd";
    case sh::Method::zvdd: return "zvdd";
    case sh::Method::zvddd: return "zvddd";
    case sh::Method::mzv: return "mzv";
    case sh::Method::ei2: return "ei2";
    case sh::Method::ei3: return "ei3";
    default: return std::nullopt;
  }
}

namespace {

// Why the design cannot be one of RRF's named types before comparing shapers ("" if it may be).
std::string why_not_named(const ShaperDesign& design, const std::optional<std::string_view>& type) {
  if (design.method == sh::Method::custom) return "the design is a custom impulse list";
  if (!type) return fmt::format("RRF has no {} type", sh::to_string(design.method));
  if (design.second_mode) return "RRF's named types shape one mode";
  if (!design.mode) return "no design mode";
  if (design.vtol && std::abs(*design.vtol - kRrfVtol) > 1e-12) {
    return fmt::format("RRF's {} is the Vtol = 5 % design, this one has Vtol = {}", *type, *design.vtol);
  }
  return {};
}

// The named form: the lines to print, or why the custom form is needed instead.
struct NamedForm {
  std::string lines;  ///< comment and M593 line; empty when no named type fits
  std::string why_custom;
};

// A named type when RRF's own design from the printed F and S matches ours.
NamedForm named_form(const ShaperDesign& design) {
  const std::optional<std::string_view> type = rrf_type_for(design.method);
  if (std::string why = why_not_named(design, type); !why.empty()) return {{}, why};
  const double f_hz = design.mode->natural_frequency_hz();
  const std::string freq = fixed_significant(f_hz, kRrfDigits);
  const std::string zeta = fixed_significant(design.mode->damping_ratio, kRrfDigits);
  if (std::stod(freq) < kRrfMinFrequencyHz || std::stod(freq) > kRrfMaxFrequencyHz) {
    return {{}, fmt::format("F = {} Hz is outside RRF's range for named types, [{:.4g}, {:g}] Hz", freq,
                            kRrfMinFrequencyHz, kRrfMaxFrequencyHz)};
  }
  if (std::stod(zeta) > 0.99) return {{}, fmt::format("S = {} is above RRF's limit 0.99", zeta)};
  const sh::Shaper theirs = *rrf_shaper(*type, std::stod(freq), std::stod(zeta));
  const ResidualDifference diff = residual_difference(design.shaper, theirs, *design.mode);
  if (diff.max_abs > kFirmwareResidualTolerance) {
    const std::string grid =
        design.update_grid_hz ? fmt::format(" on the {} Hz update grid", fixed_significant(*design.update_grid_hz, kRrfDigits)) : "";
    return {{}, fmt::format("the {} RRF builds from F{} S{} differs from the design{} by {:.3g} in residual vibration "
                            "(at r = {:.3g}; tolerance {})",
                            *type, freq, zeta, grid, diff.max_abs, diff.at_ratio, kFirmwareResidualTolerance)};
  }
  std::string lines = fmt::format("; RRF builds {} itself from F (the undamped natural frequency, Hz) and S (damping "
                                  "ratio);\n; its shaper and the design differ in residual vibration by at most "
                                  "{:.2g} over 0.5 .. 1.5 x F (tolerance {}).\n",
                                  *type, diff.max_abs, kFirmwareResidualTolerance);
  lines += fmt::format("M593 P\"{}\" F{} S{}\n", *type, freq, zeta);
  return {lines, {}};
}

// RRF's custom form: H = cumulative amplitudes of all impulses but the last, T = durations.
ExportText custom_form(const ShaperDesign& design, const std::string& header, const std::string& why_custom) {
  const sh::Shaper& shaper = design.shaper;
  if (shaper.size() < 2) {
    throw InvalidArgument("--export rrf: a one-impulse shaper does not shape; RRF's equivalent is M593 P\"none\"");
  }
  if (shaper.size() > kRrfMaxImpulses) {
    throw InvalidArgument(fmt::format("--export rrf: {} ({}), and the {} shaper has {} impulses; RRF's custom form "
                                      "takes at most {}. Use a shorter shaper or --export c-header / json",
                                      why_custom, "no named type fits", shaper.method(), shaper.size(), kRrfMaxImpulses));
  }
  std::vector<std::string> h;
  std::vector<std::string> t;
  std::vector<double> h_value;
  std::vector<double> t_value;
  double cumulative = 0.0;
  const auto impulses = shaper.impulses();
  for (std::size_t i = 0; i + 1 < impulses.size(); ++i) {
    cumulative += impulses[i].amplitude;
    h.push_back(fixed_significant(cumulative, kRrfDigits));
    t.push_back(fixed_significant(impulses[i + 1].time_s - impulses[i].time_s, kRrfDigits));
    h_value.push_back(std::stod(h.back()));
    t_value.push_back(std::stod(t.back()));
  }
  ExportText out;
  out.notes.push_back(fmt::format("rrf: custom form: {}", why_custom));
  out.text = header + fmt::format("; Custom form (H: cumulative amplitudes of every impulse but the last; T: durations "
                                  "between impulses, s):\n; {}.\n", why_custom);
  if (design.mode) {
    const sh::Shaper theirs = rrf_custom_shaper(h_value, t_value);
    const ResidualDifference diff = residual_difference(shaper, theirs, *design.mode);
    out.text += fmt::format("; As printed, it differs from the design in residual vibration by at most {:.2g} over "
                            "0.5 .. 1.5 x the mode.\n", diff.max_abs);
  }
  out.text += fmt::format("M593 P\"custom\" H{} T{}\n", join(h), join(t));
  return out;
}

}  // namespace

ExportText to_rrf(const ShaperDesign& design, const ExportOptions& /*options*/) {
  const sh::Shaper& shaper = design.shaper;
  if (!shaper.is_positive()) {
    throw InvalidArgument(fmt::format("--export rrf: the {} shaper has negative impulses; RRF shapes accelerations with "
                                      "positive fractions only. Use a positive shaper (zvd, zvdd, ei2)", shaper.method()));
  }
  std::string header = fmt::format("; Input shaper exported by clearshape {} for RepRapFirmware 3.5/3.6 (M593).\n", kVersion);
  if (!design.command.empty()) header += fmt::format(";   {}\n", design.command);
  const NamedForm named = named_form(design);
  if (!named.lines.empty()) {
    ExportText out;
    out.text = header + named.lines;
    return out;
  }
  return custom_form(design, header, named.why_custom);
}

}  // namespace clearshape::exports
