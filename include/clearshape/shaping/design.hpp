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
/// Km = exp(−0.75·ζπ/√(1−ζ²)), so the first impulse exceeds the last (RRF reversed them).
Shaper design_mzv(const Mode& mode);
/// Extra-insensitive shapers (Singhose et al. 1994/1996/1997). Defined by their V(r) curve
/// (r = ω/ωn, design damping, t1 = 0, ΣA = 1; "zero" = both sums of Eq. 2.20 vanish):
///   EI  (3 impulses): a hump at r = 1 with V(1) = vtol, dV/dω = 0; zeros at r1 < 1 < r2.
///   EI2 (4 impulses): V(1) = 0; zeros r1 < 1 < r2; humps of height vtol in (r1,1) and (1,r2).
///   EI3 (5 impulses): a hump of height vtol at r = 1, two side humps of height vtol, 4 zeros.
/// At ζ = 0 these are Singhose's exact closed forms; for ζ > 0 the square system is solved by
/// continuation in ζ (Singhose's damped curve fits approximate these roots to a few 1e-4).
/// A solution exists up to a damping that falls with vtol (at vtol = 0.05: EI ≈ 0.69,
/// EI2 ≈ 0.44, EI3 ≈ 0.27); beyond it InvalidArgument names the limit reached.
Shaper design_ei(const Mode& mode, double vtol = 0.05);
Shaper design_ei2(const Mode& mode, double vtol = 0.05);  ///< two-hump EI
Shaper design_ei3(const Mode& mode, double vtol = 0.05);  ///< three-hump EI

/// Specified-insensitivity shaper: the shortest positive shaper with V <= vtol over
/// [frequency_low_rad_s, frequency_high_rad_s] at the mode's damping (Singhose et al. 1996),
/// solved with NLopt's SLSQP (min t_N s.t. ΣA = 1, A in [0, 1], V <= vtol at sampled band
/// frequencies, refined at every local maximum of V), seeded from the closed-form shaper (ZV,
/// EI, EI2, EI3) whose band is closest, and continued in the band ratio. Deterministic. The
/// mode's frequency is not used (only its damping). Throws InvalidArgument for a band wider
/// than a 40-impulse ZV-family shaper covers, RuntimeError when no shaper with the requested
/// impulse count is found. Takes ~0.1–1 s.
struct SiOptions {
  double frequency_low_rad_s = 0.0;
  double frequency_high_rad_s = 0.0;
  double vtol = 0.05;
  int impulses = 0;           ///< 0 = choose from the required insensitivity
  int constraint_points = 60; ///< frequencies at which V <= vtol is enforced
};
Shaper design_si(const Mode& mode, const SiOptions& options);

/// Unity-magnitude ZV: impulses of ±1, shortest negative shaper ([1, −1, 1] at [0, T/6, T/3]
/// undamped; for ζ > 0 the times solve Eq. 2.20 by continuation in ζ). It reverses the commanded
/// acceleration: in a joint with clearance that makes the link cross the play and impact.
Shaper design_um_zv(const Mode& mode);

/// Multi-mode shaper by convolution (Crain, Singhose & Seering 1996): impulses at every sum of
/// times, amplitudes multiplied; coincident times (within tolerance_s) merged. V of the result
/// is the product of the factors' V. Method name "a*b".
Shaper convolve(const Shaper& a, const Shaper& b, double tolerance_s = 1e-9);

/// Parses a custom impulse list "t1:a1,t2:a2,…" (times in seconds; spaces allowed). Throws
/// InvalidArgument naming the offending entry (not a number, not finite, amplitude 0).
std::vector<Impulse> parse_impulses(std::string_view text);

/// Dispatcher used by the CLI. `vtol` applies to ei/ei2/ei3/si; `si` needs the band.
struct DesignRequest {
  Method method = Method::zvd;
  Mode mode{};
  double vtol = 0.05;
  std::optional<SiOptions> si;
  std::vector<Impulse> impulses;    ///< Method::custom: the impulses (normalised to ΣA = 1)
  std::optional<Mode> second_mode;  ///< convolve with the same method designed for this mode
};
Shaper design(const DesignRequest& request);

}  // namespace clearshape::shaping
