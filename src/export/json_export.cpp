#include "clearshape/export/json_export.hpp"

#include <nlohmann/json.hpp>

#include "clearshape/export/numbers.hpp"
#include "clearshape/io/json.hpp"
#include "clearshape/shaping/residual.hpp"

namespace clearshape::exports {

namespace sh = clearshape::shaping;

namespace {

nlohmann::ordered_json mode_json(const sh::Mode& mode) {
  return {{"frequency_hz", round_significant(mode.natural_frequency_hz(), 12)},
          {"natural_frequency_rad_s", mode.natural_frequency_rad_s},
          {"zeta", mode.damping_ratio}};
}

}  // namespace

ExportText to_json(const ShaperDesign& design, const ExportOptions& options) {
  const std::vector<sh::DiscreteTap> taps = export_taps(design, options);
  const sh::Shaper discrete = taps_as_shaper(taps, options.sample_time_s);

  nlohmann::ordered_json doc = io::make_document();
  doc["format"] = "clearshape-shaper-export";
  nlohmann::ordered_json d;
  d["method"] = design.shaper.method();
  if (design.mode) d["mode"] = mode_json(*design.mode);
  if (design.second_mode) d["second_mode"] = mode_json(*design.second_mode);
  if (design.vtol) d["vtol"] = *design.vtol;
  if (design.band_hz) d["band"] = {{"frequency_low_hz", design.band_hz->first}, {"frequency_high_hz", design.band_hz->second}};
  d["duration_s"] = design.shaper.duration_s();
  d["positive"] = design.shaper.is_positive();
  if (design.update_grid_hz) d["update_grid_hz"] = *design.update_grid_hz;  // impulses on the drive's update grid
  if (!design.command.empty()) d["command"] = design.command;
  doc["design"] = d;

  nlohmann::ordered_json impulses = nlohmann::ordered_json::array();
  for (const sh::Impulse& p : design.shaper.impulses()) impulses.push_back({{"time_s", p.time_s}, {"amplitude", p.amplitude}});
  doc["impulses"] = impulses;

  nlohmann::ordered_json grid;
  grid["sample_time_s"] = options.sample_time_s;
  grid["discretization"] = options.discretization == sh::Discretization::linear ? "linear" : "exact";
  nlohmann::ordered_json tap_list = nlohmann::ordered_json::array();
  double sum = 0.0;
  for (const sh::DiscreteTap& t : taps) {
    tap_list.push_back({{"delay_samples", t.delay_samples}, {"weight", t.weight}});
    sum += t.weight;
  }
  grid["taps"] = tap_list;
  grid["weight_sum"] = sum;
  grid["history_samples"] = sh::max_delay_samples(taps) + 1;
  doc["discrete"] = grid;

  if (design.mode) {
    nlohmann::ordered_json residual;
    residual["at_design"] = {{"continuous", sh::residual_vibration(design.shaper, *design.mode)},
                             {"discrete", sh::residual_vibration(discrete, *design.mode)}};
    nlohmann::ordered_json band = nlohmann::ordered_json::array();
    double worst_c = 0.0;
    double worst_d = 0.0;
    for (std::size_t i = 0; i < kBandPoints; ++i) {
      const double r = round_significant(
          kBandRatioLow + (kBandRatioHigh - kBandRatioLow) * static_cast<double>(i) / static_cast<double>(kBandPoints - 1), 12);
      const sh::Mode actual{r * design.mode->natural_frequency_rad_s, design.mode->damping_ratio};
      const double vc = sh::residual_vibration(design.shaper, actual);
      const double vd = sh::residual_vibration(discrete, actual);
      worst_c = std::max(worst_c, vc);
      worst_d = std::max(worst_d, vd);
      band.push_back({{"ratio", r}, {"continuous", vc}, {"discrete", vd}});
    }
    residual["band"] = {{"ratio_low", kBandRatioLow}, {"ratio_high", kBandRatioHigh}, {"max_continuous", worst_c},
                        {"max_discrete", worst_d}, {"points", band}};
    doc["residual_vibration"] = residual;
  } else {
    doc["residual_vibration"] = nullptr;
  }
  doc["units"] = {{"time_s", "s"},
                  {"amplitude", "1 (fraction of the command; sum 1)"},
                  {"weight", "1 (y[k] = sum_j weight_j * u[k - delay_samples_j])"},
                  {"delay_samples", "samples of sample_time_s"},
                  {"frequency_hz", "Hz (undamped natural frequency)"},
                  {"natural_frequency_rad_s", "rad/s"},
                  {"residual_vibration", "1 (V of Eq. 2.19: residual / unshaped residual)"}};
  return {doc.dump(2) + "\n", {}};
}

}  // namespace clearshape::exports
