// clearshape sweep: grid / Monte-Carlo sweeps over rig truth, command and shaper, on this
// machine or a Dask cluster (docs/sweeps.md). The engine is the Python package clearshape
// (bindings/python/clearshape/sweep.py, which runs the points through the C++ bindings and
// talks to Dask); this command checks its options and runs `python3 -m clearshape.sweep`.
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <unistd.h>

#include <CLI/CLI.hpp>

#include "clearshape/core/error.hpp"
#include "clearshape/io/atomic_file.hpp"
#include "command.hpp"

#ifndef CLEARSHAPE_PYTHON_EXECUTABLE
#define CLEARSHAPE_PYTHON_EXECUTABLE "/usr/bin/python3"
#endif
#ifndef CLEARSHAPE_PYTHON_BUILD_DIR
#define CLEARSHAPE_PYTHON_BUILD_DIR ""
#endif
#ifndef CLEARSHAPE_PYTHON_INSTALL_REL
#define CLEARSHAPE_PYTHON_INSTALL_REL "lib/python3/dist-packages"
#endif

namespace cs = clearshape;
namespace fs = std::filesystem;

namespace {

struct SweepState {
  std::string sweep;
  std::string out;
  std::string scheduler;
  unsigned workers = 0;
  unsigned retries = 2;
  long long max_points = 1'000'000;  // clearshape.sweep_spec.MAX_POINTS
  bool fresh = false;
  bool quiet = false;
};

// Where the package clearshape is: $CLEARSHAPE_PYTHONPATH, else beside an installed CLI
// (<prefix>/bin/../lib/python3/dist-packages), else the build tree this CLI was built in.
std::string python_path() {
  if (const char* env = std::getenv("CLEARSHAPE_PYTHONPATH"); env != nullptr && *env != '\0') return env;
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    const fs::path installed = exe.parent_path().parent_path() / CLEARSHAPE_PYTHON_INSTALL_REL;
    if (fs::exists(installed / "clearshape" / "__init__.py", ec)) return installed.string();
  }
  const fs::path build = CLEARSHAPE_PYTHON_BUILD_DIR;
  if (!build.empty() && fs::exists(build / "clearshape" / "__init__.py", ec)) return build.string();
  throw cs::RuntimeError("clearshape sweep needs the Python package clearshape, which was not found beside the "
                         "CLI nor in the build tree; build it (CLEARSHAPE_BUILD_PYTHON=ON) or set CLEARSHAPE_PYTHONPATH");
}

void run_sweep(const SweepState& st) {
  if (!st.scheduler.empty() && st.scheduler.rfind("tcp://", 0) != 0 && st.scheduler.rfind("tls://", 0) != 0) {
    throw cs::InvalidArgument("--scheduler = " + st.scheduler + " must be a Dask address such as tcp://HOST:8786");
  }
  if (st.retries > 100) throw cs::InvalidArgument("--retries = " + std::to_string(st.retries) + " is out of range; allowed: [0, 100]");
  if (st.workers > 4096) throw cs::InvalidArgument("--workers = " + std::to_string(st.workers) + " is out of range; allowed: [1, 4096]");
  if (st.max_points < 1) {
    throw cs::InvalidArgument("--max-points = " + std::to_string(st.max_points) + " is out of range; allowed: >= 1");
  }
  if (const std::string problem = cs::io::folder_problem(st.out); !problem.empty()) {
    throw cs::InvalidArgument("--out " + problem + "; give a folder (created if missing) for "
                              "results.h5, results.csv and results.json");
  }
  const std::string path = python_path();
  const char* old = std::getenv("PYTHONPATH");
  const std::string joined = (old != nullptr && *old != '\0') ? path + ":" + old : path;
  ::setenv("PYTHONPATH", joined.c_str(), 1);
  std::vector<std::string> args = {CLEARSHAPE_PYTHON_EXECUTABLE, "-m", "clearshape.sweep", st.sweep, "--out", st.out,
                                   "--retries", std::to_string(st.retries), "--max-points",
                                   std::to_string(st.max_points)};
  if (!st.scheduler.empty()) args.insert(args.end(), {"--scheduler", st.scheduler});
  if (st.workers > 0) args.insert(args.end(), {"--workers", std::to_string(st.workers)});
  if (st.fresh) args.emplace_back("--fresh");
  if (st.quiet) args.emplace_back("--quiet");
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  std::fflush(stdout);
  ::execv(argv[0], argv.data());  // returns only on failure; the module's exit code is ours
  throw cs::RuntimeError(std::string("cannot run ") + CLEARSHAPE_PYTHON_EXECUTABLE + " for the sweep");
}

void setup_sweep(CLI::App& sub) {
  auto st = std::make_shared<SweepState>();
  sub.add_option("sweep", st->sweep, "Sweep file (TOML; docs/sweeps.md)")->required()->check(CLI::ExistingFile);
  sub.add_option("--out,-o", st->out, "Output folder: results.h5, results.csv, results.json")->required();
  sub.add_option("--scheduler", st->scheduler, "Dask scheduler address tcp://HOST:8786 (default: this machine)");
  sub.add_option("--workers", st->workers, "Local worker processes, [1, 4096] (default: every core)");
  sub.add_option("--retries", st->retries, "Dask: retries of a failed task, [0, 100]")->capture_default_str();
  sub.add_flag("--fresh", st->fresh, "Remove the folder's earlier sweep results first (only the sweep's own files)");
  sub.add_flag("--quiet", st->quiet, "No progress lines on stderr");
  sub.add_option("--max-points", st->max_points,
                 "Refuse a sweep of more points than this (its estimate is printed first; ~2 kB of memory per point)")
      ->capture_default_str();
  sub.footer(
      "Examples:\n"
      "  clearshape sweep studies/sweep-play.toml --out out/sweep-play\n"
      "  clearshape sweep studies/sweep-play.toml --out out/sweep-play --scheduler tcp://head:8786");
  sub.callback([st] { run_sweep(*st); });
}

const bool sweep_registered = cs::cli::register_command(
    {"sweep", "Sweep rig, command and shaper parameters (grid / Monte-Carlo; local or Dask)", 90, setup_sweep});

}  // namespace
