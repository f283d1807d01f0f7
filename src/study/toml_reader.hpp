#pragma once
// The study's TOML access is io's strict reader (clearshape/io/toml_section.hpp).
#include "clearshape/io/toml_section.hpp"

namespace clearshape::study::detail {
using io::line_of;
using io::parse_toml;
using io::TomlSection;
}  // namespace clearshape::study::detail
