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

// What --fresh removed and what it kept because this job reads it (a recordings manifest's file).
struct Removal {
  std::size_t removed = 0;
  std::vector<std::string> kept_inputs;
  void remove(const fs::path& path) {
    std::error_code ec;
    if (!fs::exists(fs::symlink_status(path, ec))) return;
    if (io::is_input(path)) {
      kept_inputs.push_back(path.string());
      return;
    }
    removed += fs::remove(path, ec) ? 1 : 0;
  }
};

void remove_own_runs(const fs::path& runs, Removal& r) {
  std::error_code ec;
  std::vector<fs::path> sidecars;
  for (const auto& entry : fs::directory_iterator(runs, ec)) {
    if (entry.path().extension() == ".json" && is_own_sidecar(entry.path())) sidecars.push_back(entry.path());
  }
  for (const auto& sidecar : sidecars) {
    fs::path csv = sidecar;
    csv.replace_extension(".csv");
    r.remove(sidecar);  // the sidecar first: a CSV alone is never "finished"
    r.remove(csv);
  }
}

// The files a previous finished study listed in its manifest, relative to `out`, kept inside it.
void remove_manifest_files(const fs::path& out, Removal& r) {
  const fs::path manifest = out / kManifest;
  std::error_code ec;
  if (!fs::is_regular_file(manifest, ec)) return;
  json doc;
  try {
    doc = json::parse(io::read_own_output_file(manifest));
  } catch (const std::exception&) {
    return;  // not ours, or damaged: remove nothing
  }
  for (const auto& name : doc.value("files", json::array())) {
    if (!name.is_string()) continue;
    const fs::path rel = fs::path(name.get<std::string>()).lexically_normal();
    if (rel.empty() || rel.is_absolute() || *rel.begin() == "..") continue;
    r.remove(out / rel);
  }
  r.remove(manifest);
}

}  // namespace

void prepare_output_folder(const fs::path& out, bool fresh,
                           const std::function<void(const std::string&)>& log) {
  std::size_t stale = 0;
  for (const auto& dir : {out, out / "runs", out / "data"}) stale += io::remove_stale_temporaries(dir);
  if (stale > 0) log(fmt::format("removed {} temporary file(s) left by an interrupted run", stale));
  if (!fresh) return;
  Removal r;
  remove_manifest_files(out, r);
  remove_own_runs(out / "runs", r);
  log(fmt::format("--fresh: removed {} file(s) this study wrote before (other files are kept)", r.removed));
  if (!r.kept_inputs.empty()) {
    log(fmt::format("--fresh: kept {} file(s) this study reads as its inputs (the first: {})", r.kept_inputs.size(),
                    r.kept_inputs.front()));
  }
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
