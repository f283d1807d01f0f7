#pragma once
// Internal: block averaging of a free response before the subspace step (modes, stabilisation).
#include <cstddef>
#include <vector>

namespace clearshape::ident::detail {

/// Block-averaging factor: ≥ 10 samples per period of the highest of the `peaks` dominant
/// spectral peaks (Welch, cycles/sample) whose power is ≥ min_relative_power × the highest peak's,
/// and ≥ max(60, 6·order) averaged samples.
std::size_t choose_decimation(const std::vector<double>& v, std::size_t peaks, std::size_t order,
                              double min_relative_power = 0.0);

/// Means of consecutive blocks of q samples (a last partial block is dropped).
std::vector<double> block_average(const std::vector<double>& y, std::size_t q);

}  // namespace clearshape::ident::detail
