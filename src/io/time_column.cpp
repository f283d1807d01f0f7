#include "clearshape/io/time_column.hpp"

#include <cctype>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "clearshape/core/error.hpp"

namespace clearshape::io {

const std::vector<std::string>& default_time_columns() {
  static const std::vector<std::string> names{"time_s", "time", "t"};
  return names;
}

std::optional<std::string> find_time_column(const Table& table) {
  for (const auto& want : default_time_columns()) {
    for (const auto& name : table.names) {
      std::string low = name;
      for (char& ch : low) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
      if (low == want) return name;
    }
  }
  return std::nullopt;
}

std::string require_time_column(const Table& table, std::string_view requested) {
  if (!requested.empty()) {
    (void)table.column(requested);  // throws InputError listing the columns
    return std::string(requested);
  }
  if (auto name = find_time_column(table)) return *name;
  throw InputError(table.source, 0, "time column",
                   fmt::format("no time column (looked for {}); the columns are: {}",
                               fmt::join(default_time_columns(), ", "), fmt::join(table.names, ", ")));
}

}  // namespace clearshape::io
