#pragma once
// Atomic output: write to a temporary file beside the target, flush, then rename over it,
// so a reader never sees a half-written file and a failure never destroys an old one.
#include <filesystem>
#include <string_view>

namespace clearshape::io {

/// Writes `content` to `path` atomically. Creates missing parent folders.
/// Throws clearshape::RuntimeError naming the path on failure.
void write_text_atomic(const std::filesystem::path& path, std::string_view content);

}  // namespace clearshape::io
