// Golden comparisons with SciPy 1.10 (tests/golden/gen_lti.py): tf2ss, poles/zeros, freqresp,
// cont2discrete (zoh, foh), step and lsim (interp False/True), for both thesis models and
// P1D (integer and fractional delay), P2, P2I, P2U, P3DZU (fractional delay), P3Z (time
// constants 1e-4…2 s).
// Tolerances (relative to the largest magnitude of the compared quantity):
//   polynomials, tf2ss 1e-12; discretized canonical-form matrices, elementwise 1e-10 (measured
//   ≤ 6e-12: two expm implementations on companion matrices); discretized Markov parameters
//   (input-output response of the cascade realization) 1e-9 (measured ≤ 2.1e-13);
//   poles/zeros vs numpy.roots 1e-8; frequency response 1e-10 (measured ≤ 1e-15); simulated
//   outputs 1e-8 (measured ≤ 5e-14).
#include <algorithm>
#include <cmath>
#include <complex>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "clearshape/lti/discretize.hpp"
#include "clearshape/lti/process_model.hpp"
#include "clearshape/lti/simulate.hpp"
#include "support/paths.hpp"

namespace lti = clearshape::lti;
using nlohmann::json;

namespace {

json load(const std::string& name) {
  std::ifstream in(clearshape::testing::golden_path("lti_" + name + ".json"));
  EXPECT_TRUE(in.good()) << name;
  return json::parse(in);
}

Eigen::MatrixXd matrix(const json& j) {
  const auto rows = static_cast<Eigen::Index>(j.size());
  const auto cols = rows == 0 ? Eigen::Index{0} : static_cast<Eigen::Index>(j[0].size());
  Eigen::MatrixXd m(rows, cols);
  for (Eigen::Index r = 0; r < rows; ++r)
    for (Eigen::Index c = 0; c < cols; ++c) m(r, c) = j[static_cast<std::size_t>(r)][static_cast<std::size_t>(c)].get<double>();
  return m;
}

std::vector<std::complex<double>> complexes(const json& j) {
  std::vector<std::complex<double>> v;
  for (const auto& e : j) v.emplace_back(e[0].get<double>(), e[1].get<double>());
  return v;
}

double max_abs(const std::vector<double>& v) {
  double m = 0.0;
  for (double x : v) m = std::max(m, std::abs(x));
  return m;
}

// Largest |a − b| relative to max |b|.
double relative_error(const std::vector<double>& a, const std::vector<double>& b) {
  EXPECT_EQ(a.size(), b.size());
  double e = 0.0;
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) e = std::max(e, std::abs(a[i] - b[i]));
  return e / std::max(max_abs(b), 1e-300);
}
double relative_error(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  EXPECT_EQ(a.rows(), b.rows());
  EXPECT_EQ(a.cols(), b.cols());
  if (a.size() == 0 || a.rows() != b.rows() || a.cols() != b.cols()) return a.size() == b.size() ? 0.0 : 1.0;
  return (a - b).cwiseAbs().maxCoeff() / std::max(b.cwiseAbs().maxCoeff(), 1e-300);
}

lti::ProcessModel model_of(const json& doc) {
  lti::ProcessParameters p;
  p.kp = 0.0;
  for (const auto& [name, value] : doc["parameters"].items()) p.set(name, value.get<double>());
  return lti::ProcessModel(doc["structure"].get<std::string>(), p);
}

lti::StateSpace tf2ss_of(const json& doc) {
  const json& s = doc["tf2ss"];
  return {matrix(s["a"]), matrix(s["b"]), matrix(s["c"]), matrix(s["d"])};
}

std::vector<double> markov(const lti::DiscreteStateSpace& d, std::size_t count) {
  std::vector<double> out{d.d(0, 0)};
  Eigen::VectorXd x = d.b.col(0);
  for (std::size_t k = 1; k < count; ++k) {
    out.push_back(d.c.row(0).dot(x));
    x = d.a * x;
  }
  return out;
}

void expect_roots(const std::vector<std::complex<double>>& mine, const std::vector<std::complex<double>>& ref,
                  const std::string& what) {
  ASSERT_EQ(mine.size(), ref.size()) << what;
  std::vector<bool> used(ref.size(), false);
  for (const auto& r : mine) {  // match each root with its nearest reference root
    std::size_t best = 0;
    double best_d = INFINITY;
    for (std::size_t i = 0; i < ref.size(); ++i)
      if (!used[i] && std::abs(r - ref[i]) < best_d) {
        best_d = std::abs(r - ref[i]);
        best = i;
      }
    used[best] = true;
    EXPECT_LE(best_d, 1e-8 * std::max(1.0, std::abs(ref[best]))) << what << " root " << r;
  }
}

class LtiGolden : public ::testing::TestWithParam<std::string> {};

TEST_P(LtiGolden, TransferFunctionRootsAndCanonicalForm) {
  const json doc = load(GetParam());
  const auto model = model_of(doc);
  const lti::TransferFunction ref(doc["num"].get<std::vector<double>>(), doc["den"].get<std::vector<double>>());
  const auto tf = model.transfer_function();
  EXPECT_LE(relative_error(tf.numerator(), ref.numerator()), 1e-12);
  EXPECT_LE(relative_error(tf.denominator(), ref.denominator()), 1e-12);
  const auto cc = ref.controllable_canonical();
  const auto gold = tf2ss_of(doc);
  EXPECT_LE(relative_error(cc.a, gold.a), 1e-12);
  EXPECT_LE(relative_error(cc.b, gold.b), 1e-12);
  EXPECT_LE(relative_error(cc.c, gold.c), 1e-12);
  EXPECT_LE(relative_error(cc.d, gold.d), 1e-12);
  const auto poles = complexes(doc["poles"]);
  const auto zeros = complexes(doc["zeros"]);
  expect_roots(model.poles(), poles, GetParam() + " process-model poles");
  expect_roots(tf.poles(), poles, GetParam() + " transfer-function poles");
  expect_roots(lti::poles(model.state_space()), poles, GetParam() + " realization poles");
  expect_roots(model.zeros(), zeros, GetParam() + " process-model zeros");
  expect_roots(tf.zeros(), zeros, GetParam() + " transfer-function zeros");
}

TEST_P(LtiGolden, FrequencyResponse) {
  const json doc = load(GetParam());
  const auto model = model_of(doc);
  const auto omega = doc["freqresp"]["omega_rad_s"].get<std::vector<double>>();
  const auto h = complexes(doc["freqresp"]["h"]);
  const auto ss = model.state_space();
  const auto balanced = model.transfer_function().state_space();
  double worst = 0.0;
  for (std::size_t i = 0; i < omega.size(); ++i) {
    const auto delay = std::exp(std::complex<double>(0.0, -omega[i] * model.delay_s()));
    const double scale = std::abs(h[i]);
    worst = std::max(worst, std::abs(model.frequency_response(omega[i]) - h[i]) / scale);
    worst = std::max(worst, std::abs(lti::frequency_response(ss, omega[i]) * delay - h[i]) / scale);
    worst = std::max(worst, std::abs(lti::frequency_response(balanced, omega[i]) * delay - h[i]) / scale);
    worst = std::max(worst, std::abs(model.transfer_function().frequency_response(omega[i]) * delay - h[i]) / scale);
  }
  EXPECT_LE(worst, 1e-10) << GetParam();
  std::cout << "[golden] " << GetParam() << " freqresp max rel error " << worst << "\n";
}

TEST_P(LtiGolden, Cont2Discrete) {
  const json doc = load(GetParam());
  const auto model = model_of(doc);
  const auto gold = tf2ss_of(doc);
  for (const auto& [key, d] : doc["cont2discrete"].items()) {
    const double dt = d["sample_time_s"].get<double>();
    const auto hold = d["method"].get<std::string>() == "zoh" ? lti::Hold::zoh : lti::Hold::foh;
    const auto mine = lti::discretize(gold, dt, hold);
    EXPECT_LE(relative_error(mine.a, matrix(d["a"])), 1e-10) << GetParam() << " " << key;
    EXPECT_LE(relative_error(mine.b, matrix(d["b"])), 1e-10) << GetParam() << " " << key;
    EXPECT_LE(relative_error(mine.c, matrix(d["c"])), 1e-10) << GetParam() << " " << key;
    EXPECT_LE(relative_error(mine.d, matrix(d["d"])), 1e-10) << GetParam() << " " << key;
    // Input-output behaviour of the cascade realization's discretization.
    const auto ref = d["markov"].get<std::vector<double>>();
    const double err = relative_error(markov(lti::discretize(model.state_space(), dt, hold), ref.size()), ref);
    EXPECT_LE(err, 1e-9) << GetParam() << " " << key;
    std::cout << "[golden] " << GetParam() << " " << key << " markov max rel error " << err << "\n";
  }
}

TEST_P(LtiGolden, StepAndLsim) {
  const json doc = load(GetParam());
  const auto model = model_of(doc);
  const double dt = doc["lsim"]["sample_time_s"].get<double>();
  const auto ys = doc["step"]["y"].get<std::vector<double>>();
  const auto step = lti::step_response(model, dt * static_cast<double>(ys.size() - 1), dt);
  const double step_err = relative_error(step.values, ys);
  EXPECT_LE(step_err, 1e-8) << GetParam();
  const clearshape::UniformSeries u{0.0, dt, doc["lsim"]["u"].get<std::vector<double>>()};
  for (const auto& [key, hold] : {std::pair{"zoh", lti::Hold::zoh}, std::pair{"foh", lti::Hold::foh}}) {
    const auto y = lti::simulate(model, u, hold);
    const double err = relative_error(y.values, doc["lsim"][key].get<std::vector<double>>());
    EXPECT_LE(err, 1e-8) << GetParam() << " " << key;
    std::cout << "[golden] " << GetParam() << " lsim " << key << " max rel error " << err << "\n";
    if (model.delay_s() == 0.0) {  // the balanced canonical realization of the expanded H(s)
      const auto yt = lti::simulate(model.transfer_function(), u, hold);
      const double err_tf = relative_error(yt.values, doc["lsim"][key].get<std::vector<double>>());
      EXPECT_LE(err_tf, 1e-8) << GetParam() << " " << key << " (transfer function)";
      std::cout << "[golden] " << GetParam() << " lsim " << key << " via TransferFunction max rel error " << err_tf << "\n";
    }
  }
  if (doc["lsim"].contains("foh_x0")) {
    const auto& g = doc["lsim"]["foh_x0"];
    const auto x0v = g["x0"].get<std::vector<double>>();
    const Eigen::VectorXd x0 = Eigen::Map<const Eigen::VectorXd>(x0v.data(), static_cast<Eigen::Index>(x0v.size()));
    const auto y = lti::simulate(tf2ss_of(doc), u, lti::Hold::foh, 0.0, x0);
    EXPECT_LE(relative_error(y.values, g["y"].get<std::vector<double>>()), 1e-8) << GetParam() << " x0";
  }
  std::cout << "[golden] " << GetParam() << " step max rel error " << step_err << "\n";
}

INSTANTIATE_TEST_SUITE_P(Scipy, LtiGolden,
                         ::testing::Values("speed", "position", "p1d_int", "p1d_frac", "p2", "p2i", "p2u",
                                           "p3dzu_frac", "p3z_wide"));

}  // namespace
