// Zero-vibration shapers: ZV, ZVD, ZVDD, … (Eq. 2.22–2.26) and modified ZV (MZV).
#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "clearshape/core/error.hpp"
#include "clearshape/shaping/design.hpp"
#include "design_detail.hpp"

namespace clearshape::shaping {

namespace {
constexpr int kMaxDerivatives = 38;  // 40 impulses

std::string zv_name(int derivatives) {
  return derivatives == 0 ? std::string("zv") : "zv" + std::string(static_cast<std::size_t>(derivatives), 'd');
}
}  // namespace

// Eq. 2.22–2.26 generalised (Singer & Seering 1990): the n-th derivative constraint gives the
// binomial amplitudes C(n+1, k)·K^k / (1+K)^(n+1) at t_k = k·π/ωd, K from Eq. 2.24.
Shaper design_zv_derivatives(const Mode& mode, int derivatives) {
  const std::string name = zv_name(std::max(0, derivatives));
  if (derivatives < 0 || derivatives > kMaxDerivatives) {
    throw_invalid("zv: derivatives", derivatives, fmt::format("0 … {} (0 = ZV, 1 = ZVD, 2 = ZVDD)", kMaxDerivatives));
  }
  detail::validate_mode(mode, name);
  const double K = detail::half_period_decay(mode.damping_ratio);
  const double half_period_s = std::numbers::pi / mode.damped_frequency_rad_s();  // Eq. 2.23
  const int n = derivatives + 1;
  std::vector<Impulse> impulses;
  double binomial = 1.0;  // C(n, k)
  double power = 1.0;     // K^k
  for (int k = 0; k <= n; ++k) {
    impulses.push_back({k * half_period_s, binomial * power});
    binomial = binomial * (n - k) / (k + 1);
    power *= K;
  }
  return Shaper(name, std::move(impulses), Shaper::Normalize::yes);  // ΣA = (1+K)^n, Eq. 2.21
}

Shaper design_zv(const Mode& mode) { return design_zv_derivatives(mode, 0); }
Shaper design_zvd(const Mode& mode) { return design_zv_derivatives(mode, 1); }
Shaper design_zvdd(const Mode& mode) { return design_zv_derivatives(mode, 2); }
Shaper design_zvddd(const Mode& mode) { return design_zv_derivatives(mode, 3); }

// Modified ZV (as defined in Klipper's shaper_defs.py): impulses at 0, 0.375·Td, 0.75·Td with
// undamped ratio 1 : √2 : 1, the k-th scaled by Km^k, Km = exp(−0.75ζπ/√(1−ζ²)) — the decay
// over 0.375·Td, not over Td/2. The decaying factors come first-to-last (RRF reversed them).
Shaper design_mzv(const Mode& mode) {
  detail::validate_mode(mode, "mzv");
  const double zeta = mode.damping_ratio;
  const double Km = std::exp(-0.75 * zeta * std::numbers::pi / std::sqrt(1.0 - zeta * zeta));
  const double damped_period_s = 2.0 * std::numbers::pi / mode.damped_frequency_rad_s();
  const double a1 = 1.0 - 1.0 / std::numbers::sqrt2;
  const double a2 = std::numbers::sqrt2 - 1.0;
  return Shaper("mzv",
                {{0.0, a1}, {0.375 * damped_period_s, a2 * Km}, {0.75 * damped_period_s, a1 * Km * Km}},
                Shaper::Normalize::yes);
}

}  // namespace clearshape::shaping
