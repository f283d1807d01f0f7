// signal::Chirp (swept sine, linear and logarithmic) against scipy.signal.chirp
// (tests/golden/gen_chirp.py), its instantaneous frequency, parameters and validation.
// Tolerance 1e-9 absolute: the phase reaches ~260 rad, where one ulp of θ is ~6e-14.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "clearshape/core/error.hpp"
#include "clearshape/core/units.hpp"
#include "clearshape/io/table.hpp"
#include "clearshape/signal/parameters.hpp"
#include "clearshape/signal/signal.hpp"
#include "support/paths.hpp"

namespace cs = clearshape;
namespace sig = clearshape::signal;

namespace {

sig::Chirp golden_chirp(sig::ChirpSweep sweep) {
  return sig::Chirp{1.5, 0.5, 20.0, 4.0, sweep, cs::deg_to_rad(30.0), 0.25, 0.5};
}

}  // namespace

TEST(Chirp, MatchesScipyLinearAndLogarithmic) {
  const auto t = cs::io::read_table(cs::testing::golden_path("signal_chirp.csv"));
  for (const auto sweep : {sig::ChirpSweep::linear, sig::ChirpSweep::logarithmic}) {
    const auto ours = sig::sample(golden_chirp(sweep), 1000.0, 5.0);
    const auto& golden = t.column(std::string(sig::to_string(sweep)));
    ASSERT_EQ(ours.size(), golden.size());
    double worst = 0.0;
    for (std::size_t i = 0; i < golden.size(); ++i) worst = std::max(worst, std::abs(ours.values[i] - golden[i]));
    EXPECT_LT(worst, 1e-9) << sig::to_string(sweep);
  }
}

TEST(Chirp, InstantaneousFrequencySweepsFromF0ToF1) {
  // Zero crossings over 1 s around τ: two per period at f(τ) = f0 + (f1 − f0) τ/T (linear) or
  // f0 (f1/f0)^(τ/T) (logarithmic); ±1 crossing is ±0.5 Hz.
  const auto rate_hz = [](const sig::Chirp& c, double tau_s) {
    const auto s = sig::sample(c, 20000.0, c.sweep_s);
    int count = 0;
    const auto i0 = static_cast<std::size_t>((tau_s - 0.5) * 20000.0);
    for (std::size_t i = i0; i < i0 + 20000; ++i) count += (s.values[i] < 0.0) != (s.values[i + 1] < 0.0);
    return count / 2.0;
  };
  const sig::Chirp lin{1.0, 10.0, 110.0, 10.0, sig::ChirpSweep::linear, 0.0, 0.0, 0.0};
  EXPECT_NEAR(rate_hz(lin, 1.0), 20.0, 1.0);
  EXPECT_NEAR(rate_hz(lin, 9.0), 100.0, 1.0);
  const sig::Chirp log{1.0, 10.0, 100.0, 10.0, sig::ChirpSweep::logarithmic, 0.0, 0.0, 0.0};
  EXPECT_NEAR(rate_hz(log, 5.0), 10.0 * std::sqrt(10.0), 1.0);
  EXPECT_NEAR(rate_hz(log, 9.0), 10.0 * std::pow(10.0, 0.9), 1.5);
  EXPECT_EQ(lin.value_at(10.5), 0.0);  // the offset after the sweep
}

TEST(Chirp, ParametersRoundTripAndValidation) {
  const sig::Signal s = sig::make_signal("chirp", {{"f0_hz", 2.0}, {"f1_hz", 50.0}, {"sweep", std::string("logarithmic")}});
  EXPECT_EQ(s.type(), "chirp");
  const auto p = sig::parameters_of(s);
  EXPECT_EQ(std::get<std::string>(p.at("sweep")), "logarithmic");
  EXPECT_EQ(sig::make_signal("chirp", p).value_at(0.3), s.value_at(0.3));
  EXPECT_THROW(sig::make_signal("chirp", {{"sweep", std::string("cubic")}}), cs::InvalidArgument);
  EXPECT_THROW(sig::make_signal("chirp", {{"f0_hz", 0.0}}), cs::InvalidArgument);
  EXPECT_THROW(sig::make_signal("chirp", {{"sweep_s", -1.0}}), cs::InvalidArgument);
}
