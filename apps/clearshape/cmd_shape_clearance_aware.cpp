#include "cmd_shape_clearance_aware.hpp"

#include <chrono>
#include <optional>
#include <string>

#include <fmt/format.h>

#include "clearshape/study/clearance_model_json.hpp"
#include "clearshape/core/error.hpp"
#include "clearshape/core/units.hpp"
#include "clearshape/io/json.hpp"
#include "clearshape/shaping/design.hpp"
#include "clearshape/study/clearance_aware.hpp"
#include "command.hpp"

namespace clearshape::cli {

void add_clearance_aware_options(CLI::App& sub, ClearanceAwareOptions& o) {
  o.model_option = sub.add_option("--model", o.model,
                                  "clearance-aware: the identified nonlinear model — `fit-clearance --json` output or a "
                                  "study's results.json");
  o.moves_option = sub.add_option("--moves", o.moves, "clearance-aware: step amplitudes to design for (deg), e.g. 5,10,20")
                       ->delimiter(',');
  o.max_duration_option = sub.add_option("--max-duration-s", o.max_duration_s,
                                         "clearance-aware: the longest shaper (s); default: ZVDD's for the mode "
                                         "(--frequency-hz/--zeta, else the model file's link mode)");
  o.max_evaluations_option = sub.add_option("--max-evaluations", o.max_evaluations,
                                            "clearance-aware: objective evaluations (each simulates every move and "
                                            "uncertainty point), >= 10")
                                 ->capture_default_str();
  o.threads_option = sub.add_option("--threads", o.threads, "clearance-aware: parallel simulations (0: all cores)")
                         ->capture_default_str();
}

bool clearance_aware_options_given(const ClearanceAwareOptions& o) {
  for (const CLI::Option* opt : {o.model_option, o.moves_option, o.max_duration_option, o.max_evaluations_option,
                                 o.threads_option}) {
    if (opt != nullptr && opt->count() > 0) return true;
  }
  return false;
}

study::IdentifiedClearanceModel read_design_model(const ClearanceAwareOptions& o, const std::string& method) {
  if (o.model.empty()) {
    throw InvalidArgument(fmt::format("shape: --method {} needs --model FILE (fit-clearance --json output or a "
                                      "study's results.json)", method));
  }
  if (o.moves.empty()) throw InvalidArgument(fmt::format("shape: --method {} needs --moves A1,A2,… (deg)", method));
  return study::read_clearance_model_json(o.model);
}

double design_duration_bound(const ClearanceAwareOptions& o, const study::IdentifiedClearanceModel& identified,
                             double frequency_hz, double zeta, const std::string& method, std::string& source) {
  if (o.max_duration_option != nullptr && o.max_duration_option->count() > 0) {
    require_in_closed("--max-duration-s", o.max_duration_s, 1e-3, 5.0);
    source = "--max-duration-s";
    return o.max_duration_s;
  }
  std::optional<shaping::Mode> mode;
  if (frequency_hz > 0.0) {
    mode = shaping::Mode::from_hz(frequency_hz, zeta);
    source = "ZVDD of --frequency-hz/--zeta";
  } else if (identified.link_frequency_hz && identified.link_damping_ratio) {
    mode = shaping::Mode::from_hz(*identified.link_frequency_hz, *identified.link_damping_ratio);
    source = "ZVDD of the model file's link mode";
  } else {
    throw InvalidArgument(fmt::format("shape: --method {} needs a duration bound: --max-duration-s S, or "
                                      "--frequency-hz/--zeta of the linear shaper's mode (ZVDD's duration)", method));
  }
  shaping::DesignRequest zvdd;
  zvdd.method = shaping::Method::zvdd;
  zvdd.mode = *mode;
  return shaping::design(zvdd).duration_s();
}

nlohmann::ordered_json impulse_json(double time_s, double amplitude) {
  return {{"time_s", time_s}, {"amplitude", amplitude}};
}

nlohmann::ordered_json impulses_json(const shaping::Shaper& shaper) {
  nlohmann::ordered_json impulses = nlohmann::ordered_json::array();
  for (const auto& p : shaper.impulses()) impulses.push_back(impulse_json(p.time_s, p.amplitude));
  return impulses;
}

nlohmann::ordered_json impulse_units_json(const std::string& amplitude_unit) {
  return {{"time_s", "s"}, {"amplitude", amplitude_unit}};
}

std::string custom_impulses_argument(const shaping::Shaper& shaper) {
  std::string out;
  for (const auto& p : shaper.impulses()) {
    out += fmt::format("{}{:.9g}:{:.12g}", out.empty() ? "" : ",", p.time_s, p.amplitude);
  }
  return out;
}

nlohmann::ordered_json design_document(const ClearanceAwareOptions& o, const std::string& method, double max_duration_s,
                                       const std::string& bound_source) {
  auto doc = io::make_document();
  doc["command"] = "shape";
  doc["method"] = method;
  doc["model_file"] = o.model;
  doc["moves_deg"] = o.moves;
  doc["max_duration_s"] = max_duration_s;
  doc["max_duration_source"] = bound_source;
  return doc;
}

void run_clearance_aware(const ClearanceAwareOptions& o, double frequency_hz, double zeta, bool json) {
  const study::IdentifiedClearanceModel identified = read_design_model(o, "clearance-aware");
  if (o.max_evaluations < 10) throw_invalid("--max-evaluations", o.max_evaluations, ">= 10");
  if (o.threads < 0 || o.threads > 256) throw_invalid("--threads", o.threads, "0 … 256 (0: all cores)");
  study::ClearanceAwareRequest request;
  request.model = identified.model;
  request.moves = o.moves;
  request.max_evaluations = o.max_evaluations;
  request.threads = o.threads;
  // A study's results.json carries the fit's 1σ and the flank damping's run spread: the same set
  // the study's own design uses (study::design_uncertainty).
  if (identified.sigma) request.uncertainty = study::design_uncertainty(*identified.sigma);
  std::string bound_source;
  request.max_duration_s = design_duration_bound(o, identified, frequency_hz, zeta, "clearance-aware", bound_source);
  const auto begin = std::chrono::steady_clock::now();
  const study::ClearanceAwareResult r = study::design_clearance_aware(request);
  if (r.worse_than_unshaped) {  // issue 19: never offered without a warning
    fmt::print(stderr,
               "warning: the clearance-aware design leaves a case WORSE than unshaped on the model (worst {:.3g} % of "
               "its unshaped MD); do not use it as it is — widen --max-duration-s or refit the model\n",
               100.0 * r.worst_ratio);
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();

  const std::string impulses_arg = custom_impulses_argument(r.shaper);
  if (json) {
    auto doc = design_document(o, "clearance-aware", request.max_duration_s, bound_source);
    doc["impulses"] = impulses_json(r.shaper);
    doc["units"] = impulse_units_json("1 (fraction of the command; sum 1)");
    doc["custom_impulses"] = impulses_arg;  // `shape --method custom --impulses …` (and --export)
    doc["duration_s"] = r.shaper.duration_s();
    doc["positive"] = r.shaper.is_positive();
    doc["objective"] = r.objective;
    doc["worst_md_deg"] = r.worst_md_deg;
    doc["worst_unshaped_md_deg"] = r.worst_unshaped_md_deg;
    nlohmann::ordered_json cases = nlohmann::ordered_json::array();
    for (const auto& c : r.cases) {
      cases.push_back({{"move_deg", c.move},
                       {"play_factor", c.point.play_factor},
                       {"stiffness_factor", c.point.stiffness_factor},
                       {"coulomb_factor", c.point.coulomb_factor},
                       {"damping_factor", c.point.damping_factor},
                       {"initial_play_fraction", c.point.initial_play_fraction},
                       {"md_unshaped_deg", c.md_unshaped_deg},
                       {"md_shaped_deg", c.md_shaped_deg}});
    }
    doc["cases"] = cases;
    doc["worst_ratio"] = r.worst_ratio;
    doc["worse_than_unshaped"] = r.worse_than_unshaped;
    doc["evaluations"] = r.evaluations;
    doc["termination"] = r.termination;
    doc["design_time_s"] = seconds;
    print_json(doc);
    return;
  }
  fmt::print("method      clearance-aware (on the model of {})\n", o.model);
  const bool flores = request.model.contact_law == study::ContactLawChoice::flores;
  fmt::print("model       play {:.4g} deg, K {:.4g} N·m/rad^{:.3g}, {} {:.4g}{}, J {:.4g} kg·m², drive {}\n",
             rad_to_deg(request.model.play_rad), request.model.stiffness, request.model.exponent, flores ? "Flores e" : "D",
             flores ? request.model.restitution : request.model.damping, flores ? "" : " N·m·s/rad",
             request.model.link_inertia_kg_m2, request.model.drive.code());
  fmt::print("bound       {:.6g} s ({})\n\n  #        t_s                a\n", request.max_duration_s, bound_source);
  std::size_t i = 0;
  for (const auto& p : r.shaper.impulses()) fmt::print("{:3d}  {:>14.9f}  {:>15.12f}\n", ++i, p.time_s, p.amplitude);
  fmt::print("\nduration_s  {:.9g}\n\n  move_deg  play×  K×  c×  D×  phi0/beta  MD unshaped (deg)  MD shaped (deg)\n",
             r.shaper.duration_s());
  for (const auto& c : r.cases) {
    fmt::print("  {:>8.4g}  {:>5.3g}  {:>3.3g}  {:>3.3g}  {:>4.3g}  {:>9.3g}  {:>17.5g}  {:>15.5g}{}\n", c.move,
               c.point.play_factor, c.point.stiffness_factor, c.point.coulomb_factor, c.point.damping_factor,
               c.point.initial_play_fraction, c.md_unshaped_deg,
               c.md_shaped_deg, c.md_shaped_deg > c.md_unshaped_deg ? "  WORSE than unshaped" : "");
  }
  fmt::print("\nworst MD    {:.5g} deg (unshaped {:.5g} deg); worst case keeps {:.3g} % of its unshaped MD\n",
             r.worst_md_deg, r.worst_unshaped_md_deg, 100.0 * r.worst_ratio);
  fmt::print("search      {} evaluations, {} ({:.3g} s)\n", r.evaluations, r.termination, seconds);
  fmt::print("as custom   --method custom --impulses \"{}\"\n", impulses_arg);
}

}  // namespace clearshape::cli
