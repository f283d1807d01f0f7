#include "output_folder.hpp"

#include <algorithm>
#include <system_error>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "clearshape/io/atomic_file.hpp"
#include "clearshape/io/json.hpp"

namespace clearshape::study::detail {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

namespace {

constexpr const char* kManifest = "outputs.json";
constexpr const char* kTopLevel[] = {"results.json", "tables.md", "figures.json", "timing.json"};

// A run sidecar the study wrote: JSON with the keys its writer always sets.
bool is_own_sidecar(const fs::path& path) {
  try {
    const json doc = json::parse(io::read_own_output_file(path));
    return doc.is_object() && doc.contains("clearshape_version") && doc.contains("protocol_hash") &&
           doc.contains("id");
  } catch (const std::exception&) {
    return false;
  }
}

std::size_t remove_own_runs(const fs::path& runs) {
  std::error_code ec;
  std::vector<fs::path> sidecars;
  for (const auto& entry : fs::directory_iterator(runs, ec)) {
    if (entry.path().extension() == ".json" && is_own_sidecar(entry.path())) sidecars.push_back(entry.path());
  }
  std::size_t removed = 0;
  for (const auto& sidecar : sidecars) {
    fs::path csv = sidecar;
    csv.replace_extension(".csv");
    removed += fs::remove(sidecar, ec) ? 1 : 0;  // the sidecar first: a CSV alone is never "finished"
    removed += fs::remove(csv, ec) ? 1 : 0;
  }
  return removed;
}

// The files a previous finished study listed in its manifest, relative to `out`, kept inside it.
std::size_t remove_manifest_files(const fs::path& out) {
  const fs::path manifest = out / kManifest;
  std::error_code ec;
  if (!fs::is_regular_file(manifest, ec)) return 0;
  json doc;
  try {
    doc = json::parse(io::read_own_output_file(manifest));
  } catch (const std::exception&) {
    return 0;  // not ours, or damaged: remove nothing
  }
  std::size_t removed = 0;
  for (const auto& name : doc.value("files", json::array())) {
    if (!name.is_string()) continue;
    const fs::path rel = fs::path(name.get<std::string>()).lexically_normal();
    if (rel.empty() || rel.is_absolute() || *rel.begin() == "..") continue;
    removed += fs::remove(out / rel, ec) ? 1 : 0;
  }
  removed += fs::remove(manifest, ec) ? 1 : 0;
  return removed;
}

}  // namespace

void prepare_output_folder(const fs::path& out, bool fresh,
                           const std::function<void(const std::string&)>& log) {
  std::size_t stale = 0;
  for (const auto& dir : {out, out / "runs", out / "data"}) stale += io::remove_stale_temporaries(dir);
  if (stale > 0) log(fmt::format("removed {} temporary file(s) left by an interrupted run", stale));
  if (!fresh) return;
  const std::size_t removed = remove_manifest_files(out) + remove_own_runs(out / "runs");
  log(fmt::format("--fresh: removed {} file(s) this study wrote before (other files are kept)", removed));
}

void write_outputs_manifest(const fs::path& out, const std::vector<std::string>& data_files) {
  json doc = io::make_document();
  json files = json::array();
  for (const char* name : kTopLevel) files.push_back(name);
  std::vector<std::string> data = data_files;
  std::sort(data.begin(), data.end());
  data.erase(std::unique(data.begin(), data.end()), data.end());
  for (const auto& name : data) files.push_back("data/" + name);
  doc["files"] = files;
  doc["note"] = "files this study wrote; `clearshape study --fresh` removes these and its own runs/ only";
  io::write_json(out / kManifest, doc);
}

}  // namespace clearshape::study::detail
