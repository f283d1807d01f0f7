#pragma once
// Numeric tables: reading comma- or whitespace-separated numeric columns (with or without a
// header line) and writing CSV with a plain unit-suffixed header (docs/design.md §4).
#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "clearshape/core/series.hpp"

namespace clearshape::io {

struct Table {
  std::string source;                      ///< file name, for error messages
  std::vector<std::string> names;          ///< column names ("col1", "col2", … when no header)
  std::vector<std::vector<double>> columns;
  bool had_header = false;

  std::size_t rows() const noexcept { return columns.empty() ? 0 : columns.front().size(); }
  std::optional<std::size_t> find(std::string_view name) const;
  /// The column called `name`, or a 1-based index given as a number ("2"). Throws InputError
  /// listing the available columns when there is none.
  const std::vector<double>& column(std::string_view name) const;
  /// File line (1-based) holding data row `row` (0-based), for error messages.
  std::size_t line_of_row(std::size_t row) const noexcept { return row + (had_header ? 2 : 1); }
};

/// Parses text: columns separated by commas, semicolons, tabs or spaces; a first line that is
/// not all numbers is the header; blank lines and lines starting with '#' are skipped.
/// Throws InputError (file, line, field) on ragged rows, non-numeric or non-finite values, or
/// an empty table.
Table parse_table(std::string_view text, const std::string& source);
/// Reads and parses a file. Throws InputError if it cannot be read.
Table read_table(const std::filesystem::path& path);

/// Checks that `time` is strictly increasing and uniformly spaced (relative tolerance
/// `tolerance` of the mean step) and returns the mean sample time. Throws InputError naming the
/// first offending line.
double uniform_sample_time(const Table& table, std::string_view time_column, double tolerance = 1e-3);

/// Extracts a column sampled on a uniform time column as a UniformSeries.
UniformSeries series_from_table(const Table& table, std::string_view time_column,
                                std::string_view value_column);

/// Formats columns as CSV with `names` as the header. All columns must have the same length.
std::string format_csv(const std::vector<std::string>& names,
                       const std::vector<const std::vector<double>*>& columns);
/// format_csv + write_text_atomic.
void write_csv(const std::filesystem::path& path, const std::vector<std::string>& names,
               const std::vector<const std::vector<double>*>& columns);

}  // namespace clearshape::io
