// Against SciPy (tests/golden/gen_ident.py, scipy 1.10 least_squares 'lm' + signal.lsim, and a
// NumPy ERA): the same simulation-error P3UZ problems on the same noisy records must reach the
// same optimum, and the same damped-sinusoid problem the same modes.
// Tolerances: parameters within 1e-3 of their standard deviation (the two optima agree far below
// the statistical uncertainty; SciPy's finite-difference Jacobian limits it to ~1e-7 relative);
// standard deviations 1 % (ours: exact Jacobian; SciPy: forward differences); SSE 1e-7 relative;
// fit % 1e-6 absolute; ERA start poles 1e-6.
#include <cmath>
#include <complex>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "clearshape/core/linalg.hpp"
#include "clearshape/ident/modes.hpp"
#include "clearshape/ident/process_fit.hpp"
#include "clearshape/ident/subspace.hpp"
#include "clearshape/io/table.hpp"
#include "support/paths.hpp"

namespace ident = clearshape::ident;
namespace lti = clearshape::lti;
using nlohmann::json;

namespace {

json expected() {
  std::ifstream in(clearshape::testing::golden_path("ident_expected.json"));
  EXPECT_TRUE(in.good());
  return json::parse(in);
}

ident::Experiment load(const std::string& name) {
  const auto t = clearshape::io::read_table(clearshape::testing::golden_path(name));
  return ident::Experiment{name, clearshape::io::uniform_sample_time(t, "time_s"), t.column("command"), t.column("response")};
}

void compare_process(const std::string& file, const json& ref, const lti::ProcessModel& structure_of) {
  const auto data = load(file);
  ident::ProcessFitOptions o;
  o.initial_state = ident::InitialState::zero;  // as SciPy's lsim from rest
  const auto est = ident::estimate_process_model(structure_of.structure(), std::span(&data, 1), o);
  for (const auto& p : est.parameters) {
    const double v = ref["parameters"][p.name].get<double>();
    const double sd = ref["std"][p.name].get<double>();
    EXPECT_NEAR(p.value, v, 1e-3 * sd) << file << " " << p.name;
    EXPECT_NEAR(p.std_dev, sd, 0.01 * sd) << file << " " << p.name << " std";
  }
  EXPECT_NEAR(est.loss * static_cast<double>(est.samples), ref["sse"].get<double>(), 1e-7 * ref["sse"].get<double>());
  EXPECT_NEAR(est.experiments[0].fit_percent, ref["fit_percent"].get<double>(), 1e-6);
}

}  // namespace

TEST(Golden, SpeedModelStepMatchesScipyLeastSquares) {
  compare_process("ident_speed_step.csv", expected()["speed_step"], lti::thesis_speed_mode_model());
}

TEST(Golden, PositionModelPrbsMatchesScipyLeastSquares) {
  compare_process("ident_position_prbs.csv", expected()["position_prbs"], lti::thesis_position_mode_model());
}

TEST(Golden, FreeDecayModesMatchNumpyEraAndScipyRefinement) {
  const json ref = expected()["free_decay"];
  const auto t = clearshape::io::read_table(clearshape::testing::golden_path("ident_free_decay.csv"));
  const clearshape::UniformSeries y{0.0, clearshape::io::uniform_sample_time(t, "time_s"), t.column("link_rate_deg_s")};
  ident::ModeOptions o;
  o.modes = 2;
  const auto r = ident::identify_free_response_modes(y, o);
  ASSERT_EQ(r.modes.size(), 2u);
  EXPECT_EQ(r.decimation, 5u);  // as the NumPy ERA
  for (std::size_t i = 0; i < 2; ++i) {
    const json& m = ref["modes"][i];  // dominant (6.2 Hz) first in both
    EXPECT_NEAR(r.modes[i].natural_frequency_hz(), m["frequency_hz"].get<double>(), 1e-3 * m["frequency_std_hz"].get<double>());
    EXPECT_NEAR(r.modes[i].damping_ratio, m["damping_ratio"].get<double>(), 1e-3 * m["damping_ratio_std"].get<double>());
    EXPECT_NEAR(r.modes[i].amplitude, m["amplitude"].get<double>(), 1e-3 * m["amplitude_std"].get<double>());
    EXPECT_NEAR(r.modes[i].natural_frequency_std_hz(), m["frequency_std_hz"].get<double>(), 0.01 * m["frequency_std_hz"].get<double>());
    EXPECT_NEAR(r.modes[i].damping_ratio_std, m["damping_ratio_std"].get<double>(), 0.01 * m["damping_ratio_std"].get<double>());
    EXPECT_NEAR(r.modes[i].amplitude_std, m["amplitude_std"].get<double>(), 0.01 * m["amplitude_std"].get<double>());
  }
  // ERA alone (the subspace start): the NumPy poles from the same 5-sample block averages.
  std::vector<double> averaged;
  for (std::size_t k = 0; (k + 1) * 5 <= y.size(); ++k) {
    double s = 0.0;
    for (std::size_t j = 0; j < 5; ++j) s += y.values[k * 5 + j];
    averaged.push_back(s / 5.0);
  }
  const auto e = ident::era(averaged, 5, 80);
  const Eigen::VectorXcd eigenvalues = clearshape::linalg::eigen(e.a).values;  // Eigen's EigenSolver, compiled once
  std::vector<std::complex<double>> pairs;
  for (Eigen::Index k = 0; k < eigenvalues.size(); ++k) {
    const std::complex<double> z = std::exp(std::log(eigenvalues(k)) / 5.0);
    if (z.imag() > 1e-9) pairs.push_back(z);
  }
  std::sort(pairs.begin(), pairs.end(), [](auto a, auto b) { return std::arg(a) < std::arg(b); });
  ASSERT_EQ(pairs.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    const std::complex<double> zr(ref["era_poles_full_rate"][i][0].get<double>(), ref["era_poles_full_rate"][i][1].get<double>());
    EXPECT_LT(std::abs(pairs[i] - zr), 1e-6);
  }
}
