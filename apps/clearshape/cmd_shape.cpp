// clearshape shape: design an input shaper (thesis §2.5, Eq. 2.19–2.26, and beyond: MZV, EI
// family, SI, UM-ZV, custom, two-mode convolution), print its impulses, duration and 5 %
// insensitivity; optionally shape a CSV column with it (offline convolution).
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "clearshape/core/error.hpp"
#include "clearshape/core/units.hpp"
#include "clearshape/export/export.hpp"
#include "clearshape/io/atomic_file.hpp"
#include "clearshape/io/json.hpp"
#include "clearshape/io/table.hpp"
#include "clearshape/shaping/apply.hpp"
#include "clearshape/shaping/design.hpp"
#include "clearshape/shaping/grid.hpp"
#include "clearshape/shaping/residual.hpp"
#include "cmd_shape_clearance_aware.hpp"
#include "cmd_shape_options.hpp"
#include "command.hpp"
#include "option_checks.hpp"

namespace clearshape::cli {

namespace sh = clearshape::shaping;

namespace {

std::string method_list() {
  std::string out;
  for (std::string_view n : sh::method_names()) {
    if (!out.empty()) out += "|";
    out += n;
  }
  return out;
}

bool given(const CLI::Option* o) { return o != nullptr && o->count() > 0; }

constexpr double kReportVtol = 0.05;  // the insensitivity printed by `shape`

}  // namespace

void add_shaper_options(CLI::App& sub, ShaperOptions& o) {
  sub.add_option("--method,-m", o.method, "Shaper: " + method_list())->required();
  o.frequency_option = sub.add_option("--frequency-hz,-f", o.frequency_hz, "Undamped natural frequency of the mode (Hz)");
  o.wn_option = sub.add_option("--wn", o.wn_rad_s, "Undamped natural frequency of the mode (rad/s)");
  o.frequency_option->excludes(o.wn_option);
  o.zeta_option = sub.add_option("--zeta,-z", o.zeta, "Damping ratio of the mode, in [0, 1)");
  sub.add_option("--vtol", o.vtol, "Tolerable residual vibration for ei/ei2/ei3/si, in (0, 1)")->capture_default_str();
  o.band_low_option = sub.add_option("--band-low-hz", o.band_low_hz, "si: lower edge of the band where V <= vtol (Hz)");
  o.band_high_option = sub.add_option("--band-high-hz", o.band_high_hz, "si: upper edge of the band (Hz)");
  sub.add_option("--si-impulses", o.si_impulses, "si: number of impulses (0 = automatic)")->capture_default_str();
  sub.add_option("--si-points", o.si_points, "si: band frequencies at which V <= vtol is enforced initially")->capture_default_str();
  o.impulses_option = sub.add_option("--impulses", o.impulses, "custom: impulses \"t1:a1,t2:a2,...\" (t in s; normalised to sum 1)");
  o.second_frequency_option = sub.add_option("--second-frequency-hz", o.second_frequency_hz,
                                             "Also cancel a second mode (Hz): the same method is designed for it and convolved");
  o.second_zeta_option = sub.add_option("--second-zeta", o.second_zeta, "Damping ratio of the second mode, in [0, 1)");
}

DesignedShaper design_from_options(const ShaperOptions& o, std::string_view command) {
  const sh::Method method = sh::method_from_string(o.method);
  sh::DesignRequest req;
  req.method = method;
  std::optional<sh::Mode> mode;
  const bool has_frequency = given(o.frequency_option) || given(o.wn_option);
  if (has_frequency) {
    double wn = o.wn_rad_s;
    if (given(o.frequency_option)) {
      require_positive("--frequency-hz", o.frequency_hz, "the undamped natural frequency of the mode to cancel");
      wn = hz_to_rad_s(o.frequency_hz);
    } else {
      require_positive("--wn", o.wn_rad_s, "the undamped natural frequency of the mode to cancel (rad/s)");
    }
    if (!given(o.zeta_option)) {
      throw InvalidArgument(fmt::format("{}: --zeta is required with a frequency; give the mode's damping ratio in [0, 1)", command));
    }
    mode = sh::Mode{wn, o.zeta};
  } else if (method != sh::Method::custom) {
    throw InvalidArgument(fmt::format("{}: --frequency-hz (or --wn) and --zeta are required for method {}; "
                                      "give the mode to cancel (identify it with `clearshape modes`)",
                                      command, o.method));
  }
  if (mode) req.mode = *mode;
  req.vtol = o.vtol;
  if (method == sh::Method::si) {
    if (!given(o.band_low_option) || !given(o.band_high_option)) {
      throw InvalidArgument(fmt::format("{}: method si needs --band-low-hz and --band-high-hz (the band where "
                                        "V <= vtol must hold)", command));
    }
    require_positive("--band-low-hz", o.band_low_hz);
    if (!(std::isfinite(o.band_high_hz) && o.band_high_hz > o.band_low_hz)) {
      throw_invalid("--band-high-hz", o.band_high_hz, fmt::format("finite and > --band-low-hz = {}", o.band_low_hz));
    }
    sh::SiOptions si;
    si.frequency_low_rad_s = hz_to_rad_s(o.band_low_hz);
    si.frequency_high_rad_s = hz_to_rad_s(o.band_high_hz);
    si.impulses = o.si_impulses;
    si.constraint_points = o.si_points;
    req.si = si;
  } else if (given(o.band_low_option) || given(o.band_high_option)) {
    throw InvalidArgument(fmt::format("{}: --band-low-hz/--band-high-hz apply only to --method si", command));
  }
  if (method == sh::Method::custom) {
    if (!given(o.impulses_option)) {
      throw InvalidArgument(fmt::format("{}: method custom needs --impulses \"t1:a1,t2:a2,...\"", command));
    }
    req.impulses = sh::parse_impulses(o.impulses);
  } else if (given(o.impulses_option)) {
    throw InvalidArgument(fmt::format("{}: --impulses applies only to --method custom", command));
  }
  std::optional<sh::Mode> second;
  if (given(o.second_frequency_option)) {
    require_positive("--second-frequency-hz", o.second_frequency_hz);
    if (!given(o.second_zeta_option)) {
      throw InvalidArgument(fmt::format("{}: --second-zeta is required with --second-frequency-hz", command));
    }
    second = sh::Mode::from_hz(o.second_frequency_hz, o.second_zeta);
    req.second_mode = second;
  } else if (given(o.second_zeta_option)) {
    throw InvalidArgument(fmt::format("{}: --second-zeta needs --second-frequency-hz", command));
  }
  DesignedShaper out{sh::design(req), mode, second};
  if (!out.shaper.is_positive()) {
    fmt::print(stderr,
               "clearshape {}: warning: the {} shaper has negative impulses: it reverses the commanded "
               "acceleration, and in a joint with clearance that makes the link cross the play and "
               "impact. Prefer a positive shaper (zvd, zvdd, ei) for such joints.\n",
               command, out.shaper.method());
  }
  return out;
}

nlohmann::ordered_json mode_json(const sh::Mode& mode) {
  return {{"frequency_hz", mode.natural_frequency_hz()},
          {"natural_frequency_rad_s", mode.natural_frequency_rad_s},
          {"zeta", mode.damping_ratio}};
}

nlohmann::ordered_json band_json(const sh::InsensitivityBand& band, const sh::Mode& mode, double vtol) {
  return {{"vtol", vtol},
          {"width", band.width()},
          {"ratio_low", band.ratio_low},
          {"ratio_high", band.ratio_high},
          {"frequency_low_hz", band.ratio_low * mode.natural_frequency_hz()},
          {"frequency_high_hz", band.ratio_high * mode.natural_frequency_hz()}};
}

namespace {

struct ShapeState {
  ShaperOptions shaper;
  bool json = false;
  std::string input;
  std::string column;
  std::string time_column = "time_s";
  std::string output;
  bool no_extend = false;
  std::string discretization = "linear";
  CLI::Option* input_option = nullptr;
  // --export FORMAT --sample-time S [--export-name NAME] [--export-axis x|y|xy] [-o FILE]
  std::string export_format;
  double sample_time_s = 0.0;
  std::string export_name = "cs_shaper";
  std::string export_axis = "xy";
  CLI::Option* export_option = nullptr;
  CLI::Option* sample_time_option = nullptr;
  CLI::Option* export_name_option = nullptr;
  CLI::Option* export_axis_option = nullptr;
  CLI::Option* discretization_option = nullptr;
  // --grid-hz F: the drive takes a new command only every 1/F s; the shaper is snapped to that grid.
  double grid_hz = 0.0;
  CLI::Option* grid_option = nullptr;
};

// The designed shaper as the drive applies it (--grid-hz), and the design itself beside it.
struct AppliedShaper {
  DesignedShaper applied;
  std::optional<sh::Shaper> designed;  ///< set with --grid-hz: the off-grid design
};

AppliedShaper design_applied(const ShapeState& st) {
  DesignedShaper d = design_from_options(st.shaper, "shape");
  if (!given(st.grid_option)) return {std::move(d), std::nullopt};
  std::optional<sh::Shaper> designed = d.shaper;
  d.shaper = sh::on_update_grid(d.shaper, 1.0 / st.grid_hz);
  return {std::move(d), std::move(designed)};
}

// The options that regenerate the design and its export (written into the exported file).
std::string regenerate_command(const ShapeState& st) {
  const ShaperOptions& o = st.shaper;
  std::string c = "clearshape shape --method " + o.method;
  if (given(o.frequency_option)) c += fmt::format(" --frequency-hz {}", o.frequency_hz);
  if (given(o.wn_option)) c += fmt::format(" --wn {}", o.wn_rad_s);
  if (given(o.zeta_option)) c += fmt::format(" --zeta {}", o.zeta);
  const sh::Method m = sh::method_from_string(o.method);
  if (m == sh::Method::ei || m == sh::Method::ei2 || m == sh::Method::ei3 || m == sh::Method::si) {
    c += fmt::format(" --vtol {}", o.vtol);
  }
  if (given(o.band_low_option)) c += fmt::format(" --band-low-hz {} --band-high-hz {}", o.band_low_hz, o.band_high_hz);
  if (given(o.impulses_option)) c += fmt::format(" --impulses \"{}\"", o.impulses);
  if (given(o.second_frequency_option)) {
    c += fmt::format(" --second-frequency-hz {} --second-zeta {}", o.second_frequency_hz, o.second_zeta);
  }
  c += " --export " + st.export_format;
  if (given(st.sample_time_option)) c += fmt::format(" --sample-time {}", st.sample_time_s);
  if (given(st.discretization_option)) c += " --discretization " + st.discretization;
  if (given(st.export_name_option)) c += " --export-name " + st.export_name;
  if (given(st.export_axis_option)) c += " --export-axis " + st.export_axis;
  if (given(st.grid_option)) c += fmt::format(" --grid-hz {}", st.grid_hz);
  return c;
}

// `shape --export`: the design in a form a controller loads (docs/export.md). Validates the
// export options before designing, writes -o atomically (or prints to stdout).
void run_export(const ShapeState& st) {
  const exports::Format format = exports::format_from_string(st.export_format);
  if (given(st.input_option)) {
    throw InvalidArgument("shape: --export writes the shaper for a controller; shape a CSV (--input) in a separate call");
  }
  if (st.json) throw InvalidArgument("shape: --json prints the design; with --export use --export json");
  const bool sampled = format == exports::Format::json || format == exports::Format::c_header;
  if (sampled) {
    if (!given(st.sample_time_option)) {
      throw InvalidArgument(fmt::format("shape: --export {} needs --sample-time S: the controller's sample period in "
                                        "seconds, > 0 (e.g. 0.001 for 1 kHz)", st.export_format));
    }
    require_positive("--sample-time", st.sample_time_s, "The controller's sample period in seconds (e.g. 0.001 for 1 kHz).");
  } else {
    if (given(st.sample_time_option) || given(st.discretization_option)) {
      throw InvalidArgument(fmt::format("shape: --sample-time and --discretization apply to --export json and c-header; "
                                        "{} shapes on its own step timing", st.export_format));
    }
  }
  if (given(st.export_name_option) && format != exports::Format::c_header) {
    throw InvalidArgument("shape: --export-name applies to --export c-header");
  }
  if (given(st.export_axis_option) && format != exports::Format::klipper) {
    throw InvalidArgument("shape: --export-axis applies to --export klipper");
  }
  exports::ExportOptions options;
  options.sample_time_s = st.sample_time_s;
  if (st.discretization == "linear") {
    options.discretization = sh::Discretization::linear;
  } else if (st.discretization == "exact") {
    options.discretization = sh::Discretization::exact_at_mode;
  } else {
    throw InvalidArgument(fmt::format("shape: --discretization = '{}' is not valid; allowed: linear, exact", st.discretization));
  }
  options.c_name = st.export_name;
  options.klipper_axes = st.export_axis;

  const DesignedShaper d = design_applied(st).applied;
  const sh::Method method = sh::method_from_string(st.shaper.method);
  exports::ShaperDesign design{d.shaper, method, d.mode, d.second_mode, std::nullopt, std::nullopt, regenerate_command(st)};
  if (given(st.grid_option)) design.update_grid_hz = st.grid_hz;
  if (method == sh::Method::ei || method == sh::Method::ei2 || method == sh::Method::ei3 || method == sh::Method::si) {
    design.vtol = st.shaper.vtol;
  }
  if (method == sh::Method::si) design.band_hz = std::make_pair(st.shaper.band_low_hz, st.shaper.band_high_hz);
  const exports::ExportText out = exports::export_shaper(design, format, options);
  for (const std::string& note : out.notes) fmt::print(stderr, "clearshape shape: {}\n", note);
  if (st.output.empty()) {
    std::fwrite(out.text.data(), 1, out.text.size(), stdout);
  } else {
    io::write_text_atomic(st.output, out.text);
    fmt::print(stderr, "clearshape shape: wrote {} ({})\n", st.output, st.export_format);
  }
}

// Shapes a CSV column. Output columns: time_s, <column>, <column>_shaped (the suffix is
// appended to the whole input name, unit suffix included: command_deg → command_deg_shaped).
nlohmann::ordered_json shape_csv(const ShapeState& st, const DesignedShaper& d) {
  if (st.column.empty() || st.output.empty()) {
    throw InvalidArgument("shape: --input needs --column NAME and --output FILE.csv");
  }
  const io::Table table = io::read_table(st.input);
  const UniformSeries input = io::series_from_table(table, st.time_column, st.column);
  const bool extend = !st.no_extend;
  UniformSeries shaped;
  if (st.discretization == "linear") {
    shaped = sh::shape_offline(d.shaper, input, extend);
  } else if (st.discretization == "exact") {
    if (!d.mode) throw InvalidArgument("shape: --discretization exact needs the mode (--frequency-hz and --zeta)");
    const auto taps = sh::discretize(d.shaper, input.sample_time_s, sh::Discretization::exact_at_mode, *d.mode);
    shaped = sh::shape_offline(taps, input, extend);
  } else {
    throw InvalidArgument(fmt::format("shape: --discretization = '{}' is not valid; allowed: linear, exact", st.discretization));
  }
  // The original column, held at its last value over the extension.
  std::vector<double> original = input.values;
  original.resize(shaped.values.size(), input.values.empty() ? 0.0 : input.values.back());
  const std::vector<double> time = shaped.times_s();
  const std::string shaped_name = st.column + "_shaped";
  io::write_csv(st.output, {"time_s", st.column, shaped_name}, {&time, &original, &shaped.values});
  fmt::print(stderr, "clearshape shape: wrote {} ({} rows: time_s, {}, {})\n", st.output, time.size(), st.column, shaped_name);
  return {{"input", st.input},
          {"column", st.column},
          {"output", st.output},
          {"shaped_column", shaped_name},
          {"rows", time.size()},
          {"sample_time_s", input.sample_time_s},
          {"discretization", st.discretization},
          {"extended", extend}};
}

// The shape's band and its V at the design mode (when a mode was given).
struct ShapeFigures {
  std::optional<sh::InsensitivityBand> band;
  std::optional<double> v_design;
};

nlohmann::ordered_json shape_document(const ShapeState& st, const AppliedShaper& a, const ShapeFigures& fig,
                                      const nlohmann::ordered_json& csv) {
  const DesignedShaper& d = a.applied;
  const sh::Shaper& s = d.shaper;
  const auto& band = fig.band;
  const auto& v_design = fig.v_design;
  auto doc = io::make_document();
  doc["command"] = "shape";
  doc["method"] = s.method();
  if (d.mode) doc["mode"] = mode_json(*d.mode);
  if (d.second_mode) doc["second_mode"] = mode_json(*d.second_mode);
  const sh::Method m = sh::method_from_string(st.shaper.method);
  if (m == sh::Method::ei || m == sh::Method::ei2 || m == sh::Method::ei3 || m == sh::Method::si) {
    doc["vtol"] = st.shaper.vtol;
  }
  if (m == sh::Method::si) {
    doc["band"] = {{"frequency_low_hz", st.shaper.band_low_hz}, {"frequency_high_hz", st.shaper.band_high_hz}};
  }
  doc["impulses"] = impulses_json(s);
  doc["units"] = impulse_units_json("1 (fraction of the command; sum 1)");
  doc["duration_s"] = s.duration_s();
  doc["positive"] = s.is_positive();
  doc["residual_at_design"] = v_design ? nlohmann::ordered_json(*v_design) : nlohmann::ordered_json(nullptr);
  doc["insensitivity"] = band ? band_json(*band, *d.mode, kReportVtol) : nlohmann::ordered_json(nullptr);
  if (a.designed) {  // the impulses above are on the drive's update grid
    doc["update_grid"] = {{"grid_hz", st.grid_hz},
                          {"update_period_s", 1.0 / st.grid_hz},
                          {"designed_impulses", impulses_json(*a.designed)},
                          {"designed_duration_s", a.designed->duration_s()},
                          {"designed_residual_at_design",
                           d.mode ? nlohmann::ordered_json(sh::residual_vibration(*a.designed, *d.mode)) : nlohmann::ordered_json(nullptr)}};
  }
  if (!csv.is_null()) doc["shaped_csv"] = csv;
  return doc;
}

void print_shape(const ShapeState& st, const AppliedShaper& a, const ShapeFigures& fig) {
  const DesignedShaper& d = a.applied;
  const sh::Shaper& s = d.shaper;
  const auto& band = fig.band;
  const auto& v_design = fig.v_design;
  fmt::print("method      {}\n", s.method());
  if (d.mode) {
    fmt::print("mode        {:.6g} Hz ({:.6g} rad/s), zeta {:.6g}\n", d.mode->natural_frequency_hz(),
               d.mode->natural_frequency_rad_s, d.mode->damping_ratio);
  }
  if (d.second_mode) {
    fmt::print("second mode {:.6g} Hz ({:.6g} rad/s), zeta {:.6g}\n", d.second_mode->natural_frequency_hz(),
               d.second_mode->natural_frequency_rad_s, d.second_mode->damping_ratio);
  }
  if (a.designed) {
    fmt::print("grid        {:.6g} Hz drive updates: each impulse at the nearest update ({:.6g} ms), those on one update merged\n",
               st.grid_hz, 1000.0 / st.grid_hz);
    fmt::print("designed    {} impulses, duration_s {:.9g}{}\n", a.designed->size(), a.designed->duration_s(),
               d.mode ? fmt::format(", V(design) {:.3g}", sh::residual_vibration(*a.designed, *d.mode)) : std::string());
  }
  fmt::print("\n  #        t_s                a\n");
  std::size_t i = 0;
  for (const sh::Impulse& p : s.impulses()) fmt::print("{:3d}  {:>14.9f}  {:>15.12f}\n", ++i, p.time_s, p.amplitude);
  fmt::print("\nduration_s  {:.9g}\n", s.duration_s());
  if (band) {
    fmt::print("V(design)   {:.3g}\n", *v_design);
    fmt::print("insensitivity at V <= 5 %: {:.4f} (r = {:.4f} … {:.4f}; {:.6g} … {:.6g} Hz)\n", band->width(),
               band->ratio_low, band->ratio_high, band->ratio_low * d.mode->natural_frequency_hz(),
               band->ratio_high * d.mode->natural_frequency_hz());
  } else {
    fmt::print("insensitivity: give --frequency-hz and --zeta to evaluate it\n");
  }
}

void run_shape(const ShapeState& st) {
  if (given(st.export_option)) {
    run_export(st);
    return;
  }
  if (given(st.sample_time_option) || given(st.export_name_option) || given(st.export_axis_option)) {
    throw InvalidArgument("shape: --sample-time, --export-name and --export-axis apply to --export FORMAT");
  }
  const AppliedShaper a = design_applied(st);
  const DesignedShaper& d = a.applied;
  const sh::Shaper& s = d.shaper;
  ShapeFigures fig;
  if (d.mode) {
    fig.band = sh::insensitivity(s, *d.mode, kReportVtol);
    fig.v_design = sh::residual_vibration(s, *d.mode);
  }
  nlohmann::ordered_json csv;
  if (!st.input.empty()) {
    csv = shape_csv(st, d);
  } else if (!st.output.empty() || !st.column.empty()) {
    throw InvalidArgument("shape: --output and --column are for shaping a CSV column; give --input FILE.csv");
  }

  if (st.json) {
    print_json(shape_document(st, a, fig, csv));
    return;
  }
  print_shape(st, a, fig);
}

const bool shape_registered = register_command(
    {"shape", "Design an input shaper (zv, zvd, zvdd, …, ei, si, custom) and optionally shape a CSV column", 20,
     [](CLI::App& sub) {
       auto st = std::make_shared<ShapeState>();
       add_shaper_options(sub, st->shaper);
       sub.add_flag("--json", st->json, "Print a JSON document instead of the table");
       st->input_option = sub.add_option("--input,-i", st->input, "Shape a column of this CSV (uniform time column)");
       sub.add_option("--column", st->column, "Column of --input to shape");
       sub.add_option("--time-column", st->time_column, "Time column of --input (s)")->capture_default_str();
       sub.add_option("--output,-o", st->output,
                      "CSV to write: time_s, <column>, <column>_shaped; with --export, the exported file (default stdout)");
       sub.add_flag("--no-extend", st->no_extend, "Keep the input length (default: extend by the shaper's duration)");
       st->discretization_option =
           sub.add_option("--discretization", st->discretization,
                          "Impulses between samples: linear (first-order hold) or exact (Murphy-Watanabe at the mode)")
               ->capture_default_str();
       st->export_option = sub.add_option("--export", st->export_format,
                                          "Export the shaper for a controller: json, c-header, klipper, rrf (docs/export.md)");
       st->sample_time_option = sub.add_option("--sample-time", st->sample_time_s,
                                               "--export json/c-header: the controller's sample period (s), > 0");
       st->export_name_option = sub.add_option("--export-name", st->export_name,
                                               "--export c-header: prefix of the C identifiers")->capture_default_str();
       st->export_axis_option = sub.add_option("--export-axis", st->export_axis,
                                               "--export klipper: the axes to configure: x, y or xy")->capture_default_str();
       st->grid_option = sub.add_option("--grid-hz", st->grid_hz,
                                        "The drive takes a new command only at updates of this rate (Hz; the thesis's "
                                        "pulse-train drive: 30): the shaper is snapped to that grid for the table, "
                                        "--json, --input and every --export; omit for none")
                             ->check(positive_at_most(1e6, "Hz", "--grid-hz"));
       sub.footer(
           "Examples:\n"
           "  clearshape shape --method zvdd --frequency-hz 3.32 --zeta 0.288\n"
           "  clearshape shape --method ei --vtol 0.05 --frequency-hz 10 --zeta 0.1 --json\n"
           "  clearshape shape --method si --frequency-hz 10 --zeta 0.05 --band-low-hz 8 --band-high-hz 12\n"
           "  clearshape shape --method custom --impulses \"0:0.5,0.05:0.5\"\n"
           "  clearshape shape --method zvd -f 3.3 -z 0.29 -i run.csv --column command_deg -o shaped.csv\n"
           "  clearshape shape --method zvd -f 10 -z 0.1 --export c-header --sample-time 0.001 -o zvd.h\n"
           "  clearshape shape --method mzv -f 42.5 -z 0.1 --export klipper\n"
           "  clearshape shape --method clearance-aware --model fit.json --moves 5,10,20 --max-duration-s 0.3\n"
           "  clearshape shape --method take-up --model fit.json --moves 5,10,20");
       auto ca = std::make_shared<ClearanceAwareOptions>();
       add_clearance_aware_options(sub, *ca);
       sub.callback([st, ca] {
         const std::string& method = st->shaper.method;
         if (method == "clearance-aware" || method == "take-up") {  // designed on a clearance model
           if (given(st->export_option) || !st->input.empty() || given(st->grid_option)) {  // never silently ignored
             throw InvalidArgument(fmt::format("shape: --method {} designs and prints impulses; export, apply or snap (--grid-hz) them "
                                               "with --method custom --impulses T:A,… (the impulses it printed)",
                                               method));
           }
           const ShaperOptions& o = st->shaper;
           const double f_hz = given(o.frequency_option) ? o.frequency_hz
                               : given(o.wn_option)     ? o.wn_rad_s / (2.0 * M_PI)
                                                        : 0.0;
           if (method == "take-up") {
             run_take_up(*ca, f_hz, o.zeta, st->json);
           } else {
             run_clearance_aware(*ca, f_hz, o.zeta, st->json);
           }
           return;
         }
         if (clearance_aware_options_given(*ca)) {
           throw InvalidArgument("shape: --model, --moves, --max-duration-s, --max-evaluations and --threads apply "
                                 "to --method clearance-aware (and the first three to take-up)");
         }
         run_shape(*st);
       });
     }});

}  // namespace

}  // namespace clearshape::cli
