#include "clearshape/dsp/sosfilt.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>
#include <fmt/format.h>

#include "clearshape/core/error.hpp"

namespace clearshape::dsp {

namespace {

// One sample through the cascade, transposed direct form II per section (as scipy's sosfilt):
//   y = b0·x + s0,  s0 ← b1·x − a1·y + s1,  s1 ← b2·x − a2·y.   (sections have a0 = 1)
inline double filter_sample(const std::vector<Section>& sections, SectionState* state,
                            double x) noexcept {
  for (std::size_t i = 0; i < sections.size(); ++i) {
    const Section& s = sections[i];
    SectionState& z = state[i];
    const double y = s.b0 * x + z[0];
    z[0] = s.b1 * x - s.a1 * y + z[1];
    z[1] = s.b2 * x - s.a2 * y;
    x = y;
  }
  return x;
}

void check_state_size(const SosDesign& design, std::size_t size) {
  if (size != design.section_count()) {
    throw InvalidArgument(fmt::format("filter state: {} sections given; the design has {} "
                                      "(one pair of delays per section, scipy zi layout)",
                                      size, design.section_count()));
  }
}

// The recursion over a whole buffer in place, forwards or backwards, for a known number of
// sections: coefficients and delays live in registers and consecutive samples overlap across
// sections. Same operations in the same order as filter_sample (and scipy's sosfilt).
template <std::size_t N>
void filter_in_place_fixed(const Section* sections, SectionState* state, std::span<double> data,
                           bool backwards) noexcept {
  double b0[N], b1[N], b2[N], a1[N], a2[N], z0[N], z1[N];
  for (std::size_t i = 0; i < N; ++i) {
    b0[i] = sections[i].b0, b1[i] = sections[i].b1, b2[i] = sections[i].b2;
    a1[i] = sections[i].a1, a2[i] = sections[i].a2;
    z0[i] = state[i][0], z1[i] = state[i][1];
  }
  auto sample = [&](double x) {
    for (std::size_t i = 0; i < N; ++i) {
      const double y = b0[i] * x + z0[i];
      z0[i] = b1[i] * x - a1[i] * y + z1[i];
      z1[i] = b2[i] * x - a2[i] * y;
      x = y;
    }
    return x;
  };
  if (backwards) {
    for (std::size_t k = data.size(); k-- > 0;) data[k] = sample(data[k]);
  } else {
    for (double& v : data) v = sample(v);
  }
  for (std::size_t i = 0; i < N; ++i) state[i] = {z0[i], z1[i]};
}

// Any number of sections: blocks of samples through one section at a time (registers again).
void filter_in_place_blocks(const std::vector<Section>& sections, std::vector<SectionState>& state,
                            std::span<double> data, bool backwards) noexcept {
  constexpr std::size_t kBlock = 2048;
  const std::size_t n = data.size();
  for (std::size_t start = 0; start < n; start += kBlock) {
    const std::size_t count = std::min(kBlock, n - start);
    const std::span<double> block =
        data.subspan(backwards ? n - start - count : start, count);
    for (std::size_t i = 0; i < sections.size(); ++i) {
      filter_in_place_fixed<1>(&sections[i], &state[i], block, backwards);
    }
  }
}

void filter_in_place(const std::vector<Section>& sections, std::vector<SectionState>& state,
                     std::span<double> data, bool backwards) noexcept {
  const Section* s = sections.data();
  SectionState* z = state.data();
  switch (sections.size()) {
    case 1: return filter_in_place_fixed<1>(s, z, data, backwards);
    case 2: return filter_in_place_fixed<2>(s, z, data, backwards);
    case 3: return filter_in_place_fixed<3>(s, z, data, backwards);
    case 4: return filter_in_place_fixed<4>(s, z, data, backwards);
    case 5: return filter_in_place_fixed<5>(s, z, data, backwards);
    case 6: return filter_in_place_fixed<6>(s, z, data, backwards);
    case 7: return filter_in_place_fixed<7>(s, z, data, backwards);
    case 8: return filter_in_place_fixed<8>(s, z, data, backwards);
    default: return filter_in_place_blocks(sections, state, data, backwards);
  }
}

std::vector<double> run(const SosDesign& design, std::span<const double> input,
                        std::vector<SectionState>& state) {
  std::vector<double> out(input.begin(), input.end());
  filter_in_place(design.sections(), state, out, false);
  return out;
}

}  // namespace

std::vector<SectionState> sosfilt_zi(const SosDesign& design) {
  // Per section, scipy lfilter_zi: solve (I − Aᵀ)·zi = b[1:] − a[1:]·b0 with A the companion
  // matrix of a; then scale by the DC gain of the sections before it (scipy sosfilt_zi).
  std::vector<SectionState> zi;
  zi.reserve(design.section_count());
  double scale = 1.0;
  for (const Section& s : design.sections()) {
    Eigen::Matrix2d i_minus_at;
    i_minus_at << 1.0 + s.a1, -1.0, s.a2, 1.0;
    const Eigen::Vector2d rhs(s.b1 - s.a1 * s.b0, s.b2 - s.a2 * s.b0);
    const Eigen::Vector2d solution = i_minus_at.partialPivLu().solve(rhs);
    zi.push_back({scale * solution[0], scale * solution[1]});
    scale *= (s.b0 + s.b1 + s.b2) / (s.a0 + s.a1 + s.a2);
  }
  return zi;
}

StreamingSosFilter::StreamingSosFilter(const SosDesign& design)
    : design_(design),
      state_(design.section_count(), SectionState{0.0, 0.0}),
      unit_steady_state_(sosfilt_zi(design)) {}

double StreamingSosFilter::step(double input) noexcept {
  last_output_ = filter_sample(design_.sections(), state_.data(), input);
  return last_output_;
}

Status StreamingSosFilter::step(double input, double& output) noexcept {
  if (!std::isfinite(input)) {
    output = last_output_;
    return Status::not_finite;
  }
  output = step(input);
  return Status::ok;
}

void StreamingSosFilter::reset() noexcept {
  std::fill(state_.begin(), state_.end(), SectionState{0.0, 0.0});
  last_output_ = 0.0;
}

void StreamingSosFilter::reset_steady_state(double input) noexcept {
  for (std::size_t i = 0; i < state_.size(); ++i) {
    state_[i] = {unit_steady_state_[i][0] * input, unit_steady_state_[i][1] * input};
  }
  last_output_ = design_.dc_gain() * input;
}

void StreamingSosFilter::set_state(std::span<const SectionState> state) {
  check_state_size(design_, state.size());
  std::copy(state.begin(), state.end(), state_.begin());
}

std::vector<double> sosfilt(const SosDesign& design, std::span<const double> input) {
  std::vector<SectionState> state(design.section_count(), SectionState{0.0, 0.0});
  return run(design, input, state);
}

std::vector<double> sosfilt(const SosDesign& design, std::span<const double> input,
                            std::vector<SectionState>& state) {
  check_state_size(design, state.size());
  return run(design, input, state);
}

std::size_t default_pad_length(const SosDesign& design) noexcept {
  // scipy sosfiltfilt: 3 · (2·n + 1 − min(#(b2 == 0), #(a2 == 0))), compensating first-order
  // sections (roots at the origin) so the pad equals filtfilt's 3·max(len(a), len(b)).
  std::size_t b2_zero = 0;
  std::size_t a2_zero = 0;
  for (const Section& s : design.sections()) {
    b2_zero += s.b2 == 0.0 ? 1 : 0;
    a2_zero += s.a2 == 0.0 ? 1 : 0;
  }
  return 3 * (2 * design.section_count() + 1 - std::min(b2_zero, a2_zero));
}

std::vector<double> sosfiltfilt(const SosDesign& design, std::span<const double> input,
                                const FiltfiltOptions& options) {
  const std::size_t edge = options.pad_type == PadType::none
                               ? 0
                               : options.pad_length.value_or(default_pad_length(design));
  const std::size_t n = input.size();
  if (n <= edge) {
    throw InvalidArgument(fmt::format(
        "sosfiltfilt: the input has {} samples; allowed: more than the pad length {}. Give a "
        "longer signal, a smaller pad_length, or pad_type none", n, edge));
  }
  // Extension (scipy odd_ext / even_ext / const_ext).
  std::vector<double> ext;
  ext.reserve(n + 2 * edge);
  const double first = input.front();
  const double last = input.back();
  for (std::size_t i = 0; i < edge; ++i) {
    const double mirrored = input[edge - i];
    switch (options.pad_type) {
      case PadType::odd: ext.push_back(2.0 * first - mirrored); break;
      case PadType::even: ext.push_back(mirrored); break;
      default: ext.push_back(first); break;
    }
  }
  ext.insert(ext.end(), input.begin(), input.end());
  for (std::size_t i = 0; i < edge; ++i) {
    const double mirrored = input[n - 2 - i];
    switch (options.pad_type) {
      case PadType::odd: ext.push_back(2.0 * last - mirrored); break;
      case PadType::even: ext.push_back(mirrored); break;
      default: ext.push_back(last); break;
    }
  }
  // Forward pass from the steady state of ext[0], backward pass (in place, from the end) from the
  // steady state of the last forward output, then drop the extension (scipy sosfiltfilt).
  const std::vector<SectionState> zi = sosfilt_zi(design);
  std::vector<SectionState> state(zi.size());
  auto set_scaled = [&](double value) {
    for (std::size_t i = 0; i < zi.size(); ++i) state[i] = {zi[i][0] * value, zi[i][1] * value};
  };
  const std::vector<Section>& sections = design.sections();
  set_scaled(ext.front());
  filter_in_place(sections, state, ext, false);
  set_scaled(ext.back());
  filter_in_place(sections, state, ext, true);
  ext.erase(ext.begin(), ext.begin() + static_cast<std::ptrdiff_t>(edge));  // in place, no copy
  ext.resize(n);
  return ext;
}

}  // namespace clearshape::dsp
