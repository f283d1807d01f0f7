#include "recommend_plot.hpp"

#include <algorithm>
#include <cstdlib>
#include <fstream>

#include <sys/wait.h>
#include <unistd.h>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "clearshape/core/error.hpp"
#include "clearshape/io/atomic_file.hpp"

#ifndef CLEARSHAPE_PYTHON_DIR
#define CLEARSHAPE_PYTHON_DIR "python"
#endif

namespace clearshape::cli {

namespace {

// A private temporary folder, removed when the plot is done (or failed).
struct TempDir {
  std::filesystem::path path;
  TempDir() {
    std::string pattern = (std::filesystem::temp_directory_path() / "clearshape-plot-XXXXXX").string();
    if (::mkdtemp(pattern.data()) == nullptr) throw RuntimeError("cannot create a temporary folder for the plot");
    path = pattern;
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
};

int run_python(const std::vector<std::string>& args) {
  std::vector<char*> argv;
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  const pid_t pid = ::fork();
  if (pid < 0) throw RuntimeError("cannot start python3 for the plot (fork failed)");
  if (pid == 0) {
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  int status = 0;
  if (::waitpid(pid, &status, 0) < 0) throw RuntimeError("waiting for the plot's python3 failed");
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128;
}

nlohmann::ordered_json figure_data(const std::vector<advise::MeasuredSpectrum>& spectra, const advise::Recommendation& r) {
  double top = 0.0;
  for (const auto& m : r.modes) top = std::max(top, m.frequency_hz);
  double f_max = 0.0;
  for (const auto& s : spectra) f_max = std::max(f_max, s.frequency_hz.back());
  f_max = std::min(f_max, 3.0 * top);
  nlohmann::ordered_json doc;
  nlohmann::ordered_json sp = nlohmann::ordered_json::array();
  for (const auto& s : spectra) {
    std::vector<double> f, p;
    for (std::size_t k = 0; k < s.frequency_hz.size() && s.frequency_hz[k] <= f_max; ++k) {
      f.push_back(s.frequency_hz[k]);
      p.push_back(s.power[k]);
    }
    sp.push_back({{"label", std::filesystem::path(s.source).filename().string() + " (" + s.column + ")"},
                  {"frequency_hz", f},
                  {"power", p}});
  }
  doc["spectra"] = sp;
  std::vector<double> grid;
  for (int k = 0; k <= 600; ++k) grid.push_back(f_max * k / 600.0);
  doc["frequency_hz"] = grid;
  nlohmann::ordered_json cands = nlohmann::ordered_json::array();
  for (std::size_t i = 0; i < r.candidates.size(); ++i) {
    const auto& c = r.candidates[i];
    if (!c.available || !c.shaper) continue;
    cands.push_back({{"name", c.name},
                     {"design_frequency_hz", c.design_frequency_hz},
                     {"remaining_worst", c.remaining_worst},
                     {"duration_s", c.duration_s},
                     {"chosen", r.chosen && *r.chosen == i},
                     {"response", advise::worst_response(*c.shaper, grid, r.test_damping_ratios, r.frequency_scales)}});
    if (r.printer_figures) {  // Klipper's legend: smoothing and max acceleration (advise/smoothing.hpp)
      cands.back()["smoothing_mm"] = c.smoothing_mm;
      cands.back()["max_accel_mm_s2"] = std::isfinite(c.max_accel_mm_s2) ? nlohmann::ordered_json(c.max_accel_mm_s2) : nullptr;
    }
  }
  doc["candidates"] = cands;
  nlohmann::ordered_json modes = nlohmann::ordered_json::array();
  for (const auto& m : r.modes) modes.push_back({{"frequency_hz", m.frequency_hz}, {"frequency_std_hz", m.frequency_std_hz}});
  doc["modes"] = modes;
  doc["reason"] = r.reason;
  return doc;
}

}  // namespace

std::filesystem::path python_dir() {
  if (const char* env = std::getenv("CLEARSHAPE_PYTHON_DIR"); env != nullptr && *env != '\0') return env;
  return CLEARSHAPE_PYTHON_DIR;
}

void write_recommend_plot(const std::filesystem::path& png, const std::vector<advise::MeasuredSpectrum>& spectra,
                          const advise::Recommendation& recommendation) {
  if (png.extension() != ".png") throw InvalidArgument(fmt::format("--plot {}: the figure is a PNG; give a path ending in .png", png.string()));
  io::check_not_input(png);
  const std::filesystem::path script = python_dir() / "plot_recommend.py";
  if (!std::filesystem::exists(script)) {
    throw RuntimeError(fmt::format("--plot: {} not found (set CLEARSHAPE_PYTHON_DIR to the folder holding it)", script.string()));
  }
  TempDir tmp;
  const auto data = tmp.path / "recommend.json";
  const auto out = tmp.path / "recommend.png";
  {
    std::ofstream f(data);
    f << figure_data(spectra, recommendation).dump();
    if (!f) throw RuntimeError("cannot write the plot's data to a temporary file");
  }
  const int code = run_python({"/usr/bin/python3", script.string(), data.string(), out.string()});
  if (code != 0) throw RuntimeError(fmt::format("--plot: {} failed (exit {}); see its message above", script.string(), code));
  const std::string bytes = io::read_text_file(out);
  if (bytes.empty()) throw RuntimeError("--plot: the figure is empty");
  io::write_text_atomic(png, bytes);
}

}  // namespace clearshape::cli
