// Causal and zero-phase SOS filtering against scipy.signal.sosfilt / sosfilt_zi / sosfiltfilt
// (tests/golden/gen_dsp.py). Tolerance: 1e-10 absolute on the filtered signals (the input is
// O(1), |x| < 5) and on the states; 1e-12 on sosfilt_zi.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>

#include "clearshape/core/error.hpp"
#include "clearshape/dsp/butterworth.hpp"
#include "clearshape/dsp/sosfilt.hpp"
#include "golden_json.hpp"
#include "support/alloc_counter.hpp"

namespace cs = clearshape;
namespace dsp = clearshape::dsp;
using dsp::testing::load_golden;
using dsp::testing::max_abs_diff;
using dsp::testing::to_vector;

namespace {

constexpr double kSignalTolerance = 1e-10;

dsp::SosDesign design_of(const nlohmann::json& c, double fs) {
  return dsp::SosDesign(dsp::testing::to_sections(c["sos"]), fs);
}

std::vector<dsp::SectionState> states_of(const nlohmann::json& j) {
  std::vector<dsp::SectionState> out;
  for (const auto& row : j) out.push_back({row[0].get<double>(), row[1].get<double>()});
  return out;
}

double max_state_diff(const std::vector<dsp::SectionState>& a, const std::vector<dsp::SectionState>& b) {
  EXPECT_EQ(a.size(), b.size());
  double m = 0.0;
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) {
    m = std::max({m, std::abs(a[i][0] - b[i][0]), std::abs(a[i][1] - b[i][1])});
  }
  return m;
}

}  // namespace

TEST(Sosfilt, CausalFilteringMatchesScipy) {
  const auto golden = load_golden("dsp_filter.json");
  const double fs = golden["fs_hz"].get<double>();
  const auto x = to_vector(golden["x"]);
  double worst = 0.0;
  for (const auto& c : golden["cases"]) {
    const dsp::SosDesign d = design_of(c, fs);
    const double rest = max_abs_diff(dsp::sosfilt(d, x), to_vector(c["sosfilt"]));
    EXPECT_LT(rest, kSignalTolerance);
    // From the steady state of x[0], and the final state (scipy zf).
    std::vector<dsp::SectionState> state = dsp::sosfilt_zi(d);
    EXPECT_LT(max_state_diff(state, states_of(c["zi"])), 1e-12);
    for (auto& s : state) s = {s[0] * x[0], s[1] * x[0]};
    const double from_zi = max_abs_diff(dsp::sosfilt(d, x, state), to_vector(c["sosfilt_zi_x0"]));
    EXPECT_LT(from_zi, kSignalTolerance);
    EXPECT_LT(max_state_diff(state, states_of(c["zf"])), kSignalTolerance);
    worst = std::max({worst, rest, from_zi});
  }
  std::printf("[ dsp ] sosfilt: max |ours - scipy| = %.3g\n", worst);
}

TEST(Sosfilt, ZeroPhaseFilteringMatchesScipySosfiltfilt) {
  const auto golden = load_golden("dsp_filter.json");
  const double fs = golden["fs_hz"].get<double>();
  const auto x = to_vector(golden["x"]);
  double worst = 0.0;
  for (const auto& c : golden["cases"]) {
    const dsp::SosDesign d = design_of(c, fs);
    EXPECT_EQ(dsp::default_pad_length(d), c["default_padlen"].get<std::size_t>());
    const struct {
      const char* key;
      dsp::FiltfiltOptions options;
    } variants[] = {
        {"sosfiltfilt_odd", {}},
        {"sosfiltfilt_even", {dsp::PadType::even, std::nullopt}},
        {"sosfiltfilt_constant", {dsp::PadType::constant, std::nullopt}},
        {"sosfiltfilt_none", {dsp::PadType::none, std::nullopt}},
        {"sosfiltfilt_odd_padlen50", {dsp::PadType::odd, 50}},
    };
    for (const auto& v : variants) {
      const double diff = max_abs_diff(dsp::sosfiltfilt(d, x, v.options), to_vector(c[v.key]));
      EXPECT_LT(diff, kSignalTolerance) << v.key << " order " << c["order"];
      worst = std::max(worst, diff);
    }
  }
  std::printf("[ dsp ] sosfiltfilt: max |ours - scipy| = %.3g\n", worst);
}

TEST(Sosfilt, DefaultPadLengthFollowsScipyRule) {
  // Even order: 3·(2n+1); odd order has one first-order section: 3·(2n+1−1) = filtfilt's 3·(N+1).
  EXPECT_EQ(dsp::default_pad_length(dsp::butter_lowpass(4, 10.0, 1000.0)), 15u);
  EXPECT_EQ(dsp::default_pad_length(dsp::butter_lowpass(3, 10.0, 1000.0)), 12u);
  EXPECT_EQ(dsp::default_pad_length(dsp::butter_lowpass(1, 10.0, 1000.0)), 6u);
}

TEST(Sosfilt, ZeroPhaseOfASinusoidHasNoLagAndSquaredGain) {
  // sosfiltfilt's frequency response is |H|²: a 3 Hz sine through the thesis filter keeps its
  // phase and is scaled by |H(3 Hz)|² (checked away from the ends).
  const auto d = dsp::butter_lowpass_rad_s(4, 30.0, 1000.0);
  std::vector<double> x(4000);
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = std::sin(2.0 * 3.14159265358979323846 * 3.0 * 1e-3 * static_cast<double>(i));
  const auto y = dsp::sosfiltfilt(d, x);
  const double g = std::norm(d.response(3.0));
  for (std::size_t i = 1500; i < 2500; ++i) EXPECT_NEAR(y[i], g * x[i], 2e-6);
}

TEST(Sosfilt, StreamingEqualsOfflineAndIsAllocationFree) {
  // Offline filtering runs register-resident kernels (1…8 sections) or blocks (more); all must
  // equal the sample-by-sample real-time filter bitwise, across block boundaries.
  const auto golden = load_golden("dsp_filter.json");
  const auto base = to_vector(golden["x"]);
  std::vector<double> x;
  for (int r = 0; r < 5; ++r) x.insert(x.end(), base.begin(), base.end());
  for (const auto& d : {dsp::butter_lowpass(5, 45.0, 1000.0), dsp::butter_highpass(16, 300.0, 1000.0),
                        dsp::butter_bandpass(9, 20.0, 200.0, 1000.0),
                        dsp::butter_bandpass(16, 100.0, 300.0, 1000.0)}) {
    const auto offline = dsp::sosfilt(d, x);
    dsp::StreamingSosFilter filter(d);
    std::vector<double> online(x.size());
    {
      cs::testing::AllocationCounter counter;
      for (std::size_t i = 0; i < x.size(); ++i) online[i] = filter.step(x[i]);
      double out = 0.0;
      EXPECT_EQ(filter.step(1.0, out), cs::Status::ok);
      filter.reset_steady_state(2.0);
      filter.reset();
      EXPECT_EQ(counter.allocations(), 0u);
    }
    for (std::size_t i = 0; i < x.size(); ++i) ASSERT_EQ(online[i], offline[i]) << d.section_count() << " sections, sample " << i;
  }
}

TEST(Sosfilt, ZeroPhaseEqualsAPlainForwardBackwardReference) {
  // A direct transcription of scipy's sosfiltfilt steps with the streaming filter, for designs
  // with more sections than the golden cases (the block path).
  const auto golden = load_golden("dsp_filter.json");
  const auto base = to_vector(golden["x"]);
  std::vector<double> x;
  for (int r = 0; r < 3; ++r) x.insert(x.end(), base.begin(), base.end());
  for (const auto& d : {dsp::butter_highpass(16, 300.0, 1000.0), dsp::butter_bandpass(12, 50.0, 200.0, 1000.0)}) {
    const std::size_t edge = dsp::default_pad_length(d);
    std::vector<double> ext;
    for (std::size_t i = edge; i > 0; --i) ext.push_back(2.0 * x.front() - x[i]);
    ext.insert(ext.end(), x.begin(), x.end());
    for (std::size_t i = 0; i < edge; ++i) ext.push_back(2.0 * x.back() - x[x.size() - 2 - i]);
    const auto zi = dsp::sosfilt_zi(d);
    auto scaled = [&](double v) {
      std::vector<dsp::SectionState> s = zi;
      for (auto& z : s) z = {z[0] * v, z[1] * v};
      return s;
    };
    dsp::StreamingSosFilter f(d);
    f.set_state(scaled(ext.front()));
    for (double& v : ext) v = f.step(v);
    f.set_state(scaled(ext.back()));
    for (auto it = ext.rbegin(); it != ext.rend(); ++it) *it = f.step(*it);
    const std::vector<double> expected(ext.begin() + static_cast<std::ptrdiff_t>(edge),
                                       ext.end() - static_cast<std::ptrdiff_t>(edge));
    EXPECT_EQ(max_abs_diff(dsp::sosfiltfilt(d, x), expected), 0.0) << d.section_count() << " sections";
  }
}

TEST(Sosfilt, SteadyStateStartHasNoTransient) {
  for (const auto& d : {dsp::butter_lowpass(4, 4.77, 1000.0), dsp::butter_lowpass(7, 100.0, 1000.0),
                        dsp::butter_bandpass(2, 5.0, 20.0, 1000.0)}) {
    dsp::StreamingSosFilter filter(d);
    filter.reset_steady_state(3.25);
    for (int i = 0; i < 200; ++i) EXPECT_NEAR(filter.step(3.25), 3.25 * d.dc_gain(), 1e-9);
  }
}

TEST(Sosfilt, NonFiniteInputIsRejectedWithoutTouchingTheState) {
  dsp::StreamingSosFilter filter(dsp::butter_lowpass(2, 10.0, 1000.0));
  double out = 0.0;
  ASSERT_EQ(filter.step(1.0, out), cs::Status::ok);
  const auto before = std::vector<dsp::SectionState>(filter.state().begin(), filter.state().end());
  double held = -1.0;
  EXPECT_EQ(filter.step(std::numeric_limits<double>::quiet_NaN(), held), cs::Status::not_finite);
  EXPECT_EQ(held, out);
  EXPECT_EQ(max_state_diff(before, {filter.state().begin(), filter.state().end()}), 0.0);
}

TEST(Sosfilt, RejectsBadSizes) {
  const auto d = dsp::butter_lowpass(4, 10.0, 1000.0);
  std::vector<double> short_signal(15, 1.0);  // pad length is 15: needs at least 16 samples
  EXPECT_THROW(dsp::sosfiltfilt(d, short_signal), cs::InvalidArgument);
  short_signal.push_back(1.0);
  const auto y = dsp::sosfiltfilt(d, short_signal);
  for (double v : y) EXPECT_NEAR(v, 1.0, 1e-12);  // a constant passes unchanged (DC gain 1)
  std::vector<dsp::SectionState> wrong(3);
  EXPECT_THROW(dsp::sosfilt(d, short_signal, wrong), cs::InvalidArgument);
  dsp::StreamingSosFilter filter(d);
  EXPECT_THROW(filter.set_state(wrong), cs::InvalidArgument);
}
