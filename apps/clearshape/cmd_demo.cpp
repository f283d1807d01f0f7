// `clearshape demo`: a short demonstration of input shaping on the thesis's identified
// speed-mode drive model (Eq. 4.2): a step command, unshaped and shaped with ZV, ZVD and ZVDD
// (Eq. 2.22–2.26) designed from ωn = 1/Tw and ζ = Zeta (thesis §4.2), simulated by the linear
// drive model. Prints the delay, overshoot, undershoot and settling time; writes CSV and JSON.
#include <filesystem>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "clearshape/io/json.hpp"
#include "clearshape/io/table.hpp"
#include "clearshape/lti/process_model.hpp"
#include "clearshape/lti/simulate.hpp"
#include "clearshape/metrics/step_info.hpp"
#include "clearshape/shaping/apply.hpp"
#include "clearshape/shaping/design.hpp"
#include "command.hpp"
#include "option_checks.hpp"

namespace clearshape::cli {
namespace {

struct DemoOptions {
  std::string out_dir = "out/demo";
  double rate_hz = 1000.0;
  double duration_s = 1.5;
  double step_time_s = 0.1;
  bool json = false;
};

void run_demo(const DemoOptions& o) {
  const lti::ProcessModel model = lti::thesis_speed_mode_model();
  const shaping::Mode mode{model.natural_frequency_rad_s(), model.damping_ratio()};
  fmt::print(stderr, "clearshape demo: thesis speed-mode drive model (Eq. 4.2), wn = {:.3f} rad/s "
                     "({:.3f} Hz), zeta = {:.4f}\n", mode.natural_frequency_rad_s,
             mode.natural_frequency_hz(), mode.damping_ratio);

  UniformSeries step;
  step.sample_time_s = 1.0 / o.rate_hz;
  step.values.resize(sample_count(o.duration_s, step.sample_time_s));
  for (std::size_t i = 0; i < step.values.size(); ++i) {
    step.values[i] = step.time_s(i) >= o.step_time_s ? 1.0 : 0.0;  // unit speed command
  }

  struct Case {
    std::string name;
    std::optional<shaping::Shaper> shaper;
  };
  std::vector<Case> cases{{"unshaped", std::nullopt},
                          {"zv", shaping::design_zv(mode)},
                          {"zvd", shaping::design_zvd(mode)},
                          {"zvdd", shaping::design_zvdd(mode)}};

  std::vector<std::string> names{"time_s"};
  std::vector<std::vector<double>> columns{step.times_s()};
  auto doc = io::make_document();
  doc["model"] = {{"structure", model.code()}, {"kp", model.parameters().kp},
                  {"tz_s", model.parameters().tz}, {"zeta", model.parameters().zeta},
                  {"tw_s", model.parameters().tw}, {"tp3_s", model.parameters().tp3}};
  doc["units"] = {{"command", "command units (unit step)"}, {"response", "deg/s per command unit"}};
  nlohmann::ordered_json results = nlohmann::ordered_json::array();

  fmt::print("{:<10} {:>11} {:>13} {:>13} {:>11}\n", "shaper", "delay_s", "overshoot_%",
             "undershoot_%", "settle_s");
  for (const Case& c : cases) {
    const UniformSeries command = c.shaper ? shaping::shape_offline(*c.shaper, step, false) : step;
    const UniformSeries response = lti::simulate(model, command);
    metrics::StepInfoOptions si;
    si.step_time_s = o.step_time_s;
    si.final_value = model.dc_gain();
    const metrics::StepInfo info = metrics::step_info(response, si);
    const double delay_s = c.shaper ? c.shaper->duration_s() : 0.0;
    fmt::print("{:<10} {:>11.4f} {:>13.2f} {:>13.2f} {:>11.3f}\n", c.name, delay_s,
               info.overshoot_percent, info.undershoot_percent, info.settling_time_s);
    names.push_back(fmt::format("command_{}", c.name));
    columns.push_back(command.values);
    names.push_back(fmt::format("speed_{}_deg_s", c.name));
    columns.push_back(response.values);
    results.push_back({{"shaper", c.name}, {"delay_s", delay_s},
                       {"overshoot_percent", info.overshoot_percent},
                       {"undershoot_percent", info.undershoot_percent},
                       {"settling_time_s", info.settling_time_s}});
  }
  doc["results"] = results;

  const std::filesystem::path dir(o.out_dir);
  std::vector<const std::vector<double>*> pointers;
  for (const auto& c : columns) pointers.push_back(&c);
  io::write_csv(dir / "demo.csv", names, pointers);
  io::write_json(dir / "demo.json", doc);
  if (o.json) print_json(doc);
  fmt::print(stderr, "clearshape demo: wrote {} and {}\n", (dir / "demo.csv").string(),
             (dir / "demo.json").string());
}

const bool demo_registered = register_command(
    {"demo", "Demonstrate shaping a step on the thesis's speed-mode drive model", 5,
     [](CLI::App& sub) {
       auto options = std::make_shared<DemoOptions>();
       sub.add_option("--out", options->out_dir, "Output folder for demo.csv and demo.json")
           ->capture_default_str()->check(output_folder());
       sub.add_option("--rate", options->rate_hz, "Sample rate in Hz")
           ->capture_default_str()->check(CLI::Range(10.0, 1e6));
       sub.add_option("--duration", options->duration_s, "Duration in s")
           ->capture_default_str()->check(CLI::Range(0.5, 100.0));
       sub.add_flag("--json", options->json, "Print the results as JSON on stdout");
       sub.callback([options] { run_demo(*options); });
     }});

}  // namespace
}  // namespace clearshape::cli
