#pragma once
// Reading the SciPy golden files tests/golden/dsp_*.json (written by tests/golden/gen_dsp.py).
#include <algorithm>
#include <cmath>
#include <complex>
#include <cstddef>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "clearshape/dsp/sos.hpp"
#include "clearshape/dsp/welch.hpp"
#include "support/paths.hpp"

namespace clearshape::dsp::testing {

inline nlohmann::json load_golden(const std::string& name) {
  std::ifstream in(clearshape::testing::golden_path(name));
  if (!in) throw std::runtime_error("cannot open golden file " + name);
  return nlohmann::json::parse(in);
}

inline std::vector<double> to_vector(const nlohmann::json& j) { return j.get<std::vector<double>>(); }

inline std::vector<std::complex<double>> to_complex(const nlohmann::json& j) {
  std::vector<std::complex<double>> out;
  for (const auto& pair : j) out.emplace_back(pair[0].get<double>(), pair[1].get<double>());
  return out;
}

inline std::vector<Section> to_sections(const nlohmann::json& j) {
  std::vector<Section> out;
  for (const auto& r : j) {
    out.push_back(Section{r[0].get<double>(), r[1].get<double>(), r[2].get<double>(),
                          r[3].get<double>(), r[4].get<double>(), r[5].get<double>()});
  }
  return out;
}

/// max_i |a_i − b_i| (sizes must agree).
inline double max_abs_diff(const std::vector<double>& a, const std::vector<double>& b) {
  EXPECT_EQ(a.size(), b.size());
  double m = 0.0;
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) m = std::max(m, std::abs(a[i] - b[i]));
  return m;
}

inline double max_abs(const std::vector<double>& a) {
  double m = 0.0;
  for (double v : a) m = std::max(m, std::abs(v));
  return m;
}

/// Largest coefficient difference between two cascades, each row's difference relative to the
/// largest magnitude in that scipy row (so a tiny gain in b of the first section is compared
/// relative to its own size, too).
inline double max_sos_diff(const std::vector<Section>& ours, const std::vector<Section>& scipy) {
  EXPECT_EQ(ours.size(), scipy.size());
  double m = 0.0;
  for (std::size_t i = 0; i < std::min(ours.size(), scipy.size()); ++i) {
    const Section& a = ours[i];
    const Section& b = scipy[i];
    const double bs[3] = {b.b0, b.b1, b.b2};
    const double as[3] = {b.a0, b.a1, b.a2};
    const double ob[3] = {a.b0, a.b1, a.b2};
    const double oa[3] = {a.a0, a.a1, a.a2};
    double nb = 0.0, na = 0.0;
    for (int k = 0; k < 3; ++k) {
      nb = std::max(nb, std::abs(bs[k]));
      na = std::max(na, std::abs(as[k]));
    }
    for (int k = 0; k < 3; ++k) {
      m = std::max(m, std::abs(ob[k] - bs[k]) / nb);
      m = std::max(m, std::abs(oa[k] - as[k]) / na);
    }
  }
  return m;
}

/// WelchOptions from a golden case's scipy keywords (window, nperseg, noverlap, nfft, detrend, scaling).
inline WelchOptions options_of(const nlohmann::json& c) {
  WelchOptions o;
  const std::string window = c["window"].get<std::string>();
  o.window = window == "hann" ? Window::hann
             : window == "hamming" ? Window::hamming
                                   : Window::rectangular;
  o.segment_length = c["nperseg"].get<std::size_t>();
  if (c.contains("noverlap")) o.overlap = c["noverlap"].get<std::size_t>();
  if (c.contains("nfft")) o.fft_length = c["nfft"].get<std::size_t>();
  if (c.contains("detrend")) {
    const std::string d = c["detrend"].get<std::string>();
    o.detrend = d == "linear" ? Detrend::linear : d == "none" ? Detrend::none : Detrend::constant;
  }
  if (c.contains("scaling") && c["scaling"].get<std::string>() == "spectrum") {
    o.scaling = SpectralScaling::spectrum;
  }
  return o;
}

}  // namespace clearshape::dsp::testing
