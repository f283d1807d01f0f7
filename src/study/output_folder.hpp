#pragma once
// A study's output folder (internal). The study removes only what it wrote itself:
//   - runs/<id>.json sidecars it recognises as its own (keys clearshape_version, protocol_hash,
//     id) and the <id>.csv beside each;
//   - the files listed in <out>/outputs.json, the manifest a finished study leaves;
//   - temporary files of the atomic-write layer (io::is_temporary_name) left by a killed run.
// A user's own files in the folder, the folders themselves and any file this job reads as an
// input (io::is_input: a recordings manifest's files and their sidecars) are never removed.
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace clearshape::study::detail {

/// Removes stale temporaries (always) and, when `fresh`, the study's previous outputs.
void prepare_output_folder(const std::filesystem::path& out, bool fresh,
                           const std::function<void(const std::string&)>& log);
/// Writes <out>/outputs.json: the top-level files, the data/ files and the runs/ files written.
void write_outputs_manifest(const std::filesystem::path& out, const std::vector<std::string>& data_files);

}  // namespace clearshape::study::detail
