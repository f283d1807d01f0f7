#pragma once
// A shaper as a drive that takes a new command only at its own updates applies it: every impulse
// moved to the nearest update instant k·T, impulses landing on the same update merged.
//
//   const shaping::Shaper applied = shaping::on_update_grid(designed, 1.0 / 30.0);  // 30 Hz drive
#include "clearshape/shaping/shaper.hpp"

namespace clearshape::shaping {

/// The shaper on an update grid of period update_period_s: impulse i goes to
/// round(tᵢ/T)·T (halves away from zero), impulses that land on the same update are summed into
/// one, ΣA is kept (1 for a designed shaper) and so is the method name. The first impulse of a
/// designed shaper (t = 0) stays at 0; a shaper shorter than T/2 becomes one impulse (the
/// identity). A merged amplitude may be 0 for a shaper with negative impulses (it is kept).
/// Throws InvalidArgument for a period that is not finite and > 0, or so fine that
/// duration/T exceeds 2⁵² (the grid index is then not exact in a double).
Shaper on_update_grid(const Shaper& shaper, double update_period_s);

}  // namespace clearshape::shaping
