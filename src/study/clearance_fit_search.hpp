#pragma once
// The clearance fit's machinery (clearance_fit.cpp plans, runs and tabulates with it): the scaled
// fit variables, the model they stand for, the residual against the record, one NLopt BOBYQA
// search over a subset of the variables, the local 1σ and the sensor bandwidth choice.
//
// Fit variables u (all six; a fixed parameter keeps the problem's start value):
//   log K_ref (K_ref = K·δ_ref^(n−1), the secant stiffness at the reference deflection), log D
//   (with the Flores law: the restitution e itself, in [0.05, 1]),
//   log play, n, c/(J·a_ref) and b/(J/T) — the joint's Coulomb torque and viscous coefficient
//   (thesis Eq. 2.9, regularized) scaled by the record: a_ref = peak |measured link rate| / T
//   (the deceleration that would stop the fastest link motion within the window T), 1/T the
//   slowest decay rate the window can show. The friction variables are linear: 0 (no friction)
//   is their lower bound and a finding, not a cut-short search.
#include <array>
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include <nlopt.h>

#include "clearshape/study/model.hpp"

namespace clearshape::study::fit_detail {

enum Param : std::size_t { kStiffness = 0, kDamping = 1, kPlay = 2, kExponent = 3, kCoulomb = 4, kViscous = 5 };
inline constexpr std::size_t kParams = 6;
inline constexpr std::array<const char*, kParams> kParamNames{"stiffness", "damping", "play", "exponent", "coulomb", "viscous"};

using Vars = std::array<double, kParams>;

struct Setup {
  const ClearanceFitProblem* p = nullptr;
  std::array<bool, kParams> free{};
  double delta_ref_rad = 1e-3;
  double coulomb_scale_n_m = 1.0;   // J·a_ref: c = coulomb_scale · u[kCoulomb]
  double viscous_scale = 1.0;       // J/T:     b = viscous_scale · u[kViscous]
  Vars lower{}, upper{};
  std::size_t samples = 0;
  double low_pass_hz = 0.0;  // the sensor low-pass applied to the model's link rate (< 0: profiled)
  Vars step{0.3, 0.3, 0.3, 0.15, 0.3, 0.3};  // initial steps (sensitivity-scaled)
};

/// The name of parameter i in the outputs: kParamNames, "restitution" for kDamping with the Flores law.
std::string param_name(const Setup& s, std::size_t i);

/// The model for variables u (fixed parameters from the problem's start).
ClearanceModel model_of(const Setup& s, const Vars& u);

/// Residual model − measured over the compared samples (throws RuntimeError if CVODE fails).
std::vector<double> residual(const Setup& s, const ClearanceModel& m);

double rms(const std::vector<double>& r);

/// RMS error of model m; with s.low_pass_hz < 0, the least over the sensor bandwidth grid.
double rms_error(const Setup& s, const ClearanceModel& m);

struct SearchResult {
  Vars u{};
  double rms = 0.0;
  int evaluations = 0;
  nlopt_result status = NLOPT_FAILURE;
};

/// One BOBYQA search over the variables `active` (the others held at `start`), stopped by the
/// trust radius `tolerance` (scaled like the steps) or the problem's max_evaluations.
SearchResult run_search(const Setup& s, const Vars& start, const std::vector<std::size_t>& active, double tolerance);

bool is_convergence(nlopt_result r);

/// Local 1σ of the variables `active` at u: σ²(JᵀJ)⁻¹ with the AR(1)-inflated σ² (NaN: singular).
std::vector<double> std_errors(const Setup& s, const Vars& u, const std::vector<std::size_t>& active);

/// RMS contact deflection of a response: |motor − link| − half play, where positive (rad).
double rms_deflection_rad(const ModelResponse& r, double play_rad);

/// The sensor bandwidth of the grid that best explains the record for model m (one simulation);
/// `scan` (optional) receives (f_c, RMS) for every bandwidth.
double choose_low_pass(const Setup& s, const ClearanceModel& m, std::vector<std::pair<double, double>>* scan);

}  // namespace clearshape::study::fit_detail
