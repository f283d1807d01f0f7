#pragma once
// The temporary files in flight, in a fixed table a signal handler can walk
// (async-signal-safe: no allocation, no locks, only atomics and unlink()).
#include <string>

namespace clearshape::io::detail {

/// Claims a slot for `path`; returns the slot or -1 when the table is full (the file is then
/// still written, only not removed by a signal).
int register_temporary(const std::string& path) noexcept;
void release_temporary(int slot) noexcept;

}  // namespace clearshape::io::detail
