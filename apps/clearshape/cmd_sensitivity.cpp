// clearshape sensitivity: the residual-vibration curve V(r) (Eq. 2.19) of a shaper over a
// range of frequency ratios r = ω/ωm, at the design damping or a mismatched one.
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "clearshape/core/error.hpp"
#include "clearshape/io/json.hpp"
#include "clearshape/io/table.hpp"
#include "clearshape/shaping/residual.hpp"
#include "cmd_shape_options.hpp"
#include "command.hpp"

namespace clearshape::cli {

namespace {

namespace sh = clearshape::shaping;

struct SensitivityState {
  ShaperOptions shaper;
  double from = 0.0;
  double to = 2.0;
  int points = 201;
  double actual_zeta = 0.0;
  CLI::Option* actual_zeta_option = nullptr;
  bool json = false;
  std::string output;
};

void run_sensitivity(const SensitivityState& st) {
  const DesignedShaper d = design_from_options(st.shaper, "sensitivity");
  if (!d.mode) {
    throw InvalidArgument("sensitivity: give the mode (--frequency-hz or --wn, and --zeta): the curve is over r = ω/ωm");
  }
  require_non_negative("--from", st.from);
  if (!(std::isfinite(st.to) && st.to > st.from)) {
    throw_invalid("--to", st.to, fmt::format("finite and > --from = {}", st.from));
  }
  if (st.points < 2 || st.points > 1000000) throw_invalid("--points", st.points, "2 … 1000000");
  const double actual = st.actual_zeta_option->count() > 0 ? st.actual_zeta : d.mode->damping_ratio;
  if (st.actual_zeta_option->count() > 0) {
    require_in_half_open("--actual-zeta", actual, 0.0, 1.0, "the damping ratio of the actual (oscillatory) mode");
  }
  const auto curve = sh::sensitivity_curve(d.shaper, *d.mode, actual, st.from, st.to, static_cast<std::size_t>(st.points));
  std::vector<double> ratio;
  std::vector<double> frequency_hz;
  std::vector<double> residual;
  for (const auto& p : curve) {
    ratio.push_back(p.frequency_ratio);
    frequency_hz.push_back(p.frequency_ratio * d.mode->natural_frequency_hz());
    residual.push_back(p.residual);
  }
  const std::vector<std::string> names{"frequency_ratio", "frequency_hz", "residual"};
  if (!st.output.empty()) {
    io::write_csv(st.output, names, {&ratio, &frequency_hz, &residual});
    fmt::print(stderr, "clearshape sensitivity: wrote {} ({} rows)\n", st.output, curve.size());
  }
  if (st.json) {
    auto doc = io::make_document();
    doc["command"] = "sensitivity";
    doc["method"] = d.shaper.method();
    doc["mode"] = mode_json(*d.mode);
    doc["actual_zeta"] = actual;
    doc["duration_s"] = d.shaper.duration_s();
    if (actual == d.mode->damping_ratio) {
      doc["insensitivity"] = band_json(sh::insensitivity(d.shaper, *d.mode, 0.05), *d.mode, 0.05);
    }
    nlohmann::ordered_json points = nlohmann::ordered_json::array();
    for (std::size_t i = 0; i < curve.size(); ++i) {
      points.push_back({{"frequency_ratio", ratio[i]}, {"frequency_hz", frequency_hz[i]}, {"residual", residual[i]}});
    }
    doc["points"] = points;
    doc["output"] = st.output.empty() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(st.output);
    print_json(doc);
  } else if (st.output.empty()) {
    const std::string text = io::format_csv(names, {&ratio, &frequency_hz, &residual});
    std::fwrite(text.data(), 1, text.size(), stdout);
  }
}

const bool sensitivity_registered = register_command(
    {"sensitivity", "Residual vibration V(r) of a shaper over a band of frequency ratios (Eq. 2.19)", 21,
     [](CLI::App& sub) {
       auto st = std::make_shared<SensitivityState>();
       add_shaper_options(sub, st->shaper);
       sub.add_option("--from", st->from, "First frequency ratio r = ω/ωm")->capture_default_str();
       sub.add_option("--to", st->to, "Last frequency ratio")->capture_default_str();
       sub.add_option("--points", st->points, "Number of evenly spaced ratios")->capture_default_str();
       st->actual_zeta_option = sub.add_option("--actual-zeta", st->actual_zeta,
                                               "Damping ratio of the actual mode (default: the design's)");
       sub.add_flag("--json", st->json, "Print a JSON document instead of CSV");
       sub.add_option("--output,-o", st->output, "Write the CSV (frequency_ratio,frequency_hz,residual) to this file");
       sub.footer(
           "Examples:\n"
           "  clearshape sensitivity --method zvd --frequency-hz 10 --zeta 0.1 --from 0.5 --to 1.5 --points 101\n"
           "  clearshape sensitivity -m ei -f 10 -z 0.1 --actual-zeta 0.05 -o ei_curve.csv");
       sub.callback([st] { run_sensitivity(*st); });
     }});

}  // namespace

}  // namespace clearshape::cli
