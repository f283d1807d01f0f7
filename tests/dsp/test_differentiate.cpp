// Differentiation (numpy.gradient golden data, closed forms) and the thesis encoder-speed chain
// (§3.3/§4.1.1) against the same chain computed with NumPy/SciPy. Tolerances, relative to the
// largest magnitude of the reference: 1e-12 for np.gradient, 1e-10 for the filtered speed.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>

#include "clearshape/core/error.hpp"
#include "clearshape/dsp/differentiate.hpp"
#include "clearshape/dsp/encoder_speed.hpp"
#include "golden_json.hpp"
#include "support/alloc_counter.hpp"

namespace cs = clearshape;
namespace dsp = clearshape::dsp;
using dsp::testing::load_golden;
using dsp::testing::max_abs;
using dsp::testing::max_abs_diff;
using dsp::testing::to_vector;

TEST(Differentiate, CentralDifferenceMatchesNumpyGradient) {
  const auto golden = load_golden("dsp_differentiate.json");
  const double dt = golden["dt_s"].get<double>();
  const auto x = to_vector(golden["x"]);
  const auto g1 = to_vector(golden["gradient_edge1"]);
  const auto g2 = to_vector(golden["gradient_edge2"]);
  const double d1 = max_abs_diff(dsp::central_difference(x, dt), g1);
  const double d2 = max_abs_diff(dsp::central_difference(x, dt, dsp::EdgeOrder::second), g2);
  EXPECT_LT(d1, 1e-12 * max_abs(g1));
  EXPECT_LT(d2, 1e-12 * max_abs(g2));
  std::printf("[ dsp ] gradient: max |ours - numpy| = %.3g (edge 1), %.3g (edge 2), scale %.3g\n",
              d1, d2, max_abs(g2));
}

TEST(Differentiate, ExactForPolynomialsOfTheRightDegree) {
  // Central differences are exact for quadratics; second-order edges too; first-order edges and
  // backward differences are exact for straight lines.
  const double dt = 0.01;
  std::vector<double> quad(20), line(20);
  for (std::size_t i = 0; i < 20; ++i) {
    const double t = dt * static_cast<double>(i);
    quad[i] = 3.0 * t * t - 2.0 * t + 1.0;
    line[i] = 5.0 * t - 1.0;
  }
  const auto dq = dsp::central_difference(quad, dt, dsp::EdgeOrder::second);
  for (std::size_t i = 0; i < 20; ++i) EXPECT_NEAR(dq[i], 6.0 * dt * static_cast<double>(i) - 2.0, 1e-10);
  const auto dl = dsp::central_difference(line, dt);
  for (double v : dl) EXPECT_NEAR(v, 5.0, 1e-10);
  const auto bl = dsp::backward_difference(line, dt);
  EXPECT_EQ(bl[0], 0.0);  // at rest before the first sample
  for (std::size_t i = 1; i < 20; ++i) EXPECT_NEAR(bl[i], 5.0, 1e-10);
}

TEST(Differentiate, RejectsBadInput) {
  const std::vector<double> two{1.0, 2.0};
  EXPECT_NO_THROW(dsp::central_difference(two, 1.0));
  EXPECT_THROW(dsp::central_difference(two, 1.0, dsp::EdgeOrder::second), cs::InvalidArgument);
  EXPECT_THROW(dsp::central_difference(two, 0.0), cs::InvalidArgument);
  EXPECT_THROW(dsp::backward_difference(two, -1.0), cs::InvalidArgument);
  EXPECT_TRUE(dsp::backward_difference({}, 1.0).empty());
}

TEST(EncoderSpeed, ThesisChainMatchesNumpyScipy) {
  const auto golden = load_golden("dsp_differentiate.json");
  const auto& enc = golden["encoder"];
  const auto counts = enc["counts"].get<std::vector<std::int64_t>>();
  const double dt = 1.0 / enc["fs_hz"].get<double>();
  ASSERT_EQ(enc["counts_per_rev"].get<double>(), dsp::kThesisEncoderCountsPerRev);
  const auto deg = dsp::encoder_counts_to_deg(counts);
  const auto back_ref = to_vector(enc["backward_difference_deg_s"]);
  EXPECT_LT(max_abs_diff(dsp::backward_difference(deg, dt), back_ref), 1e-9 * max_abs(back_ref));

  const auto causal_ref = to_vector(enc["causal_deg_s"]);
  const auto zero_ref = to_vector(enc["zero_phase_deg_s"]);
  const double dc = max_abs_diff(dsp::encoder_speed_deg_s(counts, dt), causal_ref);
  const double dz = max_abs_diff(dsp::encoder_speed_deg_s(counts, dt, dsp::Phase::zero_phase), zero_ref);
  EXPECT_LT(dc, 1e-10 * max_abs(causal_ref));
  EXPECT_LT(dz, 1e-10 * max_abs(zero_ref));
  const std::vector<std::int64_t> first300(counts.begin(), counts.begin() + 300);
  const auto short_ref = to_vector(enc["zero_phase_first300_deg_s"]);
  EXPECT_LT(max_abs_diff(dsp::encoder_speed_deg_s(first300, dt, dsp::Phase::zero_phase), short_ref),
            1e-10 * max_abs(short_ref));
  std::printf("[ dsp ] encoder chain: max |ours - scipy| = %.3g (causal), %.3g (zero phase) deg/s; "
              "peak speed %.4g deg/s\n", dc, dz, max_abs(zero_ref));
}

TEST(EncoderSpeed, StreamingEqualsOfflineCausalAndIsAllocationFree) {
  const auto golden = load_golden("dsp_differentiate.json");
  const auto counts = golden["encoder"]["counts"].get<std::vector<std::int64_t>>();
  const auto offline = dsp::encoder_speed_deg_s(counts, 1e-3);
  dsp::StreamingEncoderSpeed chain(1e-3);
  std::vector<double> online(counts.size());
  {
    cs::testing::AllocationCounter counter;
    for (std::size_t i = 0; i < counts.size(); ++i) online[i] = chain.step(counts[i]);
    chain.reset();
    EXPECT_EQ(counter.allocations(), 0u);
  }
  for (std::size_t i = 0; i < counts.size(); ++i) ASSERT_EQ(online[i], offline[i]) << i;
}

TEST(EncoderSpeed, ConstantSpeedIsRecoveredExactlyAfterTheTransient) {
  // 1 count per ms = 0.03° per ms = 30 °/s; the filter has unit DC gain.
  std::vector<std::int64_t> counts(4000);
  for (std::size_t i = 0; i < counts.size(); ++i) counts[i] = static_cast<std::int64_t>(i) + 100;
  const auto causal = dsp::encoder_speed_deg_s(counts, 1e-3);
  const auto zero = dsp::encoder_speed_deg_s(counts, 1e-3, dsp::Phase::zero_phase);
  for (std::size_t i = 3000; i < counts.size(); ++i) EXPECT_NEAR(causal[i], 30.0, 1e-9);  // e^{-11.5·3} decay
  for (double v : zero) EXPECT_NEAR(v, 30.0, 1e-9);  // odd padding continues a ramp exactly
}
