// `clearshape study`: runs a study protocol (studies/*.toml — the thesis's programme, Chapters
// 4–5 and Appendix B) against the simulated thesis rig and writes results.json, tables.md,
// figures.json, the figures' data and every run (CSV + JSON sidecar) under --out.
// Progress on stderr; the tables (or a JSON summary with --json) on stdout.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <thread>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "clearshape/io/atomic_file.hpp"
#include "clearshape/core/error.hpp"
#include "clearshape/rig/builtin_truths.hpp"
#include "clearshape/rig/serial_rig.hpp"
#include "clearshape/rig/sim_rig.hpp"
#include "clearshape/rig/config.hpp"
#include "clearshape/rig/truth.hpp"
#include "clearshape/study/protocol.hpp"
#include "clearshape/study/recordings.hpp"
#include "clearshape/study/run_source.hpp"
#include "clearshape/study/runner.hpp"
#include "clearshape/study/study_setup.hpp"
#include "command.hpp"
#include "rig_serial_options.hpp"

namespace clearshape::cli {
namespace {

struct StudyCliOptions {
  std::string protocol;
  std::string out_dir;
  bool quick = false;
  bool fresh = false;
  bool json = false;
  int threads = 0;
  double max_memory_gb = 4.0;  // the study's estimated peak memory, checked before it starts
  std::string rig_config;
  std::string recordings;
  std::string rig;
  bool print_manifest = false;
};

// The physical rig over a serial port (`--rig serial:PORT[?baud=N]`), one run at a time. A run
// that loses a sample fails (LostSamples::fail) instead of entering the study with a hole.
study::RigFactory serial_rig_factory(const std::string& spec) {
  rig::SerialRigOptions base;
  parse_serial_rig_spec(spec, base);
  base.lost_samples = rig::LostSamples::fail;
  study::RigFactory f;
  f.description = fmt::format("serial:{} at {} baud (rig::SerialRig, the board's firmware)", base.port, base.baud);
  f.kind = "physical";
  f.parallel_runs = 1;
  f.make = [base](rig::CommandMode mode, double rate_hz, std::uint64_t) -> std::unique_ptr<rig::Rig> {
    rig::SerialRigOptions o = base;
    o.mode = mode;
    o.sample_rate_hz = rate_hz;
    o.validate();
    return std::make_unique<rig::SerialRig>(o);
  };
  return f;
}

void run(const StudyCliOptions& o) {
  // --rig: a built-in simulated truth by name, or the physical rig over a serial port.
  std::optional<study::RigFactory> serial;
  const bool builtin = !o.rig.empty() && rig::is_builtin_truth(o.rig);
  if (!o.rig.empty() && !builtin) {
    if (o.rig.rfind("serial:", 0) != 0) {
      throw InvalidArgument(fmt::format("--rig {}: allowed: {} (built-in simulated rigs), serial:PORT or "
                                        "serial:PORT?baud=N", o.rig, fmt::join(rig::kBuiltinTruthNames, ", ")));
    }
    serial = serial_rig_factory(o.rig);  // a bad spec is an error before anything else
  }
  study::Protocol protocol = study::load_protocol(o.protocol);
  if (o.quick) protocol = study::quick_variant(protocol);
  if (o.print_manifest) {
    std::cout << study::recordings_manifest_template(protocol);
    return;
  }
  if (static_cast<int>(!o.recordings.empty()) + static_cast<int>(!o.rig_config.empty()) + static_cast<int>(!o.rig.empty()) > 1) {
    throw InvalidArgument("study: give one of --recordings, --rig-config and --rig, not several");
  }
  if (!(o.max_memory_gb > 0.0)) throw_invalid("--max-memory-gb", o.max_memory_gb, "> 0 GB");
  study::check_study_size(protocol, o.threads, o.max_memory_gb);
  study::StudyOptions options;
  options.out_dir = o.out_dir.empty() ? std::filesystem::path("out") / (protocol.name + (o.quick ? "-quick" : ""))
                                      : std::filesystem::path(o.out_dir);
  options.fresh = o.fresh;
  options.threads = o.threads;
  options.progress = &std::cerr;
  // The simulated rig: --rig NAME, else the protocol's [study] rig (default: thesis).
  if (o.rig_config.empty() && !serial) options.rig = study::sim_rig_factory(builtin ? o.rig : protocol.rig);
  if (!o.rig_config.empty()) options.rig = study::configured_sim_rig_factory(o.rig_config);
  if (serial) {
    options.rig = *serial;
    options.threads = 1;
  }
  if (!o.recordings.empty()) {
    options.source = study::recordings_run_source(study::load_recordings_manifest(o.recordings, protocol), protocol);
  }
  const study::StudyResult result = study::run_study(protocol, options);
  if (o.json) {
    auto summary = result.summary();
    summary["out_dir"] = options.out_dir.string();
    print_json(summary);
  } else {
    std::cout << result.tables_markdown;
    std::cout << fmt::format("\nWritten: {}/results.json, tables.md, figures.json, data/, runs/\n",
                             options.out_dir.string());
  }
}

const bool study_registered = register_command(
    {"study", "Run a study protocol (the thesis's programme) against the simulated rig", 50,
     [](CLI::App& sub) {
       auto o = std::make_shared<StudyCliOptions>();
       sub.add_option("protocol", o->protocol, "Study protocol (TOML), e.g. studies/thesis-position.toml")
           ->required();
       sub.add_option("--out", o->out_dir, "Output folder (default: out/<study name>)");
       sub.add_flag("--quick", o->quick, "Run the protocol's [quick] reduction (fewer repetitions, shorter records)");
       sub.add_flag("--fresh", o->fresh, "Discard finished runs under --out and run everything again");
       sub.add_flag("--json", o->json, "Print a JSON summary on stdout instead of the tables");
       sub.add_option("--threads", o->threads, "Parallel runs (default: the machine's hardware threads)")
           ->check(CLI::Range(1, 256));
       sub.add_option("--rig-config", o->rig_config,
                      "Run against a simulated rig with this truth (a `clearshape simulate --config` file) "
                      "instead of the built-in thesis rig");
       sub.add_option("--rig", o->rig,
                      "The rig: a built-in simulated truth (thesis, large-play; default: the protocol's "
                      "[study] rig, else thesis; docs/large-play.md) or the physical rig, serial:PORT or "
                      "serial:PORT?baud=N (docs/hardware.md; one run at a time, a run that loses a sample fails)");
       sub.add_option("--recordings", o->recordings,
                      "Run the study on recorded runs: a folder of CSVs with a manifest.toml (docs/recordings.md)");
       sub.add_option("--max-memory-gb", o->max_memory_gb,
                      "Refuse a protocol whose records would need more memory than this (estimated before "
                      "anything is written), GB")
           ->capture_default_str();
       sub.add_flag("--print-manifest", o->print_manifest,
                    "Print the recordings manifest template listing every run the protocol expects, and exit");
       sub.callback([o] { run(*o); });
     }});

}  // namespace
}  // namespace clearshape::cli
