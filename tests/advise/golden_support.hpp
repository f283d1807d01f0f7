#pragma once
// Shared by the advise tests: the golden files of tests/golden/gen_recommend.py.
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "clearshape/advise/mode_estimate.hpp"
#include "clearshape/advise/recommend.hpp"
#include "clearshape/advise/spectrum_input.hpp"
#include "support/paths.hpp"

namespace advise_test {

inline const nlohmann::json& klipper_reference() {
  static const nlohmann::json doc = [] {
    std::ifstream in(clearshape::testing::golden_path("recommend_klipper.json"));
    return nlohmann::json::parse(in);
  }();
  return doc;
}

inline const nlohmann::json& klipper_case(const std::string& name) {
  for (const auto& c : klipper_reference()["cases"]) {
    if (c["case"] == name) return c;
  }
  throw std::runtime_error("no golden case " + name);
}

inline clearshape::advise::MeasuredSpectrum load(const std::string& file, const std::string& column) {
  clearshape::advise::SpectrumRequest r;
  r.path = clearshape::testing::golden_path(file);
  r.column = column;
  return clearshape::advise::load_spectrum(r);
}

/// A golden PSD file of gen_recommend.py as written: its independent implementation of Klipper's
/// selection scores the file's PSD without Klipper's normalisation (÷ (f + 0.1 Hz), which
/// Klipper's parse_log applies to a file without shaper columns), so the selection is compared on
/// the same PSD. The normalisation itself is checked against Klipper's parse_log in
/// test_klipper_pick.cpp.
inline clearshape::advise::MeasuredSpectrum load_as_written(const std::string& file, const std::string& column) {
  clearshape::advise::MeasuredSpectrum s = load(file, column);
  s.klipper_normalizes = false;
  return s;
}

/// A measured spectrum and the modes estimated from it: what a recommendation starts from.
struct SpectrumCase {
  clearshape::advise::MeasuredSpectrum spectrum;
  std::vector<clearshape::advise::ModeEstimate> modes;
};

/// The recommendation's candidate called `name` (throws if it has none).
inline const clearshape::advise::CandidateResult& find(const clearshape::advise::Recommendation& r,
                                                       const std::string& name) {
  for (const auto& c : r.candidates) {
    if (c.name == name) return c;
  }
  throw std::runtime_error("no candidate " + name);
}

}  // namespace advise_test
