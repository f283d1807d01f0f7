#include "clearshape/export/export.hpp"

#include <fmt/format.h>

#include "clearshape/core/error.hpp"
#include "clearshape/export/c_header.hpp"
#include "clearshape/export/json_export.hpp"
#include "clearshape/export/klipper.hpp"
#include "clearshape/export/rrf.hpp"

namespace clearshape::exports {

namespace sh = clearshape::shaping;

std::string_view to_string(Format format) noexcept {
  switch (format) {
    case Format::json: return "json";
    case Format::c_header: return "c-header";
    case Format::klipper: return "klipper";
    case Format::rrf: return "rrf";
  }
  return "?";
}

std::vector<std::string_view> format_names() { return {"json", "c-header", "klipper", "rrf"}; }

Format format_from_string(std::string_view name) {
  for (Format f : {Format::json, Format::c_header, Format::klipper, Format::rrf}) {
    if (to_string(f) == name) return f;
  }
  throw InvalidArgument(fmt::format("--export = '{}' is not a known format; allowed: {}", name,
                                    fmt::join(format_names(), ", ")));
}

std::vector<sh::DiscreteTap> export_taps(const ShaperDesign& design, const ExportOptions& options) {
  require_positive("sample_time_s", options.sample_time_s, "The controller's sample period in seconds.");
  if (options.discretization == sh::Discretization::exact_at_mode) {
    if (!design.mode) {
      throw InvalidArgument("exact discretisation needs the design mode (--frequency-hz and --zeta)");
    }
    return sh::discretize(design.shaper, options.sample_time_s, options.discretization, *design.mode);
  }
  return sh::discretize(design.shaper, options.sample_time_s);
}

sh::Shaper taps_as_shaper(std::span<const sh::DiscreteTap> taps, double sample_time_s) {
  std::vector<sh::Impulse> impulses;
  impulses.reserve(taps.size());
  for (const sh::DiscreteTap& t : taps) impulses.push_back({static_cast<double>(t.delay_samples) * sample_time_s, t.weight});
  return sh::Shaper("taps", std::move(impulses), sh::Shaper::Normalize::no);
}

ExportText export_shaper(const ShaperDesign& design, Format format, const ExportOptions& options) {
  switch (format) {
    case Format::json: return to_json(design, options);
    case Format::c_header: return to_c_header(design, options);
    case Format::klipper: return to_klipper(design, options);
    case Format::rrf: return to_rrf(design, options);
  }
  throw InvalidArgument("export_shaper: unknown format");
}

}  // namespace clearshape::exports
