#pragma once
// Which columns of a record are the input, the output and the time, for the commands that relate
// an input to an output (identify, frf): explicit options first, else the defaults (a time column
// time_s/time/t, an input named command…/input…/u…, the output the next other column); the
// mapping is printed, and a pair whose output only converts the input (a D/A copy,
// ident/column_check.hpp) is refused naming the other columns (issue 20).
#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "clearshape/io/table.hpp"

namespace clearshape::cli {

struct IoColumns {
  std::optional<std::size_t> time;
  std::size_t input = 0, output = 0;
};

/// Lower-case copy (ASCII).
std::string lower(std::string s);

/// The columns to use; InputError/InvalidArgument naming the file and what is missing.
IoColumns choose_io_columns(const io::Table& t, const std::string& input, const std::string& output,
                            const std::string& time, bool have_sample_time, bool need_input);

/// "input 'a' (column 2), output 'b' (column 3), time 't' (column 1)" (or "--sample-time 0.001 s").
std::string describe_io_columns(const io::Table& t, const IoColumns& c, double sample_time_s);

/// Throws InvalidArgument "<command>: <path>: output '…' is input '…' through a converter …" when
/// the output only converts the input (holds of at most 0.05 s at sample_time_s).
void refuse_converted_copy(const io::Table& t, const IoColumns& c, double sample_time_s, std::string_view command);

}  // namespace clearshape::cli
