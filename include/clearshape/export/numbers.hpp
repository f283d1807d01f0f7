#pragma once
// How exported numbers are written. Two rules, each stated where it is used:
//   - data a program reads back bit for bit (JSON taps, C `double`/`float` literals): the shortest
//     decimal that parses back to the same binary64/binary32 value (fmt's "{}", Ryu-style);
//   - settings a person reads (Klipper/RRF frequencies, damping, durations): a stated number of
//     significant digits, fixed notation (no exponent, which G-code parsers do not take), trailing
//     zeros trimmed — 14.955 Hz, not 14.955000000000002.
#include <string>

namespace clearshape::exports {

/// Shortest decimal that reads back to the same binary64; always has a '.' or an exponent.
std::string shortest(double x);
/// Shortest decimal that reads back to the same binary32; always has a '.' or an exponent.
std::string shortest(float x);
/// x rounded to `digits` significant digits (round half to even on the decimal digits).
double round_significant(double x, int digits);
/// x to `digits` significant digits in fixed notation, trailing zeros trimmed: "14.955", "0.0123",
/// "40". Throws InvalidArgument for a non-finite x or digits outside [1, 17].
std::string fixed_significant(double x, int digits);

}  // namespace clearshape::exports
