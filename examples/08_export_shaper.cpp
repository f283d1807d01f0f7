// Export a shaper for a controller: ZVDD for the thesis rig's link mode (3.32 Hz, ζ = 0.288),
// sampled at the drive's 1 kHz command rate, as a C99 header and as JSON; then what Klipper
// and RepRapFirmware can take of a printer-like 40 Hz mode. Writes export_zvdd.h and
// export_zvdd.json in the working folder. Exit 1 when a check fails.
#include <cmath>
#include <cstdio>
#include <string>

#include <nlohmann/json.hpp>

#include "clearshape/core/error.hpp"
#include "clearshape/export/export.hpp"
#include "clearshape/io/atomic_file.hpp"
#include "clearshape/shaping/design.hpp"

namespace ex = clearshape::exports;
namespace sh = clearshape::shaping;

int main() {
  const sh::Mode link = sh::Mode::from_hz(3.32, 0.288);
  const ex::ShaperDesign zvdd{sh::design_zvdd(link), sh::Method::zvdd, link, {}, {}, {}, ""};
  ex::ExportOptions options;
  options.sample_time_s = 1e-3;

  const ex::ExportText header = ex::export_shaper(zvdd, ex::Format::c_header, options);
  const ex::ExportText json = ex::export_shaper(zvdd, ex::Format::json, options);
  clearshape::io::write_text_atomic("export_zvdd.h", header.text);
  clearshape::io::write_text_atomic("export_zvdd.json", json.text);
  const auto doc = nlohmann::json::parse(json.text);
  double sum = 0.0;
  for (const auto& tap : doc["discrete"]["taps"]) sum += tap["weight"].get<double>();
  std::printf("ZVDD at 3.32 Hz, zeta 0.288, Ts = 1 ms: %zu taps over %zu samples, sum %.17g\n",
              doc["discrete"]["taps"].size(), doc["discrete"]["history_samples"].get<std::size_t>(), sum);
  std::printf("V at the mode: continuous %.2e, taps %.2e\n",
              doc["residual_vibration"]["at_design"]["continuous"].get<double>(),
              doc["residual_vibration"]["at_design"]["discrete"].get<double>());
  std::printf("wrote export_zvdd.h (%zu bytes) and export_zvdd.json\n", header.text.size());

  // A printer's 40 Hz mode: RRF has zvdd; Klipper does not, and says what to use instead.
  const sh::Mode printer = sh::Mode::from_hz(40.0, 0.1);
  const ex::ShaperDesign printer_zvdd{sh::design_zvdd(printer), sh::Method::zvdd, printer, {}, {}, {}, ""};
  std::printf("%s", ex::export_shaper(printer_zvdd, ex::Format::rrf, {}).text.c_str());
  bool klipper_refused = false;
  try {
    ex::export_shaper(printer_zvdd, ex::Format::klipper, {});
  } catch (const clearshape::InvalidArgument& e) {
    std::printf("klipper: %s\n", e.what());
    klipper_refused = true;
  }
  const bool ok = std::abs(sum - 1.0) < 1e-12 && klipper_refused &&
                  header.text.find("cs_shaper_step_q15") != std::string::npos;
  if (!ok) std::fprintf(stderr, "export check failed\n");
  return ok ? 0 : 1;
}
