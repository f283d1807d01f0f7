#pragma once
// What the protocol tests share: the smallest protocol that parses, and the parse error of a text.
#include <string>

#include "clearshape/core/error.hpp"
#include "clearshape/study/protocol.hpp"

namespace clearshape::testing {

/// The smallest protocol that parses: one 10° step, everything else at its default.
inline const char* const kMiniProtocol = R"(format = "clearshape-study-protocol/1"
[study]
name = "mini"
mode = "position"
[[input]]
name = "step"
type = "step"
amplitude_deg = 10.0
start_s = 0.5
)";

/// The InputError that parsing `text` (as "mini.toml") raises; "" when it parses.
inline std::string protocol_error_of(const std::string& text) {
  try {
    study::parse_protocol(text, "mini.toml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace clearshape::testing
