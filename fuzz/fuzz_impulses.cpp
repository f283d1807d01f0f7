// Fuzz target: the impulse-list parser of `shape --method custom --impulses "t:a,…"`, then what
// `shape` does with the shaper it accepted: its residual vibration and 5 % insensitivity band
// at a design mode (10 Hz, ζ = 0.05, as `shape --frequency-hz 10 --zeta 0.05`).
#include <numbers>

#include "clearshape/shaping/design.hpp"
#include "clearshape/shaping/residual.hpp"
#include "fuzz_common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace clearshape;
  fuzz::expect_clean_rejection([&] {
    shaping::DesignRequest req;
    req.method = shaping::method_from_string("custom");
    req.impulses = shaping::parse_impulses(fuzz::as_text(data, size));
    const shaping::Shaper shaper = shaping::design(req);
    const shaping::Mode mode{2.0 * std::numbers::pi * 10.0, 0.05};
    (void)shaping::residual_vibration(shaper, mode);
    (void)shaping::insensitivity(shaper, mode, 0.05);
  });
  return 0;
}
