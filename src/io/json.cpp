#include "clearshape/io/json.hpp"

#include "clearshape/core/version.hpp"
#include "clearshape/io/atomic_file.hpp"

namespace clearshape::io {

nlohmann::ordered_json make_document() {
  nlohmann::ordered_json doc;
  doc["schema_version"] = kSchemaVersion;
  doc["clearshape_version"] = kVersion;
  return doc;
}

void write_json(const std::filesystem::path& path, const nlohmann::ordered_json& document) {
  write_text_atomic(path, document.dump(2) + "\n");
}

}  // namespace clearshape::io
