#include "clearshape/io/time_column.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "clearshape/core/error.hpp"

namespace clearshape::io {

const std::vector<std::string>& default_time_columns() {
  static const std::vector<std::string> names{"time_s", "time", "t"};
  return names;
}

std::optional<std::string> find_time_column(const Table& table) {
  for (const auto& name : default_time_columns()) {
    if (table.find(name)) return name;
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
