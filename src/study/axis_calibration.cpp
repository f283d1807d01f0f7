#include "clearshape/study/axis_calibration.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "clearshape/core/error.hpp"
#include "clearshape/dsp/frf.hpp"
#include "clearshape/study/recommend_report.hpp"

namespace clearshape::study {

void AxisCalibrationRequest::validate() const {
  if (excitations.empty()) throw InvalidArgument("axis calibration: excitations: at least one run is needed");
  if (!(duration_s > 0.0 && duration_s <= 600.0)) {
    throw InvalidArgument(fmt::format("axis calibration: duration_s = {:g}: allowed (0, 600] s", duration_s));
  }
  if (from_s && !(*from_s >= 0.0 && *from_s < duration_s)) {
    throw InvalidArgument(fmt::format("axis calibration: from_s = {:g}: allowed [0, duration_s = {:g}) s", *from_s,
                                      duration_s));
  }
  if (!(segment_s >= 0.0 && segment_s <= duration_s)) {
    throw InvalidArgument(fmt::format("axis calibration: segment_s = {:g}: allowed 0 (automatic) … duration_s", segment_s));
  }
}

std::vector<signal::Signal> step_excitations(const std::vector<double>& amplitudes, double start_s, double rise_s) {
  if (amplitudes.empty()) throw InvalidArgument("axis calibration: amplitudes: at least one step is needed");
  std::vector<signal::Signal> out;
  for (const double a : amplitudes) {
    if (!(std::isfinite(a) && a != 0.0)) {
      throw InvalidArgument(fmt::format("axis calibration: amplitude {:g}: allowed a finite, non-zero value", a));
    }
    out.emplace_back(signal::Step{.amplitude = a, .start_s = start_s, .rise_s = rise_s});
  }
  return out;
}

namespace {

std::string run_label(const signal::Signal& s) {
  if (const auto* step = s.get_if<signal::Step>()) return fmt::format("step {:g}", step->amplitude);
  if (const auto* c = s.get_if<signal::Chirp>()) {
    return fmt::format("chirp {:g} {:g}–{:g} Hz", c->amplitude, c->f0_hz, c->f1_hz);
  }
  return std::string(s.type());
}

// The band a forced response is read in: a chirp's sweep, else everything above 0 Hz.
std::pair<double, double> excitation_band_hz(const signal::Signal& s, double sample_time_s) {
  if (const auto* c = s.get_if<signal::Chirp>()) return {std::min(c->f0_hz, c->f1_hz), std::max(c->f0_hz, c->f1_hz)};
  return {0.0, 0.5 / sample_time_s};
}

// The joint's transmissibility from the motor's angle to the link's, |T(f)| = |H1(f)| / (2πf) with
// H1 = P(motor_deg, gyro_deg_s) / P(motor_deg) (Bendat & Piersol, Random Data, ch. 9; the gyro reads
// the link's rate), squared, in the excitation's band: under a forced excitation the link's PSD
// follows the excitation (a chirp's rate grows with f), its ratio to the motor's does not.
advise::MeasuredSpectrum transmissibility(const AxisCalibrationRun& run, const signal::Signal& excitation, std::size_t k0,
                                          double sample_time_s, double segment_s) {
  const std::span<const double> motor(run.record.motor_deg.data() + k0, run.record.size() - k0);
  const std::span<const double> gyro(run.record.gyro_deg_s.data() + k0, run.record.size() - k0);
  dsp::WelchOptions o;
  o.segment_length = segment_s > 0.0 ? static_cast<std::size_t>(std::llround(segment_s / sample_time_s))
                                     : std::clamp<std::size_t>(std::bit_floor(motor.size() / 4), 64, motor.size());
  o.fft_length = 4 * o.segment_length;  // as advise::spectrum_of_series: a finer grid for the peak
  const dsp::FrequencyResponse fr = dsp::estimate_frequency_response(motor, gyro, 1.0 / sample_time_s, o);
  const auto [lo_hz, hi_hz] = excitation_band_hz(excitation, sample_time_s);
  advise::MeasuredSpectrum s;
  for (std::size_t k = 0; k < fr.frequency_hz.size(); ++k) {
    const double f = fr.frequency_hz[k];
    if (f <= 0.0 || f < lo_hz || f > hi_hz || !std::isfinite(std::abs(fr.response[k]))) continue;
    s.frequency_hz.push_back(f);
    s.power.push_back(std::norm(fr.response[k]) / std::pow(2.0 * std::numbers::pi * f, 2));
  }
  if (s.frequency_hz.size() < 8) {
    throw InvalidArgument(fmt::format("axis calibration: the {} run's band {:g}–{:g} Hz holds {} frequency bins; widen "
                                      "the sweep or lengthen the run", run.label, lo_hz, hi_hz, s.frequency_hz.size()));
  }
  s.segments = fr.segments;
  s.resolution_hz = 1.0 / (static_cast<double>(o.segment_length) * sample_time_s);
  s.column = "transmissibility motor_deg → gyro_deg_s";
  return s;
}

// A run's command still changing in its last quarter is a forced excitation (a chirp).
bool is_forced(const std::vector<double>& command) {
  for (std::size_t k = 3 * command.size() / 4 + 1; k < command.size(); ++k) {
    if (command[k] != command[k - 1]) return true;
  }
  return false;
}

}  // namespace

std::vector<AxisCalibrationRun> record_calibration_runs(rig::SerialRig& board, const AxisCalibrationRequest& request) {
  request.validate();
  std::vector<AxisCalibrationRun> runs;
  const double rate_hz = 1.0 / board.sample_time_s();
  const auto samples = static_cast<std::size_t>(std::llround(request.duration_s * rate_hz)) + 1;
  for (const signal::Signal& excitation : request.excitations) {
    rig::BoardRunOptions o = request.board;
    o.command = signal::sample(excitation, rate_hz, request.duration_s).values;
    o.command.resize(samples, o.command.empty() ? 0.0 : o.command.back());
    AxisCalibrationRun run{run_label(excitation), {}, {}};
    run.outcome = rig::run_on_board(board, o, run.record);
    runs.push_back(std::move(run));
    if (!runs.back().outcome.complete()) break;
  }
  return runs;
}

double analysis_start_s(const std::vector<double>& command, double sample_time_s, const AxisCalibrationRequest& request) {
  if (request.from_s) return *request.from_s;
  std::size_t first = command.size(), last = 0;
  for (std::size_t k = 1; k < command.size(); ++k) {
    if (command[k] != command[k - 1]) {
      first = std::min(first, k - 1);
      last = k;
    }
  }
  if (first == command.size()) return 0.0;                           // a constant command: all of it
  if (is_forced(command)) return static_cast<double>(first) * sample_time_s;  // still moving: the forced response
  return static_cast<double>(last + 1) * sample_time_s;             // the free decay after the move
}

AxisCalibration analyse_calibration(const std::vector<AxisCalibrationRun>& runs, const AxisCalibrationRequest& request,
                                    double sample_time_s) {
  request.validate();
  AxisCalibration out;
  if (runs.size() > request.excitations.size()) {
    throw InvalidArgument(fmt::format("axis calibration: {} runs for {} excitations: the runs must come from this request",
                                      runs.size(), request.excitations.size()));
  }
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const AxisCalibrationRun& run = runs[i];
    if (!run.outcome.complete()) {
      throw RuntimeError(fmt::format("axis calibration: the {} run is not complete ({}); nothing is recommended from a "
                                     "degraded record", run.label, fmt::join(run.outcome.degraded, "; ")));
    }
    const double from_s = analysis_start_s(run.record.command, sample_time_s, request);
    const auto k0 = static_cast<std::size_t>(std::llround(from_s / sample_time_s));
    if (k0 + 64 > run.record.size()) {
      throw InvalidArgument(fmt::format("axis calibration: the {} run's analysis window from {:g} s has fewer than 64 "
                                        "samples; make --duration longer or --from-s earlier", run.label, from_s));
    }
    advise::MeasuredSpectrum s;
    if (is_forced(run.record.command)) {
      s = transmissibility(run, request.excitations[i], k0, sample_time_s, request.segment_s);
    } else {
      UniformSeries gyro{static_cast<double>(k0) * sample_time_s, sample_time_s,
                         {run.record.gyro_deg_s.begin() + static_cast<std::ptrdiff_t>(k0), run.record.gyro_deg_s.end()}};
      s = advise::spectrum_of_series(gyro, request.segment_s);
      s.column = "gyro_deg_s";
    }
    s.source = run.label;
    out.spectra.push_back(std::move(s));
    out.window_start_s.push_back(from_s);
  }
  if (out.spectra.empty()) throw InvalidArgument("axis calibration: no run to analyse");
  out.estimation = advise::estimate_modes(out.spectra, request.modes);
  out.recommendation = advise::recommend(out.spectra, out.estimation.modes, request.options);
  return out;
}

exports::ShaperDesign recommended_design(const advise::Recommendation& r, const advise::RecommendOptions& options) {
  if (!r.chosen || !r.candidates[*r.chosen].shaper) {
    throw RuntimeError(fmt::format("axis calibration: no shaper is recommended: {}{}", r.reason,
                                   r.warning.empty() ? "" : "; " + r.warning));
  }
  const advise::CandidateResult& c = r.candidates[*r.chosen];
  const auto star = c.name.find('*');
  exports::ShaperDesign d{.shaper = *c.shaper,
                          .method = shaping::method_from_string(c.name.substr(0, star)),
                          .mode = shaping::Mode::from_hz(c.design_frequency_hz[0], c.design_damping),
                          .second_mode = std::nullopt,
                          .vtol = std::nullopt,
                          .band_hz = std::nullopt,
                          .command = shape_command(c, r, options.update_grid_hz)};
  if (star != std::string::npos && c.design_frequency_hz.size() > 1 && r.modes.size() > 1) {
    d.second_mode = shaping::Mode::from_hz(c.design_frequency_hz[1], std::clamp(r.modes[1].damping_ratio, 0.0, 0.9));
  }
  if (d.method == shaping::Method::ei || d.method == shaping::Method::ei2 || d.method == shaping::Method::ei3 ||
      d.method == shaping::Method::si) {
    d.vtol = options.vtol;
  }
  if (d.method == shaping::Method::si) {  // the band shape_command gives: the worst case's frequency scales
    const double half = std::max(r.frequency_scales.size() > 1 ? r.frequency_scales.back() - 1.0 : 0.0, 0.02);
    d.band_hz = {c.design_frequency_hz[0] * (1.0 - half), c.design_frequency_hz[0] * (1.0 + half)};
  }
  if (options.update_grid_hz > 0.0) d.update_grid_hz = options.update_grid_hz;
  return d;
}

}  // namespace clearshape::study
