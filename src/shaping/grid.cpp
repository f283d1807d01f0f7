#include "clearshape/shaping/grid.hpp"

#include <cmath>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "clearshape/core/error.hpp"

namespace clearshape::shaping {

// A position-mode drive takes a new pulse frequency only at its updates (30 Hz in the thesis,
// Gündüzalp 2015 §3.2), so the impulses it applies sit on that grid.
Shaper on_update_grid(const Shaper& shaper, double update_period_s) {
  require_positive("update grid: update_period_s", update_period_s,
                   "The drive's update period in seconds (1 / its update rate; e.g. 1/30 for 30 Hz).");
  constexpr double kMaxIndex = 4503599627370496.0;  // 2^52: above it k·T is not an exact grid index
  if (!(shaper.duration_s() / update_period_s <= kMaxIndex)) {
    throw InvalidArgument(fmt::format("update grid: update_period_s = {} s is out of range for a shaper lasting {} s; "
                                      "allowed: > duration / 2^52", update_period_s, shaper.duration_s()));
  }
  std::vector<Impulse> on_grid;
  on_grid.reserve(shaper.size());
  for (const Impulse& i : shaper.impulses()) {
    const double t = std::round(i.time_s / update_period_s) * update_period_s;
    if (!on_grid.empty() && std::abs(on_grid.back().time_s - t) < 0.5 * update_period_s) {
      on_grid.back().amplitude += i.amplitude;
    } else {
      on_grid.push_back({t, i.amplitude});
    }
  }
  return Shaper(shaper.method(), std::move(on_grid), Shaper::Normalize::no);
}

}  // namespace clearshape::shaping
