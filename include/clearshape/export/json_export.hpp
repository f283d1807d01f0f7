#pragma once
// `--export json`: one document with schema_version and the tool version (io::make_document),
// the design (method, mode, ζ, vtol, band), the impulses, the taps on the sample grid and the
// residual vibration V (Eq. 2.19) the taps leave at the design mode and over r ∈ [0.9, 1.1],
// beside the continuous shaper's. Numbers are binary64 written shortest-round-trip (the taps
// parse back to exactly what discretize() returned); frequency_hz is rounded to 12 significant
// digits (the 2π round trip otherwise shows as 14.955000000000002).
#include "clearshape/export/export.hpp"

namespace clearshape::exports {

ExportText to_json(const ShaperDesign& design, const ExportOptions& options);

}  // namespace clearshape::exports
