// The arm study's TOML (arm/study.hpp; docs/arm.md, "The arm study"): strict keys, errors naming
// the file, line and key with the allowed values.
#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "clearshape/arm/study.hpp"
#include "clearshape/core/error.hpp"
#include "clearshape/io/atomic_file.hpp"
#include "clearshape/io/toml_section.hpp"

namespace clearshape::arm {

namespace {

using io::TomlSection;

// A number for every joint, or one array of numbers, each in (lo, hi] (lo_open) or [lo, hi].
std::vector<double> per_joint(const TomlSection& t, std::string_view key, double lo, double hi, bool lo_open) {
  const toml::node* n = t.node(key);
  std::vector<double> v;
  if (n != nullptr && (n->is_integer() || n->is_floating_point())) {
    v.push_back(t.number(key));
  } else {
    v = t.numbers(key);
    if (n != nullptr && v.empty()) t.fail(key, "is empty; allowed: a number, or one number per joint");
  }
  for (const double x : v) {
    if (x > hi || x < lo || (lo_open && x == lo)) {
      t.fail(key, fmt::format("= {} is out of range; allowed: {}{} … {}", x, lo_open ? "> " : "", lo, hi));
    }
  }
  return v;
}

void read_study_table(const TomlSection& t, ArmStudySpec& s) {
  s.name = t.text("name", s.name);
  const bool has_urdf = t.has("urdf") || t.has("config");
  if (has_urdf && t.has("arm")) t.fail("arm", "give either arm (a built-in arm) or urdf + config, not both");
  if (has_urdf) {
    s.arm.clear();
    s.urdf = t.text("urdf");
    s.config = t.text("config");
  } else {
    s.arm = t.text("arm", s.arm);
    const std::vector<std::string> names = builtin_arm_names();
    if (std::find(names.begin(), names.end(), s.arm) == names.end()) {
      t.fail("arm", fmt::format("'{}' is not a built-in arm; allowed: {} (or urdf + config)", s.arm,
                                fmt::join(names, ", ")));
    }
  }
  s.play_deg = per_joint(t, "play_deg", 0.0, 10.0, false);
  t.finish("name, arm, urdf, config, play_deg");
}

void read_benchmark(const TomlSection& t, ArmStudySpec& s) {
  s.moves = static_cast<std::size_t>(t.integer("moves", 20, 20, 1000));
  s.seed = static_cast<std::uint64_t>(t.integer("seed", 1, 0, std::int64_t{1} << 62));
  s.margin = t.number("margin", s.margin);
  if (!(s.margin >= 0.0 && s.margin <= 0.45)) t.fail("margin", fmt::format("= {} is out of range; allowed: 0 … 0.45", s.margin));
  const std::vector<double> v = per_joint(t, "velocity_rad_s", 0.0, 1e3, true);
  const std::vector<double> a = per_joint(t, "acceleration_rad_s2", 0.0, 1e5, true);
  const std::vector<double> j = per_joint(t, "jerk_rad_s3", 0.0, 1e7, true);
  if (v.size() != a.size() || v.size() != j.size()) {
    t.fail("velocity_rad_s", fmt::format("velocity_rad_s, acceleration_rad_s2 and jerk_rad_s3 have {}, {} and {} values; "
                                         "allowed: the same count (one, or one per joint)", v.size(), a.size(), j.size()));
  }
  s.limits.clear();
  for (std::size_t i = 0; i < v.size(); ++i) s.limits.push_back({v[i], a[i], j[i]});
  s.sample_time_s = t.number("sample_time_s", s.sample_time_s);
  if (!(s.sample_time_s >= 1e-4 && s.sample_time_s <= 0.01)) {
    t.fail("sample_time_s", fmt::format("= {} is out of range; allowed: 1e-4 … 0.01", s.sample_time_s));
  }
  s.settle_s = t.number("settle_s", s.settle_s);
  if (!(s.settle_s >= 0.2 && s.settle_s <= 10.0)) t.fail("settle_s", fmt::format("= {} is out of range; allowed: 0.2 … 10", s.settle_s));
  t.finish("moves, seed, margin, velocity_rad_s, acceleration_rad_s2, jerk_rad_s3, sample_time_s, settle_s");
}

void read_designs(const TomlSection& t, ArmStudySpec& s) {
  if (t.has("run")) s.designs = t.texts("run");
  for (const std::string& d : s.designs) {
    if (d != "fixed" && d != "scheduled" && d != "clearance-aware" && d != "flank-unshaped" && d != "flank-scheduled") {
      t.fail("run", fmt::format("'{}' is not a design; allowed: fixed, scheduled, clearance-aware, flank-unshaped, "
                                "flank-scheduled (unshaped is "
                                "always run: it is the reference)", d));
    }
    if (std::count(s.designs.begin(), s.designs.end(), d) > 1) t.fail("run", fmt::format("'{}' is listed twice", d));
  }
  const std::string method = t.text("method", "zvd");
  try {
    s.method = shaping::method_from_string(method);
  } catch (const InvalidArgument& e) {
    t.fail("method", e.what());
  }
  s.every_mode = t.boolean("every_mode", false);
  s.evaluations = static_cast<int>(t.integer("evaluations", s.evaluations, 10, 100000));
  s.slots = static_cast<int>(t.integer("slots", s.slots, 2, 32));
  s.threads = static_cast<int>(t.integer("threads", s.threads, 1, 64));
  s.flank_margin = t.number("flank_margin", s.flank_margin);
  if (!(s.flank_margin > 0.0 && s.flank_margin <= 1.0)) {
    t.fail("flank_margin", fmt::format("= {} is out of range; allowed: 0 < flank_margin <= 1", s.flank_margin));
  }
  s.flank_floor = t.number("flank_floor", s.flank_floor);
  if (!(s.flank_floor > 0.0 && s.flank_floor <= 1.0)) {
    t.fail("flank_floor", fmt::format("= {} is out of range; allowed: 0 < flank_floor <= 1", s.flank_floor));
  }
  t.finish("run, method, every_mode, evaluations, slots, threads, flank_margin, flank_floor");
}

}  // namespace

ArmStudySpec parse_arm_study(std::string_view text, const std::string& file) {
  const toml::table root = io::parse_toml(text, file);
  const TomlSection top(root, "", file);
  ArmStudySpec s;
  s.file = file;
  s.name = std::filesystem::path(file).stem().string();
  s.limits = {{2.0, 20.0, 400.0}};
  const auto study = top.table("study");
  if (!study) top.fail("study", "is missing; allowed: a [study] table naming the arm");
  read_study_table(*study, s);
  if (const auto b = top.table("benchmark")) read_benchmark(*b, s);
  if (const auto d = top.table("designs")) read_designs(*d, s);
  if (const auto m = top.table("map")) {
    s.map_points = static_cast<int>(m->integer("points", s.map_points, 2, 101));
    m->finish("points");
  }
  top.finish("study, benchmark, designs, map");
  const std::filesystem::path folder = std::filesystem::path(file).parent_path();
  if (!s.urdf.empty() && s.urdf.is_relative()) s.urdf = folder / s.urdf;
  if (!s.config.empty() && s.config.is_relative()) s.config = folder / s.config;
  return s;
}

ArmStudySpec read_arm_study(const std::filesystem::path& file) {
  return parse_arm_study(io::read_text_file(file), file.string());
}

void make_quick(ArmStudySpec& spec) {
  spec.moves = std::min<std::size_t>(spec.moves, 3);
  spec.evaluations = 10;
  spec.map_points = 3;
  spec.quick = true;
}

ArmModel study_arm(const ArmStudySpec& spec) {
  ArmModel arm = spec.arm.empty() ? load_arm(spec.urdf.string(), spec.config.string()) : builtin_arm(spec.arm);
  const auto dof = static_cast<std::size_t>(arm.dof());
  const auto fits = [&](std::size_t n) { return n == 0 || n == 1 || n == dof; };
  if (!fits(spec.play_deg.size()) || !fits(spec.limits.size())) {
    throw InvalidArgument(fmt::format("{}: study.play_deg has {} values and the benchmark's limits {}; allowed: one, "
                                      "or one per joint of {} ({})", spec.file, spec.play_deg.size(),
                                      spec.limits.size(), arm.name, dof));
  }
  if (!spec.play_deg.empty()) {
    for (std::size_t i = 0; i < dof; ++i) {
      const double deg = spec.play_deg[spec.play_deg.size() == 1 ? 0 : i];
      arm.joints[i].half_play_rad = 0.5 * deg * M_PI / 180.0;
    }
  }
  return arm;
}

}  // namespace clearshape::arm
