#include "io_columns.hpp"

#include <cctype>
#include <cmath>
#include <initializer_list>

#include <fmt/format.h>

#include "clearshape/core/error.hpp"
#include "clearshape/ident/column_check.hpp"
#include "clearshape/io/time_column.hpp"

namespace clearshape::cli {

namespace {

// The longest hold of a converter copy of the input (ident::is_converted_copy): 1.5 updates of the
// thesis's 30 Hz pulse-train drive (§3.2).
constexpr double kMaxConverterHoldS = 0.05;

// Index of a column given by name or 1-based number; nullopt if absent.
std::optional<std::size_t> column_index(const io::Table& t, const std::string& spec) {
  if (auto i = t.find(spec)) return i;
  (void)t.column(spec);  // throws InputError listing the columns when neither a name nor an index
  return static_cast<std::size_t>(std::stoul(spec)) - 1;
}

std::optional<std::size_t> find_named(const io::Table& t, std::initializer_list<const char*> names, bool prefix) {
  for (std::size_t i = 0; i < t.names.size(); ++i) {
    const std::string n = lower(t.names[i]);
    for (const char* want : names) {
      if (n == want || (prefix && n.rfind(want, 0) == 0)) return i;
    }
  }
  return std::nullopt;
}

}  // namespace

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

namespace {

// A spectrum or a least-squares fit sums products of samples: a value beyond √DBL_MAX / n
// (core/error.hpp) overflows them into NaN (frf printed -nan columns and exited 0).
void refuse_unsquarable(const io::Table& t, std::size_t column) {
  const std::vector<double>& v = t.columns[column];
  if (const std::size_t k = first_unsquarable(v); k < v.size()) {
    throw InputError(t.source, t.line_of_row(k), t.names[column],
                     fmt::format("value {:g} is too large: sums of products of the record's samples would overflow; "
                                 "allowed: |value| <= {:.3g} for a record of {} rows. Rescale the record (other units)",
                                 v[k], largest_squarable(v.size()), v.size()));
  }
}

}  // namespace

IoColumns choose_io_columns(const io::Table& t, const std::string& input, const std::string& output,
                            const std::string& time, bool have_sample_time, bool need_input) {
  IoColumns c;
  if (!time.empty()) {
    if (have_sample_time) throw InvalidArgument("give either --time-column or --sample-time, not both");
    c.time = column_index(t, time);
  } else if (!have_sample_time) {
    if (const auto name = io::find_time_column(t)) c.time = t.find(*name);  // the shared defaults
  }
  auto others = [&](std::size_t i) { return !c.time || i != *c.time; };
  if (need_input) {
    if (!input.empty()) {
      c.input = *column_index(t, input);
    } else if (auto named = find_named(t, {"command", "input", "u"}, true); named && others(*named)) {
      c.input = *named;
    } else {
      std::size_t i = 0;
      while (i < t.columns.size() && !others(i)) ++i;
      c.input = i;
    }
  }
  if (!output.empty()) {
    c.output = *column_index(t, output);
  } else {
    std::size_t i = 0;
    while (i < t.columns.size() && (!others(i) || (need_input && i == c.input))) ++i;
    c.output = i;
  }
  if (c.output >= t.columns.size() || (need_input && c.input >= t.columns.size())) {
    throw InputError(t.source, 0, "", "needs an input and an output column besides the time column; found " +
                                          std::to_string(t.columns.size()) + " column(s)");
  }
  refuse_unsquarable(t, c.output);
  if (need_input) refuse_unsquarable(t, c.input);
  return c;
}

std::string describe_io_columns(const io::Table& t, const IoColumns& c, double sample_time_s) {
  return fmt::format("input '{}' (column {}), output '{}' (column {}), {}", t.names[c.input], c.input + 1, t.names[c.output],
                     c.output + 1,
                     c.time ? fmt::format("time '{}' (column {})", t.names[*c.time], *c.time + 1)
                            : fmt::format("--sample-time {:g} s", sample_time_s));
}

void refuse_converted_copy(const io::Table& t, const IoColumns& c, double sample_time_s, std::string_view command) {
  // An output that only converts the input (a D/A or the drive's applied command) has no dynamics.
  const auto hold_samples = static_cast<std::size_t>(std::ceil(kMaxConverterHoldS / sample_time_s));
  if (!ident::is_converted_copy(t.columns[c.input], t.columns[c.output], hold_samples)) return;
  std::string others;
  for (std::size_t i = 0; i < t.names.size(); ++i) {
    if (i != c.input && i != c.output && (!c.time || i != *c.time)) others += (others.empty() ? "" : ", ") + t.names[i];
  }
  throw InvalidArgument(fmt::format(
      "{}: {}: output '{}' is input '{}' through a converter (equal within {:g} % of its range apart from holds of at most "
      "{:g} s): nothing to {}; give the response with {} (other columns: {})",
      command, t.source, t.names[c.output], t.names[c.input], 100.0 * ident::kCopyTolerance, kMaxConverterHoldS,
      command == "identify" ? "identify" : "estimate", command == "identify" ? "--output-column" : "--output",
      others.empty() ? "none" : others));
}

}  // namespace clearshape::cli
