#pragma once
// What `clearshape study` sets up before study::run_study (Python: clearshape.study): the rig a
// `simulate --config` / `--rig-config` file describes, and the check that a protocol fits in
// memory before anything is written.
#include <filesystem>

#include "clearshape/study/protocol.hpp"
#include "clearshape/study/record.hpp"

namespace clearshape::study {

/// A simulated rig (rig::SimRig) with the truth of a rig configuration file (rig/config.hpp),
/// described by the file's name and FNV-1a 64 hash (results.json names the rig it ran on).
/// Throws InputError naming the file, line and key.
RigFactory configured_sim_rig_factory(const std::filesystem::path& rig_config);

/// Refuses a protocol whose records would not fit in `max_memory_gb` (8 columns of doubles per
/// sample, ~3 copies while a stage computes, the largest stage's runs or the parallel runs held
/// at once), with its numbers and the limit to raise (`--max-memory-gb`). `threads` 0: all cores.
void check_study_size(const Protocol& protocol, int threads, double max_memory_gb);

}  // namespace clearshape::study
