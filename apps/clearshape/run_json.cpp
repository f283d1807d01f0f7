#include "run_json.hpp"

#include <variant>

#include "clearshape/signal/parameters.hpp"

namespace clearshape::cli {

std::filesystem::path sidecar_path(const std::string& output) {
  std::filesystem::path p(output);
  p.replace_extension(".json");
  return p;
}

nlohmann::ordered_json signal_parameters_json(const signal::Signal& signal) {
  nlohmann::ordered_json out = nlohmann::ordered_json::object();
  for (const auto& [key, value] : signal::parameters_of(signal)) {
    out[key] = std::visit([](const auto& x) { return nlohmann::ordered_json(x); }, value);
  }
  return out;
}

nlohmann::ordered_json shaper_json(const shaping::Shaper& shaper, double frequency_hz, double zeta) {
  nlohmann::ordered_json impulses = nlohmann::ordered_json::array();
  for (const auto& i : shaper.impulses()) impulses.push_back({{"time_s", i.time_s}, {"amplitude", i.amplitude}});
  return {{"method", shaper.method()},
          {"frequency_hz", frequency_hz},
          {"damping_ratio", zeta},
          {"duration_s", shaper.duration_s()},
          {"impulses", impulses}};
}

}  // namespace clearshape::cli
