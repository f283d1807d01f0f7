#pragma once
// Shaper design from a vibration mode (ωn, ζ). Every function validates at the boundary:
// ωn finite and > 0; ζ in [0, 1) (ζ >= 1: the mode is not oscillatory, shaping would be the
// identity — identify the link's residual mode instead, see `clearshape modes`); Vtol in (0, 1).
#include <optional>
#include <string_view>
#include <vector>

#include "clearshape/shaping/shaper.hpp"

namespace clearshape::shaping {

enum class Method { zv, zvd, zvdd, zvddd, mzv, ei, ei2, ei3, si, um_zv, custom };

std::string_view to_string(Method method) noexcept;
/// Parses a CLI method name (zv, zvd, zvdd, zvddd, mzv, ei, ei2, ei3, si, um-zv, custom).
/// Throws InvalidArgument listing the allowed names.
Method method_from_string(std::string_view name);
/// All method names, in the order above.
std::vector<std::string_view> method_names();

/// ZV with n derivative constraints: n = 0 ZV, 1 ZVD, 2 ZVDD, 3 ZVDDD, …
/// Amplitudes C(n+1,k)·K^k / (1+K)^(n+1) at k·π/ωd (Eq. 2.22–2.26; Singer & Seering 1990).
Shaper design_zv_derivatives(const Mode& mode, int derivatives);
Shaper design_zv(const Mode& mode);
Shaper design_zvd(const Mode& mode);
Shaper design_zvdd(const Mode& mode);
Shaper design_zvddd(const Mode& mode);
/// Modified ZV: three impulses over 0.75·Td, 1:√2:1 undamped, k-th scaled by Km^k with
/// Km = exp(−0.75·ζπ/√(1−ζ²)) — largest impulse first (avoids RRF's reversed order).
Shaper design_mzv(const Mode& mode);
/// Extra-insensitive shapers (Singhose et al. 1996/1997) with V(design) = vtol.
Shaper design_ei(const Mode& mode, double vtol = 0.05);
Shaper design_ei2(const Mode& mode, double vtol = 0.05);  ///< two-hump EI
Shaper design_ei3(const Mode& mode, double vtol = 0.05);  ///< three-hump EI

/// Specified-insensitivity shaper: the shortest positive shaper with V <= vtol over
/// [frequency_low_rad_s, frequency_high_rad_s] at the mode's damping (Singhose et al. 1996),
/// solved as a constrained optimisation with NLopt.
struct SiOptions {
  double frequency_low_rad_s = 0.0;
  double frequency_high_rad_s = 0.0;
  double vtol = 0.05;
  int impulses = 0;           ///< 0 = choose from the required insensitivity
  int constraint_points = 60; ///< frequencies at which V <= vtol is enforced
};
Shaper design_si(const Mode& mode, const SiOptions& options);

/// Unity-magnitude ZV: impulses of ±1, shortest negative shaper. It reverses the commanded
/// acceleration: in a joint with clearance that makes the link cross the play and impact.
Shaper design_um_zv(const Mode& mode);

/// Multi-mode shaper by convolution (Crain, Singhose & Seering 1996): impulses at every sum of
/// times, amplitudes multiplied; coincident times (within tolerance_s) merged.
Shaper convolve(const Shaper& a, const Shaper& b, double tolerance_s = 1e-9);

/// Dispatcher used by the CLI. `vtol` applies to ei/ei2/ei3/si; `si` needs the band.
struct DesignRequest {
  Method method = Method::zvd;
  Mode mode{};
  double vtol = 0.05;
  std::optional<SiOptions> si;
};
Shaper design(const DesignRequest& request);

}  // namespace clearshape::shaping
