// clearshape frf: the H1 frequency-response estimate of a record's output against its input, with
// the magnitude-squared coherence, by Welch averaging (MATLAB tfestimate/mscohere, scipy.signal
// csd/coherence; dsp/frf.hpp, docs/frf.md).
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "clearshape/core/error.hpp"
#include "clearshape/dsp/frf.hpp"
#include "clearshape/io/json.hpp"
#include "clearshape/io/table.hpp"
#include "command.hpp"
#include "io_columns.hpp"

namespace clearshape::cli {

namespace {

struct FrfState {
  std::string in;
  std::string input_column, output_column, time_column;
  double sample_time_s = 0.0;
  CLI::Option* sample_time_option = nullptr;
  double segment_s = 0.0;  ///< 0: MATLAB's default, 8 half-overlapping segments
  double overlap = 0.5;    ///< fraction of a segment
  std::string window = "hann";
  std::string out;
  bool json = false;
};

// The shortest segment that still resolves anything: 8 samples (5 one-sided bins).
constexpr std::size_t kMinSegmentSamples = 8;
// Coherence below which a bin's H1 is dominated by noise or nonlinearity (reported, docs/frf.md).
constexpr double kLowCoherence = 0.8;

struct FrfRecord {
  std::vector<double> input, output;
  double sample_time_s = 0.0;
  std::string input_name, output_name;
};

FrfRecord load(const FrfState& st) {
  const io::Table t = io::read_table(st.in);
  const bool have_ts = st.sample_time_option != nullptr && st.sample_time_option->count() > 0;
  const IoColumns c = choose_io_columns(t, st.input_column, st.output_column, st.time_column, have_ts, true);
  FrfRecord r;
  if (c.time) {
    r.sample_time_s = io::uniform_sample_time(t, t.names[*c.time]);
  } else if (have_ts) {
    require_positive("--sample-time", st.sample_time_s, "Give the sample time of the record in seconds.");
    r.sample_time_s = st.sample_time_s;
  } else {
    throw InputError(st.in, 0, "", "has no time column (time_s, time or t); give --time-column NAME or --sample-time SECONDS");
  }
  fmt::print(stderr, "clearshape frf: {}: {}\n", st.in, describe_io_columns(t, c, r.sample_time_s));
  refuse_converted_copy(t, c, r.sample_time_s, "frf");
  r.input = t.columns[c.input];
  r.output = t.columns[c.output];
  r.input_name = t.names[c.input];
  r.output_name = t.names[c.output];
  return r;
}

dsp::Window parse_window(const std::string& name) {
  const std::string w = lower(name);
  if (w == "hann") return dsp::Window::hann;
  if (w == "hamming") return dsp::Window::hamming;
  if (w == "rectangular" || w == "boxcar") return dsp::Window::rectangular;
  throw InvalidArgument(fmt::format("--window = '{}' is not valid; allowed: hann, hamming, rectangular", name));
}

dsp::WelchOptions welch_options(const FrfState& st, const FrfRecord& r) {
  const std::size_t n = r.input.size();
  const double record_s = static_cast<double>(n) * r.sample_time_s;
  const double min_s = static_cast<double>(kMinSegmentSamples) * r.sample_time_s;
  dsp::WelchOptions o;
  o.window = parse_window(st.window);
  if (st.segment_s == 0.0) {
    o.segment_length = dsp::matlab_default_segment_length(n);
  } else if (!(st.segment_s >= min_s && st.segment_s <= record_s)) {
    throw InvalidArgument(fmt::format("--segment-s = {:g} is out of range; allowed: {:g} … {:g} s ({} samples … the record "
                                      "of {} samples at {:g} s)", st.segment_s, min_s, record_s, kMinSegmentSamples, n,
                                      r.sample_time_s));
  } else {
    o.segment_length = static_cast<std::size_t>(std::llround(st.segment_s / r.sample_time_s));
  }
  if (o.segment_length < kMinSegmentSamples) {
    throw InvalidArgument(fmt::format("frf: {}: {} samples are too few; allowed: at least {} (a segment of {} samples)",
                                      st.in, n, 2 * kMinSegmentSamples, kMinSegmentSamples));
  }
  if (!(st.overlap >= 0.0 && st.overlap < 1.0)) {
    throw InvalidArgument(fmt::format("--overlap = {:g} is out of range; allowed: 0 ≤ overlap < 1 (a fraction of the segment)",
                                      st.overlap));
  }
  o.overlap = std::min(o.segment_length - 1,
                       static_cast<std::size_t>(std::llround(st.overlap * static_cast<double>(o.segment_length))));
  return o;
}

nlohmann::ordered_json numbers(const std::vector<double>& v) {
  nlohmann::ordered_json a = nlohmann::ordered_json::array();
  for (double x : v) a.push_back(std::isfinite(x) ? nlohmann::ordered_json(x) : nlohmann::ordered_json(nullptr));
  return a;
}

struct FrfSummary {
  std::size_t peak = 0;           ///< bin of the largest |H1| above DC
  std::size_t low_coherence = 0;  ///< bins above DC with coherence < kLowCoherence
};

FrfSummary summarise(const dsp::FrequencyResponse& h, const std::vector<double>& magnitude) {
  FrfSummary s;
  for (std::size_t k = 1; k < magnitude.size(); ++k) {
    if (std::isfinite(magnitude[k]) && (s.peak == 0 || magnitude[k] > magnitude[s.peak])) s.peak = k;
    if (!(h.coherence[k] >= kLowCoherence)) ++s.low_coherence;
  }
  return s;
}

nlohmann::ordered_json frf_json(const FrfState& st, const FrfRecord& r, const dsp::WelchOptions& o,
                                const dsp::FrequencyResponse& h, const FrfSummary& s) {
  auto doc = io::make_document();
  doc["command"] = "frf";
  doc["file"] = st.in;
  doc["input_column"] = r.input_name;
  doc["output_column"] = r.output_name;
  doc["estimator"] = "H1 = Pxy/Pxx, coherence |Pxy|^2/(Pxx Pyy), Welch averaging";
  doc["sample_time_s"] = r.sample_time_s;
  doc["segment_samples"] = o.segment_length;
  doc["segment_s"] = static_cast<double>(o.segment_length) * r.sample_time_s;
  doc["overlap_samples"] = *o.overlap;
  doc["window"] = lower(st.window);
  doc["segments"] = h.segments;
  doc["resolution_hz"] = h.frequency_hz.size() > 1 ? h.frequency_hz[1] : 0.0;
  const auto magnitude = h.magnitude();
  doc["peak"] = {{"frequency_hz", h.frequency_hz[s.peak]}, {"magnitude", magnitude[s.peak]},
                 {"phase_deg", h.phase_deg()[s.peak]}, {"coherence", numbers({h.coherence[s.peak]})[0]}};
  doc["low_coherence_threshold"] = kLowCoherence;
  doc["low_coherence_bins"] = s.low_coherence;
  doc["frequency_hz"] = h.frequency_hz;
  doc["magnitude"] = numbers(magnitude);
  doc["phase_deg"] = numbers(h.phase_deg());
  doc["coherence"] = numbers(h.coherence);
  if (!st.out.empty()) doc["out"] = st.out;
  return doc;
}

void print_summary(const FrfRecord& r, const dsp::WelchOptions& o, const dsp::FrequencyResponse& h, const FrfSummary& s) {
  fmt::print("frf of '{}' against '{}': H1 with coherence, {} segments of {} samples ({:g} s), {} overlapping, "
             "resolution {:.4g} Hz\n",
             r.output_name, r.input_name, h.segments, o.segment_length, static_cast<double>(o.segment_length) * r.sample_time_s,
             *o.overlap, h.frequency_hz.size() > 1 ? h.frequency_hz[1] : 0.0);
  fmt::print("  largest |H1| {:.6g} at {:.6g} Hz, phase {:.4g}°, coherence {:.4f}\n", h.magnitude()[s.peak],
             h.frequency_hz[s.peak], h.phase_deg()[s.peak], h.coherence[s.peak]);
  fmt::print("  {} of {} bins above DC have coherence below {:g} (H1 there is noise or nonlinearity)\n", s.low_coherence,
             h.frequency_hz.size() - 1, kLowCoherence);
}

void run_frf(const FrfState& st) {
  const FrfRecord r = load(st);
  const dsp::WelchOptions o = welch_options(st, r);
  const auto h = dsp::estimate_frequency_response(r.input, r.output, 1.0 / r.sample_time_s, o);
  const auto magnitude = h.magnitude();
  const auto phase = h.phase_deg();
  const FrfSummary s = summarise(h, magnitude);
  const std::vector<std::string> names{"frequency_hz", "magnitude", "phase_deg", "coherence"};
  const std::vector<const std::vector<double>*> columns{&h.frequency_hz, &magnitude, &phase, &h.coherence};
  if (!st.out.empty()) {
    io::write_csv(st.out, names, columns);
    fmt::print(stderr, "clearshape frf: wrote {} ({} rows)\n", st.out, h.frequency_hz.size());
  }
  if (st.json) {
    print_json(frf_json(st, r, o, h, s));
  } else if (st.out.empty()) {
    const std::string csv = io::format_csv(names, columns);
    std::fwrite(csv.data(), 1, csv.size(), stdout);  // a write error is reported by main (exit 1)
  } else {
    print_summary(r, o, h, s);
  }
}

void setup_frf(CLI::App& sub) {
  auto st = std::make_shared<FrfState>();
  sub.add_option("--in", st->in, "Record (CSV or whitespace columns, header optional) with input and output columns")
      ->required();
  sub.add_option("--input,--input-column", st->input_column, "Input (excitation) column: name or 1-based index");
  sub.add_option("--output,--output-column", st->output_column, "Output (response) column: name or 1-based index");
  sub.add_option("--time-column", st->time_column, "Time column in seconds (default: time_s, time or t if present)");
  st->sample_time_option = sub.add_option("--sample-time", st->sample_time_s, "Sample time in s when there is no time column");
  sub.add_option("--segment-s", st->segment_s,
                 "Welch segment length, s (default: 8 half-overlapping segments, MATLAB's tfestimate); resolution = 1/segment");
  sub.add_option("--overlap", st->overlap, "Overlap of consecutive segments, a fraction in [0, 1)")->capture_default_str();
  sub.add_option("--window", st->window, "Segment window: hann, hamming, rectangular")->capture_default_str();
  sub.add_option("--out", st->out, "Write frequency_hz, magnitude, phase_deg, coherence to this CSV (atomically)");
  sub.add_flag("--json", st->json, "Print the estimate and its summary as JSON");
  sub.footer("Without --out or --json the CSV goes to stdout. Magnitude in output units per input unit, phase in (-180, 180]°.\n"
             "H1 is unbiased by output noise; coherence near 1 says the output is linear in the input there (docs/frf.md).");
  sub.callback([st] { run_frf(*st); });
}

const bool frf_registered = register_command(
    {"frf", "Frequency response (H1) and coherence of a record's output against its input (MATLAB tfestimate/mscohere)", 33,
     setup_frf});

}  // namespace

}  // namespace clearshape::cli
