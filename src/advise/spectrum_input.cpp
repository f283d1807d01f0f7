#include "clearshape/advise/spectrum_input.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cctype>
#include <cmath>

#include <fmt/format.h>

#include "clearshape/core/error.hpp"
#include "clearshape/dsp/welch.hpp"
#include "clearshape/io/atomic_file.hpp"
#include "clearshape/io/table.hpp"
#include "clearshape/io/time_column.hpp"
#include "klipper_csv.hpp"

namespace clearshape::advise {

namespace {

std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

// Klipper axis from a --column value: 0 x, 1 y, 2 z, 3 xyz (sum of the three PSDs).
std::size_t klipper_axis(const std::string& column, bool psd_file, const std::string& source) {
  const std::string c = lower(column);
  const std::string prefix = psd_file ? "psd_" : "accel_";
  const std::vector<std::string> names{"x", "y", "z", "xyz"};
  for (std::size_t a = 0; a < names.size(); ++a) {
    if (c.empty() && a == 3) return a;
    if (c == names[a] || c == prefix + names[a] || (a == 3 && (c == "all" || c == "psd_xyz" || c == "accel_xyz"))) return a;
  }
  throw InvalidArgument(fmt::format("--column {}: {} is a Klipper {} file; allowed: {}x, {}y, {}z, xyz (the sum of the three "
                                    "axes' PSDs, as Klipper's psd_xyz)",
                                    column, source, psd_file ? "PSD" : "accelerometer", prefix, prefix, prefix));
}

// [from, end) samples of a record starting at start_s, from the request's window in seconds.
std::pair<std::size_t, std::size_t> window(const SpectrumRequest& r, std::size_t n, double dt) {
  const double duration = dt * static_cast<double>(n);
  std::size_t from = 0, end = n;
  if (r.from_s) {
    if (!(*r.from_s >= 0.0) || !(*r.from_s < duration)) throw_invalid("--from-s", *r.from_s, fmt::format("[0, {})", duration));
    from = static_cast<std::size_t>(std::llround(*r.from_s / dt));
  }
  if (r.to_s) {
    if (!(*r.to_s > (r.from_s ? *r.from_s : 0.0))) throw_invalid("--to-s", *r.to_s, "greater than --from-s (and than 0)");
    end = std::min(n, static_cast<std::size_t>(std::llround(*r.to_s / dt)));
  }
  if (end <= from + 64) {
    throw InvalidArgument(fmt::format("{}: the window [{}, {}) s holds {} samples; at least 65 are needed", r.path.string(),
                                      dt * static_cast<double>(from), dt * static_cast<double>(end), end > from ? end - from : 0));
  }
  return {from, end};
}

// The window [w.first, w.second) of `column` in `source` (its file line `first_line`, 0: unknown).
// A spectrum sums products of samples: a value beyond largest_squarable (error.hpp) would
// overflow it, so it is refused by name here.
UniformSeries cut(const std::vector<double>& values, double dt, std::pair<std::size_t, std::size_t> w,
                  const std::string& source, const std::string& column, std::size_t first_line) {
  const auto first = values.begin() + static_cast<std::ptrdiff_t>(w.first);
  const auto last = values.begin() + static_cast<std::ptrdiff_t>(w.second);
  UniformSeries out{dt * static_cast<double>(w.first), dt, std::vector<double>(first, last)};
  if (const std::size_t k = first_unsquarable(out.values); k < out.size()) {
    throw InputError(source, first_line == 0 ? 0 : first_line + k, column, fmt::format("value {:g} at t = {:g} s is too large for a power spectrum (it "
                                                    "would overflow); allowed: |value| <= {:.3g} for a window of {} "
                                                    "samples. Rescale the record (other units)", out.values[k],
                                                    out.time_s(k), largest_squarable(out.size()), out.size()));
  }
  return out;
}

void add_into(std::vector<double>& sum, const std::vector<double>& x) {
  for (std::size_t k = 0; k < sum.size(); ++k) sum[k] += x[k];
}

// The unit of a Klipper accelerometer's PSD: its samples are in mm/s² (Klipper's Measuring
// Resonances); calibrate_shaper's files with shaper columns hold the PSD ÷ (f + 0.1 Hz).
std::string klipper_unit(bool normalized) { return normalized ? "(mm/s²)²/Hz²" : "(mm/s²)²/Hz"; }

MeasuredSpectrum load_table(const SpectrumRequest& r, const std::string& text, const std::string& source) {
  if (r.column.empty()) {
    throw InvalidArgument(fmt::format("--column: {} is a table; name the column to analyse (e.g. --column gyro_deg_s)", source));
  }
  const io::Table t = io::parse_table(text, source);
  const std::string time_name = io::require_time_column(t, r.time_column);
  const double dt = io::uniform_sample_time(t, time_name);
  const std::vector<double>& y = t.column(r.column);
  const auto w = window(r, y.size(), dt);
  const std::string column = t.find(r.column) ? r.column : t.names[static_cast<std::size_t>(std::stoul(r.column)) - 1];
  MeasuredSpectrum s = spectrum_of_series(cut(y, dt, w, source, column, t.line_of_row(w.first)), r.segment_s);
  s.column = column;
  s.power_unit = psd_unit_of_column(column);
  return s;
}

MeasuredSpectrum load_klipper_raw(const SpectrumRequest& r, const std::string& text, const std::string& source) {
  const std::size_t axis = klipper_axis(r.column, false, source);
  const detail::KlipperRaw raw = detail::parse_klipper_raw(text, source);
  // Klipper takes the mean rate N / (t_last − t_first) and treats the samples as uniform.
  const double dt = (raw.time_s.back() - raw.time_s.front()) / static_cast<double>(raw.time_s.size());
  const auto w = window(r, raw.time_s.size(), dt);
  std::array<MeasuredSpectrum, 3> parts;
  for (std::size_t a = 0; a < 3; ++a) {
    parts[a] = spectrum_of_series(cut(raw.accel[a], dt, w, source, std::string("accel_") + "xyz"[a], 0), r.segment_s);
  }
  MeasuredSpectrum s = parts[axis < 3 ? axis : 0];
  for (std::size_t a = 0; a < 3; ++a) s.axes.push_back({std::string("accel_") + "xyz"[a], parts[a].power});
  s.axes.push_back({"xyz", parts[0].power});
  for (std::size_t a = 1; a < 3; ++a) add_into(s.axes.back().power, parts[a].power);
  if (axis == 3) {
    s.power = s.axes.back().power;
    s.series.reset();  // no single record for the free-decay fit
  }
  s.column = axis < 3 ? std::string("accel_") + "xyz"[axis] : "xyz";
  s.power_unit = klipper_unit(false);
  s.klipper_normalizes = true;  // calibrate_shaper.py, parse_log: raw data is always normalised
  return s;
}

MeasuredSpectrum load_klipper_psd(const SpectrumRequest& r, const std::string& text, const std::string& source) {
  const std::size_t axis = klipper_axis(r.column, true, source);
  if (r.from_s || r.to_s) throw InvalidArgument(fmt::format("--from-s/--to-s: {} is a PSD file; a window needs a time record", source));
  detail::KlipperPsd p = detail::parse_klipper_psd(text, source);
  MeasuredSpectrum s;
  s.frequency_hz = std::move(p.frequency_hz);
  s.power = p.psd[axis];
  for (std::size_t a = 0; a < 4; ++a) s.axes.push_back({a < 3 ? std::string("psd_") + "xyz"[a] : "psd_xyz", std::move(p.psd[a])});
  s.power_unit = klipper_unit(p.normalized);
  s.klipper_normalizes = !p.normalized;  // parse_log: a file with shaper columns is normalised already
  s.resolution_hz = (s.frequency_hz.back() - s.frequency_hz.front()) / static_cast<double>(s.frequency_hz.size() - 1);
  s.column = axis < 3 ? std::string("psd_") + "xyz"[axis] : "psd_xyz";
  return s;
}

}  // namespace

std::string psd_unit_of_column(std::string_view column) {
  // docs/design.md §4: a plain header with unit suffixes (time_s, command_deg, gyro_deg_s, input_v).
  static const std::vector<std::pair<std::string_view, std::string_view>> kSuffixes{
      {"_deg_s2", "deg/s²"}, {"_rad_s2", "rad/s²"}, {"_mm_s2", "mm/s²"}, {"_m_s2", "m/s²"}, {"_deg_s", "deg/s"},
      {"_rad_s", "rad/s"},   {"_mm_s", "mm/s"},     {"_m_s", "m/s"},     {"_n_m", "N·m"},   {"_rpm", "rpm"},
      {"_deg", "deg"},       {"_rad", "rad"},       {"_mm", "mm"},       {"_m", "m"},       {"_v", "V"},
      {"_a", "A"},           {"_g", "g"},           {"_n", "N"},         {"_counts", "counts"}, {"_lsb", "LSB"}};
  const std::string name = lower(column);
  std::string_view unit;
  std::size_t matched = 0;
  for (const auto& [suffix, u] : kSuffixes) {
    if (suffix.size() > matched && name.size() > suffix.size() && name.ends_with(suffix)) {
      unit = u;
      matched = suffix.size();
    }
  }
  if (unit.empty()) return fmt::format("(unit of {})²/Hz", column);
  const bool compound = unit.find_first_of("/·") != std::string_view::npos;
  return compound ? fmt::format("({})²/Hz", unit) : fmt::format("{}²/Hz", unit);
}

std::string_view to_string(InputFormat format) noexcept {
  switch (format) {
    case InputFormat::table: return "table";
    case InputFormat::klipper_raw: return "klipper-accelerometer";
    case InputFormat::klipper_psd: return "klipper-psd";
  }
  return "table";
}

InputFormat detect_format(std::string_view text) noexcept {
  std::size_t i = 0;
  while (i < text.size()) {
    const std::size_t j = text.find('\n', i);
    std::string_view line = text.substr(i, j == std::string_view::npos ? std::string_view::npos : j - i);
    const auto first = line.find_first_not_of(" \t\r");
    if (first != std::string_view::npos) {
      line.remove_prefix(first);
      if (line.starts_with("#time,")) return InputFormat::klipper_raw;
      if (line.starts_with("freq,psd_x")) return InputFormat::klipper_psd;
      return InputFormat::table;
    }
    if (j == std::string_view::npos) break;
    i = j + 1;
  }
  return InputFormat::table;
}

MeasuredSpectrum spectrum_of_series(const UniformSeries& series, double segment_s) {
  const std::size_t n = series.size();
  if (n < 65) throw InvalidArgument(fmt::format("a record of {} samples is too short for a spectrum; at least 65 are needed", n));
  std::size_t segment = 0;
  if (segment_s > 0.0) {
    segment = static_cast<std::size_t>(std::llround(segment_s / series.sample_time_s));
    if (segment < 16 || segment > n) {
      throw_invalid("--segment-s", segment_s,
                    fmt::format("[{}, {}] s (16 samples … the record)", 16 * series.sample_time_s, series.end_s() - series.start_s));
    }
  } else {
    segment = std::clamp<std::size_t>(std::bit_floor(n / 4), std::size_t{64}, n);
  }
  dsp::WelchOptions o;
  o.segment_length = segment;
  o.fft_length = 4 * segment;
  const double rate_hz = 1.0 / series.sample_time_s;
  dsp::Spectrum w = dsp::welch(series.values, rate_hz, o);
  MeasuredSpectrum s;
  s.frequency_hz = std::move(w.frequency_hz);
  s.power = std::move(w.power);
  s.segments = w.segments;
  s.resolution_hz = rate_hz / static_cast<double>(segment);
  s.series = series;
  return s;
}

MeasuredSpectrum load_spectrum(const SpectrumRequest& request) {
  const std::string source = request.path.string();
  const std::string text = io::read_text_file(request.path);
  const InputFormat format = detect_format(text);
  MeasuredSpectrum s;
  switch (format) {
    case InputFormat::table: s = load_table(request, text, source); break;
    case InputFormat::klipper_raw: s = load_klipper_raw(request, text, source); break;
    case InputFormat::klipper_psd: s = load_klipper_psd(request, text, source); break;
  }
  s.source = source;
  s.format = format;
  return s;
}

}  // namespace clearshape::advise
