// `clearshape shape --method take-up --model FIT.json --moves 5,10,20`: per move, the take-up
// profile on the 30 Hz position grid (study/take_up.hpp; derivation in docs/large-play.md).
#include <chrono>
#include <cmath>
#include <string>

#include <fmt/format.h>

#include "clearshape/core/error.hpp"
#include "clearshape/core/units.hpp"
#include "clearshape/io/json.hpp"
#include "clearshape/study/take_up.hpp"
#include "cmd_shape_clearance_aware.hpp"
#include "command.hpp"

namespace clearshape::cli {

void run_take_up(const ClearanceAwareOptions& o, double frequency_hz, double zeta, bool json) {
  for (const CLI::Option* opt : {o.max_evaluations_option, o.threads_option}) {
    if (opt != nullptr && opt->count() > 0) {
      throw InvalidArgument(fmt::format("shape: {} applies to --method clearance-aware (take-up is a closed form, "
                                        "no search)", opt->get_name()));
    }
  }
  const study::IdentifiedClearanceModel identified = read_design_model(o, "take-up");
  study::TakeUpRequest request;
  request.model = identified.model;
  request.moves = o.moves;
  std::string bound_source;
  request.max_duration_s = design_duration_bound(o, identified, frequency_hz, zeta, "take-up", bound_source);
  if (bound_source != "--max-duration-s") {  // ZVDD's delay as the pulse generator runs it: on its grid
    request.max_duration_s = std::round(request.max_duration_s / request.grid_s) * request.grid_s;
    bound_source += ", on the 30 Hz update grid";
  }
  const auto begin = std::chrono::steady_clock::now();
  const study::TakeUpResult r = study::design_take_up(request);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();

  if (json) {
    auto doc = design_document(o, "take-up", request.max_duration_s, bound_source);
    doc["flank_keeping_deceleration_rad_s2"] = r.flank_keeping_deceleration_rad_s2;
    nlohmann::ordered_json moves = nlohmann::ordered_json::array();
    for (std::size_t i = 0; i < r.moves.size(); ++i) {
      auto m = study::take_up_move_json(r.moves[i]);
      m["custom_impulses"] = custom_impulses_argument(r.moves[i].shaper);
      const double t = r.flank_keeping_move_time_s[i];
      m["flank_keeping_move_time_s"] = std::isfinite(t) ? nlohmann::ordered_json(t) : nlohmann::ordered_json(nullptr);
      moves.push_back(m);
    }
    doc["moves"] = moves;
    doc["units"] = impulse_units_json("1 (fraction of the move; sum 1)");
    doc["design_time_s"] = seconds;
    print_json(doc);
    return;
  }
  fmt::print("method      take-up (on the model of {})\n", o.model);
  fmt::print("model       play {:.4g} deg, J {:.4g} kg·m², Coulomb {:.4g} N·m, drive {}\n",
             rad_to_deg(request.model.play_rad), request.model.link_inertia_kg_m2, request.model.coulomb_n_m,
             request.model.drive.code());
  fmt::print("bound       {:.6g} s ({})\n", request.max_duration_s, bound_source);
  fmt::print("flank keeping: the link stays on its driving flank for decelerations up to c/J = {:.4g} rad/s²\n",
             r.flank_keeping_deceleration_rad_s2);
  for (std::size_t i = 0; i < r.moves.size(); ++i) {
    const auto& m = r.moves[i];
    fmt::print("\nmove {:g} deg: slots (deg/s)", m.move_deg);
    for (const double v : m.slot_velocity_deg_s) fmt::print(" {:.5g}", v);
    fmt::print("\n  link leaves the rear flank at {:.4f} s ({:.5g} deg/s), meets the braking flank at {:.4f} s "
               "after taking up {:.4g} deg (relative rate {:.3g} deg/s)\n",
               m.separation_s, m.link_rate_deg_s, m.contact_s, m.take_up_deg, m.contact_relative_rate_deg_s);
    if (std::isfinite(r.flank_keeping_move_time_s[i])) {
      fmt::print("  flank keeping instead: {:.3g} s (2·sqrt(θ/(c/J)))\n", r.flank_keeping_move_time_s[i]);
    } else {
      fmt::print("  flank keeping instead: never (the model has no friction to hold the link on its flank)\n");
    }
    fmt::print("  as custom --method custom --impulses \"{}\"\n", custom_impulses_argument(m.shaper));
  }
  fmt::print("\ndesign      {:.3g} s\n", seconds);
}

}  // namespace clearshape::cli
