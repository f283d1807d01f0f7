#pragma once
// JSON documents written by clearshape carry schema_version and the tool version (docs/design.md §4).
#include <filesystem>

#include <nlohmann/json.hpp>

namespace clearshape::io {

/// A JSON object pre-filled with "schema_version" and "clearshape_version".
nlohmann::ordered_json make_document();
/// Pretty-prints (2-space indent) and writes atomically.
void write_json(const std::filesystem::path& path, const nlohmann::ordered_json& document);

}  // namespace clearshape::io
