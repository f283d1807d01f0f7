#include "clearshape/io/table.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

#include "clearshape/core/error.hpp"
#include "clearshape/io/atomic_file.hpp"

namespace clearshape::io {

namespace {

bool is_separator(char c) { return c == ',' || c == ';' || c == ' ' || c == '\t' || c == '\r'; }

// Splits a line on commas/semicolons (keeping empty fields) when it has any, else on runs of
// white space.
std::vector<std::string_view> split_fields(std::string_view line) {
  std::vector<std::string_view> fields;
  const bool delimited = line.find_first_of(",;") != std::string_view::npos;
  std::size_t i = 0;
  if (delimited) {
    while (true) {
      const std::size_t j = line.find_first_of(",;", i);
      std::string_view f = line.substr(i, j == std::string_view::npos ? std::string_view::npos : j - i);
      while (!f.empty() && (f.front() == ' ' || f.front() == '\t')) f.remove_prefix(1);
      while (!f.empty() && (f.back() == ' ' || f.back() == '\t' || f.back() == '\r')) f.remove_suffix(1);
      fields.push_back(f);
      if (j == std::string_view::npos) break;
      i = j + 1;
    }
  } else {
    while (i < line.size()) {
      while (i < line.size() && is_separator(line[i])) ++i;
      if (i >= line.size()) break;
      std::size_t j = i;
      while (j < line.size() && !is_separator(line[j])) ++j;
      fields.push_back(line.substr(i, j - i));
      i = j;
    }
  }
  return fields;
}

bool parse_number(std::string_view s, double& out) {
  if (s.empty()) return false;
  if (s.front() == '+') s.remove_prefix(1);
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
  return ec == std::errc() && ptr == s.data() + s.size();
}

// The first field of `line` written with a decimal comma ("0,125"): a comma between two digits on a
// line that a ';' separates, and its 0-based position among the ';'-separated fields; text ""
// when there is none.
struct CommaField {
  std::string text;
  std::size_t index = 0;
};

CommaField decimal_comma_field(std::string_view line) {
  if (line.find(';') == std::string_view::npos) return {};
  const auto digit = [](char c) { return c >= '0' && c <= '9'; };
  for (std::size_t i = 1; i + 1 < line.size(); ++i) {
    if (line[i] != ',' || !digit(line[i - 1]) || !digit(line[i + 1])) continue;
    std::size_t a = i, b = i + 1;
    while (a > 0 && line[a - 1] != ';' && line[a - 1] != ' ' && line[a - 1] != '\t') --a;
    while (b < line.size() && line[b] != ';' && line[b] != ' ' && line[b] != '\t' && line[b] != '\r') ++b;
    const std::string_view before = line.substr(0, a);
    return {std::string(line.substr(a, b - a)), static_cast<std::size_t>(std::count(before.begin(), before.end(), ';'))};
  }
  return {};
}

std::string decimal_comma_hint(const std::string& field) {
  return fmt::format("'{}' uses a decimal comma and ';' separates the fields: export the CSV with decimal points "
                     "(e.g. 0.125; LC_NUMERIC=C, or a spreadsheet's English/\"C\" locale) — clearshape reads ',' "
                     "and ';' both as separators", field);
}

bool is_blank_or_comment(std::string_view line) {
  const auto pos = line.find_first_not_of(" \t\r");
  return pos == std::string_view::npos || line[pos] == '#';
}

}  // namespace

std::optional<std::size_t> Table::find(std::string_view name) const {
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (names[i] == name) return i;
  }
  return std::nullopt;
}

const std::vector<double>& Table::column(std::string_view name) const {
  if (auto i = find(name)) return columns[*i];
  double index = 0.0;
  if (parse_number(name, index) && index >= 1 && index <= static_cast<double>(columns.size()) &&
      std::floor(index) == index) {
    return columns[static_cast<std::size_t>(index) - 1];
  }
  std::string available;
  for (std::size_t i = 0; i < names.size(); ++i) {
    available += fmt::format("{}{} ({})", i ? ", " : "", names[i], i + 1);
  }
  throw InputError(source, 0, std::string(name),
                   fmt::format("no such column; available: {}", available));
}

Table parse_table(std::string_view text, const std::string& source) {
  if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);  // UTF-8 byte-order mark
  Table table;
  table.source = source;
  std::size_t line_no = 0;
  std::size_t start = 0;
  bool first_content_line = true;
  while (start <= text.size()) {
    const std::size_t end = text.find('\n', start);
    std::string_view line = text.substr(start, end == std::string_view::npos ? std::string_view::npos : end - start);
    ++line_no;
    start = (end == std::string_view::npos) ? text.size() + 1 : end + 1;
    if (is_blank_or_comment(line)) continue;
    // A decimal comma would split "0,125" into two fields: refused with the fix, before the
    // fields are counted (a header-less file would otherwise read with twice its columns).
    if (const CommaField f = decimal_comma_field(line); !f.text.empty()) {
      const std::string column =
          f.index < table.names.size() ? table.names[f.index] : fmt::format("column {}", f.index + 1);
      throw InputError(source, line_no, column, decimal_comma_hint(f.text));
    }
    const auto fields = split_fields(line);
    if (first_content_line) {
      first_content_line = false;
      double tmp = 0.0;
      const bool numeric = std::all_of(fields.begin(), fields.end(),
                                       [&](std::string_view f) { return parse_number(f, tmp); });
      table.columns.resize(fields.size());
      if (!numeric) {
        table.had_header = true;
        for (std::size_t i = 0; i < fields.size(); ++i) {
          if (fields[i].empty()) throw InputError(source, line_no, fmt::format("column {}", i + 1), "empty column name in header");
          table.names.emplace_back(fields[i]);
        }
        continue;
      }
      for (std::size_t i = 0; i < fields.size(); ++i) table.names.push_back(fmt::format("col{}", i + 1));
    }
    if (fields.size() != table.columns.size()) {
      const bool comma_decimals = fields.size() > table.columns.size() && line.find(',') != std::string_view::npos &&
                                  std::any_of(line.begin(), line.end(), [](char c) { return c >= '0' && c <= '9'; });
      throw InputError(source, line_no, "",
                       fmt::format("expected {} columns, found {}{}", table.columns.size(), fields.size(),
                                   comma_decimals ? " — if the numbers use a decimal comma (0,125), export them with "
                                                    "decimal points (',' separates fields here)"
                                                  : ""));
    }
    for (std::size_t i = 0; i < fields.size(); ++i) {
      double v = 0.0;
      if (!parse_number(fields[i], v)) {
        throw InputError(source, line_no, table.names[i], fmt::format("'{}' is not a number", fields[i]));
      }
      if (!std::isfinite(v)) {
        throw InputError(source, line_no, table.names[i], fmt::format("value {} is not finite", fields[i]));
      }
      table.columns[i].push_back(v);
    }
  }
  if (table.columns.empty() || table.rows() == 0) {
    throw InputError(source, 0, "", "no data rows");
  }
  return table;
}

Table read_table(const std::filesystem::path& path) {
  return parse_table(read_text_file(path), path.string());
}

double uniform_sample_time(const Table& table, std::string_view time_column, double tolerance) {
  const auto& t = table.column(time_column);
  if (t.size() < 2) throw InputError(table.source, 0, std::string(time_column), "need at least 2 samples");
  const double mean_step = (t.back() - t.front()) / static_cast<double>(t.size() - 1);
  for (std::size_t i = 1; i < t.size(); ++i) {
    if (!(t[i] > t[i - 1])) {
      throw InputError(table.source, table.line_of_row(i), std::string(time_column),
                       fmt::format("time must increase strictly; {} follows {}", t[i], t[i - 1]));
    }
  }
  for (std::size_t i = 1; i < t.size(); ++i) {
    const double step = t[i] - t[i - 1];
    if (std::abs(step - mean_step) > tolerance * mean_step) {
      throw InputError(table.source, table.line_of_row(i), std::string(time_column),
                       fmt::format("irregular sampling: step {} differs from the mean step {} by more "
                                   "than {:.3g}%; resample to a uniform time base",
                                   step, mean_step, tolerance * 100.0));
    }
  }
  return mean_step;
}

UniformSeries series_from_table(const Table& table, std::string_view time_column,
                                std::string_view value_column) {
  UniformSeries s;
  s.sample_time_s = uniform_sample_time(table, time_column);
  s.start_s = table.column(time_column).front();
  s.values = table.column(value_column);
  return s;
}

std::string format_csv(const std::vector<std::string>& names,
                       const std::vector<const std::vector<double>*>& columns) {
  if (names.size() != columns.size()) {
    throw InvalidArgument(fmt::format("format_csv: {} names for {} columns", names.size(), columns.size()));
  }
  const std::size_t rows = columns.empty() ? 0 : columns.front()->size();
  for (std::size_t c = 0; c < columns.size(); ++c) {
    if (columns[c]->size() != rows) {
      throw InvalidArgument(fmt::format("format_csv: column '{}' has {} rows, expected {}", names[c],
                                        columns[c]->size(), rows));
    }
  }
  std::string out;
  out.reserve((rows + 1) * columns.size() * 14);
  for (std::size_t c = 0; c < names.size(); ++c) {
    if (c) out += ',';
    out += names[c];
  }
  out += '\n';
  for (std::size_t r = 0; r < rows; ++r) {
    for (std::size_t c = 0; c < columns.size(); ++c) {
      if (c) out += ',';
      // Shortest representation that round-trips: deterministic bytes, no precision loss.
      fmt::format_to(std::back_inserter(out), "{}", (*columns[c])[r]);
    }
    out += '\n';
  }
  return out;
}

void write_csv(const std::filesystem::path& path, const std::vector<std::string>& names,
               const std::vector<const std::vector<double>*>& columns) {
  write_text_atomic(path, format_csv(names, columns));
}

}  // namespace clearshape::io
