// clearshape arm study: the arm's pick-and-place study of a study TOML (docs/arm.md, "The arm
// study"): every design on every move, the mode map, results.json and tables.md into --out. The
// library does the work (arm/study.hpp).
#include <chrono>
#include <memory>
#include <string>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "arm_options.hpp"
#include "clearshape/arm/study.hpp"

namespace clearshape::cli {

namespace {

struct StudyState {
  std::string file, out;
  bool quick = false;
  int threads = 0;
};

void run_study(const StudyState& st) {
  arm::ArmStudySpec spec = arm::read_arm_study(st.file);
  if (st.quick) arm::make_quick(spec);
  if (st.threads > 0) spec.threads = st.threads;
  const arm::ArmModel model = arm::study_arm(spec);
  const auto start = std::chrono::steady_clock::now();
  const arm::ArmStudyResult result = arm::run_arm_study(spec, model);
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  arm::write_arm_study(st.out, spec, model, result);
  fmt::print("arm study   {} on {} ({} moves, {} threads): {:.1f} s\n", spec.name, model.name, result.moves.size(),
             spec.threads, wall_s);
  const double reference = result.designs.front().total_residual_m;
  for (const arm::BenchmarkDesign& b : result.designs) {
    fmt::print("  {:<16} {:9.4f} mm  {}\n", b.name, 1e3 * b.total_residual_m,
               &b == &result.designs.front() ? std::string("reference")
               : b.total_residual_m > reference
                   ? fmt::format("{:.1f} % (worse than unshaped)", 100.0 * b.improvement)
                   : fmt::format("{:.1f} % removed", 100.0 * b.improvement));
  }
  fmt::print("written     {}/results.json, {}/tables.md\n", st.out, st.out);
}

}  // namespace

void setup_arm_study(CLI::App& parent) {
  auto st = std::make_shared<StudyState>();
  CLI::App* sub = parent.add_subcommand(
      "study", "The arm's pick-and-place study of a study TOML: tool-tip residual (Eq. 5.1) per design and move, "
               "the mode map over the workspace; writes results.json and tables.md (docs/arm.md)");
  sub->add_option("file", st->file, "The study TOML (e.g. studies/arm-scara2.toml)")->required()->check(CLI::ExistingFile);
  sub->add_option("--out", st->out, "Output folder for results.json and tables.md")->required();
  sub->add_flag("--quick", st->quick, "A few seconds' run for tests: 3 moves, 10 evaluations per clearance-aware "
                                      "design, 3×3 map poses");
  sub->add_option("--threads", st->threads, "Moves played in parallel (1-64; default the study's designs.threads)")
      ->check(CLI::Range(1, 64));
  sub->callback([st] { run_study(*st); });
}

}  // namespace clearshape::cli
