// The fit's internal sampled model against lti::SampledModel (an independent code path: lti's
// own realization and hold integrals), and its exact sensitivities against central differences.
// Tolerances: taps/outputs 1e-11 relative (two expm evaluations of the same matrices);
// Jacobian vs central differences 1e-6 relative to the column's largest value (the differences
// themselves carry ~1e-8 truncation/rounding error).
#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "../../src/ident/process_sampling.hpp"
#include "clearshape/lti/simulate.hpp"

namespace lti = clearshape::lti;
namespace detail = clearshape::ident::detail;

namespace {

struct Case {
  const char* code;
  lti::ProcessParameters p;
};

std::vector<Case> cases() {
  std::vector<Case> c;
  lti::ProcessParameters p;
  p = {};
  p.kp = 25.47; p.tz = -0.0398; p.zeta = 0.288; p.tw = 0.0479; p.tp3 = 0.0857;
  c.push_back({"P3UZ", p});
  p.td = 0.0123;  // fractional delay (12.3 samples at 1 ms)
  c.push_back({"P3DUZ", p});
  p = {};
  p.kp = -1.7; p.tp1 = 0.05; p.tz = 0.02; p.td = 0.0037;
  c.push_back({"P1DZ", p});  // feedthrough D = Kp Tz/Tp
  p = {};
  p.kp = 2.0; p.tp1 = 0.2; p.tp2 = 0.01; p.tz = 0.03;
  c.push_back({"P2IZ", p});
  p = {};
  p.kp = 0.9959; p.tz = 0.0042; p.zeta = 1.3; p.tw = 0.0102; p.tp3 = 0.0034; p.td = 0.002;
  c.push_back({"P3DUZ", p});  // overdamped pair, integer delay
  return c;
}

std::vector<double> prbs(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<double> u(n);
  double level = 1.0;
  for (std::size_t k = 0; k < n; ++k) {
    if (k % 7 == 0 && (rng() & 1U)) level = -level;
    u[k] = level + 0.3 * std::sin(0.01 * static_cast<double>(k));
  }
  return u;
}

}  // namespace

TEST(Sampling, MatchesLtiSampledModelAndSimulation) {
  for (const auto hold : {lti::Hold::zoh, lti::Hold::foh}) {
    for (const auto& c : cases()) {
      const lti::ProcessModel model(c.code, c.p);
      const double T = 1e-3;
      const auto values = model.to_vector();
      const detail::Sampled s = detail::sample(model.structure(), values, T, hold, false);
      const lti::SampledModel ref(model, T, hold);
      ASSERT_EQ(s.n, ref.order()) << c.code;
      EXPECT_EQ(s.delay_samples, ref.delay_samples()) << c.code;
      EXPECT_NEAR(s.fraction, ref.delay_fraction(), 1e-12) << c.code;
      EXPECT_LE((s.phi - ref.phi()).cwiseAbs().maxCoeff(), 1e-11) << c.code;
      EXPECT_LE((s.taps - ref.input_taps()).cwiseAbs().maxCoeff(), 1e-11 * (1.0 + ref.input_taps().cwiseAbs().maxCoeff()))
          << c.code;
      EXPECT_LE((s.c - ref.c().row(0)).cwiseAbs().maxCoeff(), 1e-12 * (1.0 + ref.c().cwiseAbs().maxCoeff())) << c.code;
      EXPECT_LE((s.h - ref.output_taps()).cwiseAbs().maxCoeff(), 1e-12) << c.code;

      const auto u = prbs(800, 3);
      std::vector<double> y(u.size());
      detail::KernelInput in;
      in.model = &s;
      in.input = u;
      ASSERT_TRUE(detail::simulate(in, y.data(), nullptr));
      const auto yref = lti::simulate(ref, clearshape::UniformSeries{0.0, T, u});
      double scale = 0.0, err = 0.0;
      for (std::size_t k = 0; k < y.size(); ++k) {
        scale = std::max(scale, std::abs(yref.values[k]));
        err = std::max(err, std::abs(y[k] - yref.values[k]));
      }
      EXPECT_LE(err, 1e-10 * scale) << c.code << " hold " << static_cast<int>(hold);
    }
  }
}

TEST(Sampling, SensitivitiesMatchCentralDifferences) {
  for (const auto hold : {lti::Hold::zoh, lti::Hold::foh}) {
    for (const auto& c : cases()) {
      const lti::ProcessModel model(c.code, c.p);
      const double T = 1e-3;
      const auto values = model.to_vector();
      const std::size_t np = values.size();
      const detail::Sampled s = detail::sample(model.structure(), values, T, hold, true);
      const auto u = prbs(600, 5);
      const std::size_t n = u.size();
      std::vector<int> dirs(np);
      std::vector<double> scale(np, 1.0);
      for (std::size_t i = 0; i < np; ++i) dirs[i] = static_cast<int>(i);
      std::vector<double> x0(static_cast<std::size_t>(s.n));
      for (std::size_t i = 0; i < x0.size(); ++i) x0[i] = 0.1 * static_cast<double>(i + 1);
      detail::KernelInput in;
      in.model = &s;
      in.input = u;
      in.x0 = x0;
      in.y0 = 0.5;
      in.directions = dirs;
      in.scale = scale;
      in.d_x0 = true;
      in.d_y0 = true;
      const std::size_t cols = detail::jacobian_columns(in);
      std::vector<double> y(n), jac(n * cols);
      ASSERT_TRUE(detail::simulate(in, y.data(), jac.data()));
      for (std::size_t i = 0; i < np; ++i) {
        const double h = 1e-6 * std::max(1e-3, std::abs(values[i]));
        auto vp = values, vm = values;
        vp[i] += h;
        vm[i] -= h;
        const auto sp = detail::sample(model.structure(), vp, T, hold, false);
        const auto sm = detail::sample(model.structure(), vm, T, hold, false);
        ASSERT_EQ(sp.delay_samples, s.delay_samples) << "step crosses a sample boundary";
        std::vector<double> yp(n), ym(n);
        detail::KernelInput a = in, b = in;
        a.model = &sp;
        b.model = &sm;
        detail::simulate(a, yp.data(), nullptr);
        detail::simulate(b, ym.data(), nullptr);
        double big = 0.0, err = 0.0;
        for (std::size_t k = 0; k < n; ++k) {
          const double fd = (yp[k] - ym[k]) / (2.0 * h);
          big = std::max(big, std::abs(fd));
          err = std::max(err, std::abs(fd - jac[k * cols + i]));
        }
        EXPECT_LE(err, 1e-6 * big + 1e-9) << c.code << " parameter " << model.structure().parameter_names()[i]
                                          << " hold " << static_cast<int>(hold);
      }
      // x0 and y0 columns: y is linear in them.
      for (std::size_t j = 0; j < x0.size(); ++j) {
        auto xp = x0;
        xp[j] += 1.0;
        detail::KernelInput a = in;
        a.x0 = xp;
        std::vector<double> yp(n);
        detail::simulate(a, yp.data(), nullptr);
        for (std::size_t k = 0; k < n; k += 37) EXPECT_NEAR(yp[k] - y[k], jac[k * cols + np + j], 1e-9);
      }
      for (std::size_t k = 0; k < n; k += 41) EXPECT_EQ(jac[k * cols + np + x0.size()], 1.0);
    }
  }
}
