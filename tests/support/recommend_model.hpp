#pragma once
// What the `recommend --model` CLI tests share: the spectrum they recommend from, a thesis-like
// P3UZ drive for a fit-clearance document, and the unshaped MD `recommend` predicts on a model.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "support/cli.hpp"
#include "support/paths.hpp"

namespace clearshape::testing {

/// `recommend` on the one-mode spectrum of the golden data (the gyro column).
inline std::string recommend_spectrum_args() {
  return "recommend --data " + golden_path("recommend_one_mode.csv").string() + " --column gyro_deg_s";
}

/// The thesis position drive (P3UZ) as a fit-clearance document's "drive".
inline const char* const kThesisDriveJson = R"({"model": "P3UZ", "parameters": {"Kp": {"value": 0.9959}, "Tz": {"value": 0.0042},
  "Zeta": {"value": 0.9968}, "Tw": {"value": 0.0102}, "Tp3": {"value": 0.0034}}})";

/// The rest of a `simulate --config` file after [joint] and [contact]: the thesis link (J 0.005,
/// no gravity, no ground drag), the same P3UZ drive, a gyroscope without its low pass.
inline const char* const kThesisLinkDriveToml = R"([link]
inertia_kg_m2 = 0.005
mass_kg = 0.0
com_distance_m = 0.0
axis_tilt_deg = 0.0
ground_viscous_n_m_s_per_rad = 0.0
[drive.position]
kp = 0.9959
tz_s = 0.0042
zeta = 0.9968
tw_s = 0.0102
tp3_s = 0.0034
td_s = 0.0
[gyroscope]
low_pass_hz = 0
)";

/// `<tmp>/<prefix>_<pid>_<name>`: a test's own file, per process, keeping `name`'s extension.
inline std::filesystem::path pid_temp_file(const std::string& prefix, const std::string& name) {
  return std::filesystem::temp_directory_path() / (prefix + "_" + std::to_string(::getpid()) + "_" + name);
}

/// Writes `text` to `path` (test fixtures; the file is the test's own).
inline void write_text(const std::filesystem::path& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
}

/// The unshaped MD `recommend --model fit --move step<move>` predicts (−1 and a failure if it fails).
inline double recommend_unshaped_md(const std::filesystem::path& fit, const std::string& move) {
  const auto r = run_cli(recommend_spectrum_args() + " --model " + fit.string() + " --move step" + move +
                         " --move-duration-s 3 --json");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return r.exit_code == 0 ? nlohmann::json::parse(r.out)["model"]["unshaped_md"].get<double>() : -1.0;
}

/// Eq. 2.19: V = exp(−ζωt_N)·|Σ A_i exp(ζωt_i) exp(jω_d t_i)| of a JSON impulse list.
inline double linear_v(const nlohmann::json& impulses, double f_hz, double zeta) {
  const double w = 2.0 * M_PI * f_hz, wd = w * std::sqrt(1.0 - zeta * zeta);
  double c = 0.0, s = 0.0;
  for (const auto& i : impulses) {
    const double t = i["time_s"].get<double>(), a = i["amplitude"].get<double>();
    c += a * std::exp(zeta * w * t) * std::cos(wd * t);
    s += a * std::exp(zeta * w * t) * std::sin(wd * t);
  }
  return std::exp(-zeta * w * impulses.back()["time_s"].get<double>()) * std::hypot(c, s);
}

/// On a rigid link, `recommend --model … --json`'s predicted MDs must rank its available
/// candidates (and "none", V = 1) as the linear V at the model's mode (f_hz, zeta) does; pairs
/// within a factor 1.25 of V are near-ties and skipped. Returns the number of pairs compared.
inline int expect_md_ranks_as_linear_v(const nlohmann::json& doc, double f_hz, double zeta) {
  struct Row { std::string name; double v, md; };
  std::vector<Row> rows{{"none", 1.0, doc["model"]["unshaped_md"].get<double>()}};
  for (const auto& c : doc["candidates"]) {
    if (c.contains("available") && !c["available"].get<bool>()) continue;
    rows.push_back({c["name"], linear_v(c["impulses"], f_hz, zeta), c["predicted_md"].get<double>()});
  }
  int compared = 0;
  for (const auto& a : rows) {
    for (const auto& b : rows) {
      if (a.v * 1.25 < b.v) {
        ++compared;
        EXPECT_LT(a.md, b.md) << a.name << " V " << a.v << " MD " << a.md << " vs " << b.name << " V " << b.v << " MD " << b.md;
      }
    }
  }
  return compared;
}

}  // namespace clearshape::testing
