#include "clearshape/study/study_setup.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <thread>

#include <fmt/format.h>

#include "clearshape/core/error.hpp"
#include "clearshape/io/atomic_file.hpp"
#include "clearshape/rig/config.hpp"
#include "clearshape/rig/sim_rig.hpp"
#include "clearshape/study/run_source.hpp"
#include "clearshape/study/runner.hpp"

namespace clearshape::study {
namespace {

std::string file_hash(const std::filesystem::path& path) {
  std::uint64_t h = 0xcbf29ce484222325ULL;  // FNV-1a 64
  for (const unsigned char c : io::read_text_file(path)) {
    h ^= c;
    h *= 0x100000001b3ULL;
  }
  return fmt::format("{:016x}", h);
}

// A protocol's size is known before it runs: one record holds 8 columns of doubles per sample and
// a stage keeps its records while it computes (~3 copies: the record, filtered and integrated
// signals). A protocol of 9·10⁸-sample records passed validation and ended in std::bad_alloc
// after the output folder was made; it is refused here, with its numbers, before anything exists.
constexpr double kStudyBytesPerSample = 8.0 * 8.0 * 3.0;

}  // namespace

void check_study_size(const Protocol& p, int threads, double max_memory_gb) {
  const double record_s = std::max(p.record_s, p.simulation.record_s);
  const double samples = std::floor(record_s * p.sample_rate_hz) + 1.0;
  std::size_t largest_stage = 0;
  for (const auto& stage : plan_runs(p)) largest_stage = std::max(largest_stage, stage.runs.size());
  const unsigned parallel = threads > 0 ? static_cast<unsigned>(threads) : std::max(1u, std::thread::hardware_concurrency());
  const double held = static_cast<double>(std::max<std::size_t>(largest_stage, parallel));
  const double gb = samples * kStudyBytesPerSample * held / 1e9;
  if (gb > max_memory_gb) {
    throw InvalidArgument(fmt::format(
        "study {}: too large for memory: records of {:.3g} samples ({:g} s at {:g} Hz), up to {:g} held at once "
        "(the largest stage, or the parallel runs) need about {:.3g} GB; the limit is {:g} GB — shorten record_s, "
        "lower sample_rate_hz, or allow it with --max-memory-gb {:.0f}",
        p.name, samples, record_s, p.sample_rate_hz, held, gb, max_memory_gb, std::ceil(gb)));
  }
}

// A simulated rig with the truth of a `clearshape simulate` configuration file (what-if studies).
RigFactory configured_sim_rig_factory(const std::filesystem::path& path) {
  auto truth = std::make_shared<const rig::RigTruth>(rig::configured_truth(rig::load_rig_config(path)));
  RigFactory f;
  f.description = fmt::format("sim (rig::SimRig, truth from {} {})", path.filename().string(), file_hash(path));
  f.kind = "simulated-config";
  f.parallel_runs = 64;
  f.make = sim_rig_maker(truth);
  return f;
}

}  // namespace clearshape::study
