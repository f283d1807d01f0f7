#pragma once
// Status values returned by real-time paths, which never throw (docs/design.md §3, after Ruckig's
// Result and ros2_control's return_type).
#include <cstdint>
#include <string_view>

namespace clearshape {

enum class Status : std::uint8_t {
  ok = 0,
  not_ready,     ///< called in the wrong lifecycle state (e.g. before configure/activate)
  out_of_range,  ///< an input was outside the allowed range; output was clamped or held
  not_finite,    ///< an input or state became NaN/Inf; output was held
  overrun,       ///< a deadline was missed
  device_error,  ///< the hardware or simulator reported a failure
};

constexpr std::string_view to_string(Status s) noexcept {
  switch (s) {
    case Status::ok: return "ok";
    case Status::not_ready: return "not_ready";
    case Status::out_of_range: return "out_of_range";
    case Status::not_finite: return "not_finite";
    case Status::overrun: return "overrun";
    case Status::device_error: return "device_error";
  }
  return "unknown";
}

}  // namespace clearshape
