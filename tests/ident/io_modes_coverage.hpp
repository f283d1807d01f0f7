#pragma once
// Coverage of the 1σ that `modes` reports on the two-resonance input/output record
// (free_decay.hpp two_resonance_record: 4 Hz ζ 0.02, 11 Hz ζ 0.05): per parameter, the seeded
// records whose truth lies within ±1σ and ±2σ of the estimate. Shared by the white-noise and the
// coloured-noise coverage tests; each states its own binomial band.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <limits>
#include <vector>

#include "clearshape/core/error.hpp"
#include "clearshape/ident/modes.hpp"

namespace clearshape::testing {

inline constexpr double kIoTrueHz[2] = {4.0, 11.0};
inline constexpr double kIoTrueZeta[2] = {0.02, 0.05};
inline constexpr const char* kIoCoverageNames[4] = {"4 Hz f", "4 Hz zeta", "11 Hz f", "11 Hz zeta"};

/// Per parameter (mode 1 f, mode 1 ζ, mode 2 f, mode 2 ζ): records with |estimate − truth| ≤ kσ.
struct IoCovered {
  std::size_t one_sigma[4] = {0, 0, 0, 0};
  std::size_t two_sigma[4] = {0, 0, 0, 0};
  std::size_t records = 0;
};

/// The reported mode nearest `hz` and within `max_offset_hz` of it (none: unreported).
inline const ident::ModeEstimate* mode_near(const std::vector<ident::ModeEstimate>& modes, double hz,
                                            double max_offset_hz) {
  const ident::ModeEstimate* best = nullptr;
  for (const auto& m : modes) {
    const double d = std::abs(m.natural_frequency_hz() - hz);
    if (d < max_offset_hz && (best == nullptr || d < std::abs(best->natural_frequency_hz() - hz))) best = &m;
  }
  return best;
}

/// `records` seeded records from `first_seed`, identified with two modes on a diagram up to order
/// 12; a mode not found within `max_offset_hz` of its truth covers nothing, as does a NaN σ.
inline IoCovered io_modes_coverage(std::uint64_t first_seed, std::size_t records,
                                   const std::function<ident::Experiment(std::uint64_t)>& record,
                                   double max_offset_hz = std::numeric_limits<double>::infinity()) {
  IoCovered c;
  ident::ModeOptions o;
  o.modes = 2;
  o.stabilisation.max_order = 12;  // two modes: a diagram up to order 12 (--max-order 12) holds them
  const auto count = [&c](std::size_t k, double error, double sigma) {
    c.one_sigma[k] += std::abs(error) <= sigma ? 1 : 0;
    c.two_sigma[k] += std::abs(error) <= 2.0 * sigma ? 1 : 0;
  };
  for (std::uint64_t seed = first_seed; seed < first_seed + records; ++seed) {
    ++c.records;
    ident::ModeIdentification r;
    try {
      r = ident::identify_modes(record(seed), o);
    } catch (const RuntimeError&) {
      continue;  // no mode found: covers nothing
    }
    for (std::size_t i = 0; i < 2; ++i) {
      const ident::ModeEstimate* m = mode_near(r.modes, kIoTrueHz[i], max_offset_hz);
      if (m == nullptr) continue;
      count(2 * i, m->natural_frequency_hz() - kIoTrueHz[i], m->natural_frequency_std_hz());
      count(2 * i + 1, m->damping_ratio - kIoTrueZeta[i], m->damping_ratio_std);
    }
  }
  for (std::size_t k = 0; k < 4; ++k) {
    std::printf("%-10s within 1 sigma in %zu of %zu records, within 2 sigma in %zu\n", kIoCoverageNames[k],
                c.one_sigma[k], c.records, c.two_sigma[k]);
  }
  return c;
}

}  // namespace clearshape::testing
