#pragma once
// The one set of time-column names every command accepts by default (in this order):
// time_s, time, t — the column holds seconds.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "clearshape/io/table.hpp"

namespace clearshape::io {

/// "time_s", "time", "t".
const std::vector<std::string>& default_time_columns();
/// The first default time column present in `table` (names compared case-insensitively).
std::optional<std::string> find_time_column(const Table& table);
/// `requested` if given (it must exist; InputError listing the columns otherwise), else the
/// first default time column, else an InputError naming the file and the accepted names.
std::string require_time_column(const Table& table, std::string_view requested = {});

}  // namespace clearshape::io
