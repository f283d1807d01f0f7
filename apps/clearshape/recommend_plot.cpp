#include "recommend_plot.hpp"

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

}  // namespace

std::filesystem::path python_dir() {
  if (const char* env = std::getenv("CLEARSHAPE_PYTHON_DIR"); env != nullptr && *env != '\0') return env;
  return CLEARSHAPE_PYTHON_DIR;
}

void write_recommend_plot(const std::filesystem::path& png, const study::RecommendReport& report) {
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
    f << study::recommend_plot_data(report).dump();
    if (!f) throw RuntimeError("cannot write the plot's data to a temporary file");
  }
  const int code = run_python({"/usr/bin/python3", script.string(), data.string(), out.string()});
  if (code != 0) throw RuntimeError(fmt::format("--plot: {} failed (exit {}); see its message above", script.string(), code));
  const std::string bytes = io::read_text_file(out);
  if (bytes.empty()) throw RuntimeError("--plot: the figure is empty");
  io::write_text_atomic(png, bytes);
}

}  // namespace clearshape::cli
