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

std::vector<double> run(const SosDesign& design, std::span<const double> input,
                        std::vector<SectionState>& state) {
  std::vector<double> out(input.size());
  for (std::size_t n = 0; n < input.size(); ++n) {
    out[n] = filter_sample(design.sections(), state.data(), input[n]);
  }
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
  const std::vector<SectionState> zi = sosfilt_zi(design);
  auto scaled = [&](double value) {
    std::vector<SectionState> s(zi.size());
    for (std::size_t i = 0; i < zi.size(); ++i) s[i] = {zi[i][0] * value, zi[i][1] * value};
    return s;
  };
  std::vector<SectionState> state = scaled(ext.front());  // forward from steady state at x[0]
  std::vector<double> y = run(design, ext, state);
  std::reverse(y.begin(), y.end());
  state = scaled(y.front());  // backward from steady state at the last forward output
  y = run(design, y, state);
  std::reverse(y.begin(), y.end());
  return std::vector<double>(y.begin() + static_cast<std::ptrdiff_t>(edge),
                             y.end() - static_cast<std::ptrdiff_t>(edge));
}

}  // namespace clearshape::dsp
