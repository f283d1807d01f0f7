#include "klipper_csv.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>

#include <fmt/format.h>

#include "clearshape/core/error.hpp"

namespace clearshape::advise::detail {

namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

std::vector<std::string_view> split_commas(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (true) {
    const std::size_t j = line.find(',', i);
    out.push_back(trim(line.substr(i, j == std::string_view::npos ? std::string_view::npos : j - i)));
    if (j == std::string_view::npos) break;
    i = j + 1;
  }
  return out;
}

// Calls f(line_number, line) for every non-blank line.
template <typename F>
void for_each_line(std::string_view text, F&& f) {
  std::size_t number = 0, i = 0;
  while (i <= text.size()) {
    const std::size_t j = text.find('\n', i);
    const std::string_view line = text.substr(i, j == std::string_view::npos ? std::string_view::npos : j - i);
    ++number;
    if (!trim(line).empty()) f(number, trim(line));
    if (j == std::string_view::npos) break;
    i = j + 1;
  }
}

double number(std::string_view field, const std::string& source, std::size_t line, const std::string& name) {
  double v = 0.0;
  std::string_view s = field;
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (s.empty() || ec != std::errc() || ptr != s.data() + s.size()) {
    throw InputError(source, line, name, fmt::format("'{}' is not a number", field));
  }
  if (!std::isfinite(v)) throw InputError(source, line, name, fmt::format("'{}' is not finite", field));
  return v;
}

void expect_header(const std::vector<std::string_view>& got, const std::vector<std::string_view>& want,
                   const std::string& source, std::size_t line) {
  for (std::size_t k = 0; k < want.size(); ++k) {
    if (k >= got.size() || got[k] != want[k]) {
      throw InputError(source, line, k < got.size() ? std::string(got[k]) : std::string("header"),
                       fmt::format("Klipper header column {} must be '{}'", k + 1, want[k]));
    }
  }
}

}  // namespace

KlipperRaw parse_klipper_raw(std::string_view text, const std::string& source) {
  static const std::vector<std::string_view> names{"#time", "accel_x", "accel_y", "accel_z"};
  KlipperRaw raw;
  bool header = false;
  for_each_line(text, [&](std::size_t line, std::string_view s) {
    const auto fields = split_commas(s);
    if (!header) {
      expect_header(fields, names, source, line);
      header = true;
      return;
    }
    if (s.front() == '#') return;  // further comments
    if (fields.size() < 4) {
      throw InputError(source, line, std::string(names[fields.size()]),
                       fmt::format("the row has {} fields; 4 are needed (time, accel_x, accel_y, accel_z)", fields.size()));
    }
    const double t = number(fields[0], source, line, "time");
    if (!raw.time_s.empty() && !(t > raw.time_s.back())) {
      throw InputError(source, line, "time", fmt::format("time {} does not increase (previous {})", t, raw.time_s.back()));
    }
    raw.time_s.push_back(t);
    for (std::size_t a = 0; a < 3; ++a) raw.accel[a].push_back(number(fields[a + 1], source, line, std::string(names[a + 1])));
  });
  if (raw.time_s.size() < 2) throw InputError(source, 0, "", "a Klipper accelerometer file needs at least two samples");
  return raw;
}

KlipperPsd parse_klipper_psd(std::string_view text, const std::string& source) {
  static const std::vector<std::string_view> names{"freq", "psd_x", "psd_y", "psd_z", "psd_xyz"};
  KlipperPsd p;
  bool header = false;
  for_each_line(text, [&](std::size_t line, std::string_view s) {
    const auto fields = split_commas(s);
    if (!header) {
      expect_header(fields, names, source, line);
      p.normalized = std::find(fields.begin(), fields.end(), "shapers:") != fields.end();
      header = true;
      return;
    }
    if (fields.size() < 5) {
      throw InputError(source, line, std::string(names[fields.size()]),
                       fmt::format("the row has {} fields; 5 are needed (freq, psd_x, psd_y, psd_z, psd_xyz)", fields.size()));
    }
    const double f = number(fields[0], source, line, "freq");
    if (f < 0.0) throw InputError(source, line, "freq", fmt::format("frequency {} is negative", f));
    if (!p.frequency_hz.empty() && !(f > p.frequency_hz.back())) {
      throw InputError(source, line, "freq", fmt::format("frequency {} does not increase (previous {})", f, p.frequency_hz.back()));
    }
    p.frequency_hz.push_back(f);
    for (std::size_t a = 0; a < 4; ++a) {
      const double v = number(fields[a + 1], source, line, std::string(names[a + 1]));
      if (v < 0.0) throw InputError(source, line, std::string(names[a + 1]), fmt::format("a PSD cannot be negative ({})", v));
      p.psd[a].push_back(v);
    }
  });
  if (p.frequency_hz.size() < 3) throw InputError(source, 0, "", "a Klipper PSD file needs at least three frequencies");
  return p;
}

}  // namespace clearshape::advise::detail
