// Stabilisation diagram (issue 20): the rules on hand-made poles; the diagram of a free decay
// against an independent NumPy implementation (tests/golden/gen_stabilisation.py) and against the
// record's true poles; and the reported frequency no longer moving with --modes.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "clearshape/core/error.hpp"
#include "clearshape/ident/modes.hpp"
#include "clearshape/ident/stabilisation.hpp"
#include "clearshape/io/table.hpp"
#include "clearshape/lti/discretize.hpp"
#include "free_decay.hpp"
#include "support/paths.hpp"

namespace ident = clearshape::ident;
using clearshape::UniformSeries;
using nlohmann::json;

namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

ident::DiagramPole pole(double f_hz, double zeta) {
  ident::DiagramPole p;
  p.natural_frequency_rad_s = kTwoPi * f_hz;
  p.damping_ratio = zeta;
  p.amplitude = 1.0;
  return p;
}

json golden() {
  std::ifstream in(clearshape::testing::golden_path("stabilisation_expected.json"));
  return json::parse(in);
}

UniformSeries golden_record() {
  const auto t = clearshape::io::read_table(clearshape::testing::golden_path("stabilisation_free_decay.csv"));
  return UniformSeries{0.0, clearshape::io::uniform_sample_time(t, "time_s"), t.column("link_rate_deg_s")};
}

double relative_spread(const std::vector<double>& v) {
  const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
  return (*hi - *lo) / *lo;
}

using clearshape::testing::two_resonance_record;

}  // namespace

// A pole that moves 0.5 % in f and 2 % in ζ per order is stable; one that moves 3 % in f, or
// 10 % in ζ, is not; a persistent mode needs 5 stable orders, 70 % of those from its first on.
TEST(Stabilisation, RulesOnHandMadePoles) {
  std::vector<ident::DiagramOrder> orders;
  for (std::size_t n = 2; n <= 9; ++n) {
    const double k = static_cast<double>(n - 2);
    ident::DiagramOrder d{n, {pole(10.0 * (1.0 + 0.005 * k), 0.02 * (1.0 + 0.02 * k))}};
    d.poles.push_back(pole(40.0 * (1.0 + 0.03 * k), 0.01));                       // frequency wanders
    d.poles.push_back(pole(90.0, n % 2 == 0 ? 0.01 : 0.0111));                     // ζ jumps 11 %
    orders.push_back(d);
  }
  const auto d = ident::build_stabilisation_diagram(orders, {});
  EXPECT_FALSE(d.orders[0].poles[0].stable);  // no previous order
  for (std::size_t j = 1; j < d.orders.size(); ++j) {
    EXPECT_TRUE(d.orders[j].poles[0].stable) << "order " << d.orders[j].order;
    EXPECT_FALSE(d.orders[j].poles[1].stable_frequency);
    EXPECT_TRUE(d.orders[j].poles[2].stable_frequency);
    EXPECT_FALSE(d.orders[j].poles[2].stable_damping);
  }
  ASSERT_EQ(d.modes.size(), 1u);
  EXPECT_NEAR(d.modes[0].frequency_hz(), 10.0 * 1.02, 1e-9);  // median of the 7 stable poles (k = 1…7): k = 4
  EXPECT_EQ(d.modes[0].stable_orders, 7u);
  EXPECT_EQ(d.chosen_order, 4u);  // its first stable pole within 1 % of that median (k = 2: 10.1 Hz)
  // A negative ζ is never stable; a mode stable in 4 orders does not persist.
  orders.resize(5);
  for (auto& o : orders) o.poles[0].damping_ratio = -0.02;
  const auto none = ident::build_stabilisation_diagram(orders, {});
  EXPECT_TRUE(none.modes.empty());
  EXPECT_EQ(none.chosen_order, 0u);
  ident::StabilisationOptions bad;
  bad.max_order = 2;
  EXPECT_THROW((void)ident::build_stabilisation_diagram(orders, bad), clearshape::InvalidArgument);
}

// The diagram of the golden free decay (three modes + offset + noise) against NumPy's: the same
// stable poles at every order, the same persistent modes and chosen order; and those are the truth.
TEST(Stabilisation, FreeDecayMatchesNumpyAndTheTruth) {
  const json ref = golden();
  const auto d = ident::free_response_stabilisation(golden_record());
  EXPECT_EQ(d.decimation, 1u);
  ASSERT_EQ(d.orders.size(), ref["orders"].size());
  for (std::size_t j = 0; j < d.orders.size(); ++j) {
    const json& o = ref["orders"][j];
    ASSERT_EQ(d.orders[j].order, o["order"].get<std::size_t>());
    ASSERT_EQ(d.orders[j].poles.size(), o["poles"].size()) << "order " << d.orders[j].order;
    for (std::size_t i = 0; i < d.orders[j].poles.size(); ++i) {
      EXPECT_NEAR(d.orders[j].poles[i].frequency_hz(), o["poles"][i]["frequency_hz"].get<double>(), 1e-6);
      EXPECT_EQ(d.orders[j].poles[i].stable, o["poles"][i]["stable"].get<bool>()) << "order " << d.orders[j].order;
    }
  }
  ASSERT_EQ(d.modes.size(), ref["persistent_modes"].size());
  ASSERT_EQ(d.modes.size(), ref["truth"].size());
  for (std::size_t i = 0; i < d.modes.size(); ++i) {
    const json& m = ref["persistent_modes"][i];
    EXPECT_NEAR(d.modes[i].frequency_hz(), m["frequency_hz"].get<double>(), 1e-7 * m["frequency_hz"].get<double>());
    EXPECT_NEAR(d.modes[i].damping_ratio, m["damping_ratio"].get<double>(), 1e-6 * m["damping_ratio"].get<double>());
    EXPECT_EQ(d.modes[i].stable_orders, m["stable_orders"].get<std::size_t>());
    const json& t = ref["truth"][i];
    EXPECT_NEAR(d.modes[i].frequency_hz(), t["frequency_hz"].get<double>(), 2e-3 * t["frequency_hz"].get<double>());
    EXPECT_NEAR(d.modes[i].damping_ratio, t["damping_ratio"].get<double>(), 0.05 * t["damping_ratio"].get<double>());
  }
  EXPECT_EQ(d.chosen_order, ref["chosen_order"].get<std::size_t>());
}

// The complaint: the frequency moved with --modes. With the diagram's order the same record
// gives the same modes for --modes 2, 3 and 4 (the order no longer follows --modes).
TEST(Stabilisation, FrequencyDoesNotMoveWithModes) {
  const auto y = clearshape::testing::free_decay({{6.2, 0.03, 40.0, 0.4}, {17.5, 0.012, 15.0, -1.0}}, 1e-3, 2500, 2.0, 5);
  std::vector<double> f1, f2, f1_fixed, f2_fixed;
  for (std::size_t modes = 2; modes <= 4; ++modes) {
    ident::ModeOptions o;
    o.modes = modes;
    const auto r = ident::identify_free_response_modes(y, o);
    EXPECT_EQ(r.order_source, "stabilisation");
    ASSERT_GE(r.modes.size(), 2u);
    f1.push_back(r.modes[0].natural_frequency_hz());
    f2.push_back(r.modes[1].natural_frequency_hz());
    o.use_stabilisation = false;  // the order 2·modes + 2 of before
    const auto fixed = ident::identify_free_response_modes(y, o);
    f1_fixed.push_back(fixed.modes[0].natural_frequency_hz());
    f2_fixed.push_back(fixed.modes[1].natural_frequency_hz());
  }
  std::printf("spread over --modes 2..4: diagram %.2e / %.2e, order 2*modes+2 %.2e / %.2e\n", relative_spread(f1),
              relative_spread(f2), relative_spread(f1_fixed), relative_spread(f2_fixed));
  EXPECT_LT(relative_spread(f1), 0.005);
  EXPECT_LT(relative_spread(f2), 0.005);
  EXPECT_NEAR(f1[0], 6.2, 0.01);
  EXPECT_NEAR(f2[0], 17.5, 0.03);
}

// Input/output: a random input through two resonances + 5 % output noise; --modes 2, 3, 4 report the
// same two modes (the diagram's), each at its true frequency.
TEST(Stabilisation, InputOutputFrequencyDoesNotMoveWithModes) {
  const double w1 = kTwoPi * 4.0, w2 = kTwoPi * 11.0;
  const ident::Experiment e = two_resonance_record(9, 0.05);
  std::vector<double> low, high;
  for (std::size_t modes = 2; modes <= 4; ++modes) {
    ident::ModeOptions o;
    o.modes = modes;
    const auto r = ident::identify_modes(e, o);
    EXPECT_EQ(r.order_source, "stabilisation");
    ASSERT_EQ(r.modes.size(), 2u) << "--modes " << modes;
    const double a = r.modes[0].natural_frequency_rad_s, b = r.modes[1].natural_frequency_rad_s;
    low.push_back(std::min(a, b));
    high.push_back(std::max(a, b));
  }
  EXPECT_LT(relative_spread(low), 0.005);
  EXPECT_LT(relative_spread(high), 0.005);
  EXPECT_NEAR(low[0], w1, 0.005 * w1);
  EXPECT_NEAR(high[0], w2, 0.005 * w2);
}

// This seed (10 % output noise) diverged at the diagram's order from the single horizon-10 subspace
// start, and the next order up was fitted instead of failing the record. With the starts from
// several horizons (state_space_fit.hpp) it fits at the diagram's order itself — as do seeds 1–400.
TEST(Stabilisation, InputOutputFitHoldsTheDiagramsOrderWhereTheShortHorizonDiverged) {
  ident::ModeOptions o;
  o.modes = 2;
  const auto r = ident::identify_modes(two_resonance_record(49, 0.1), o);
  EXPECT_EQ(r.order_source, "stabilisation");
  EXPECT_EQ(r.order, r.stabilisation.chosen_order);
  ASSERT_EQ(r.modes.size(), 2u);
  EXPECT_NEAR(r.modes[0].natural_frequency_hz(), 4.0, 0.01);
  EXPECT_NEAR(r.modes[1].natural_frequency_hz(), 11.0, 0.05);
}
