// Stage 7, the measurement floor (issue 12), as plan → run → tabulate: the protocol's rest trials
// (rig_tests.floor_trials; a zero command of the record's length, seeded like every trial), Eq. 5.1
// on each in every rig table's input window, and the table "What a command can reach here": the
// 90 % target of each input against that floor and the best shaped column (measurement_floor.hpp).
#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "clearshape/study/measurement_floor.hpp"
#include "clearshape/study/measures.hpp"
#include "context.hpp"
#include "rig_tests.hpp"

namespace clearshape::study::detail {

namespace {

std::vector<RunRequest> plan_rest_trials(const Context& c) {
  UniformSeries zero = c.command_of(c.p.inputs.front(), c.p.record_s);  // the record's length
  std::fill(zero.values.begin(), zero.values.end(), 0.0);
  std::vector<RunRequest> requests;
  for (int r = 1; r <= c.p.rig_tests.floor_trials; ++r) {
    RunRequest req;
    req.id = rest_run_id(r);
    req.stage = "rest";
    req.column = "rest";
    req.repetition = r;
    req.seed = run_seed(c.p.seed, req.id);
    req.command = zero;
    req.record_s = c.p.record_s;
    requests.push_back(std::move(req));
  }
  return requests;
}

const json* rig_table_json(const Context& c, const std::string& id) {
  for (const auto& t : c.tables) {
    // find() rather than value(): GCC 12 warns -Wnull-dereference inside value() when inlined here.
    const auto table_id = t.find("id"), kind = t.find("kind");
    if (table_id != t.end() && kind != t.end() && *table_id == id && *kind == "mean-deviation") return &t;
  }
  return nullptr;
}

// A column whose design came out as the identity (a single unit impulse at 0, or no design at
// all: its note says so) ran the unshaped command: a second set of unshaped trials, not a design.
bool runs_unshaped(const json& col) {
  const auto note = col.find("note");
  if (note != col.end() && note->is_string() && note->get<std::string>().rfind("identity shaper", 0) == 0) return true;
  const auto shaper = col.find("shaper");
  if (shaper == col.end() || !shaper->is_object() || !shaper->contains("impulses")) return false;
  const json& impulses = shaper->at("impulses");
  return impulses.size() == 1 && impulses[0].at("time_s").get<double>() == 0.0 &&
         impulses[0].at("amplitude").get<double>() == 1.0;
}

// The numbers of one rig table's verdict: its unshaped column and its shaped column with the
// smallest mean MD (the key of that column in `best_key`); columns that ran unshaped are skipped.
ReachNumbers reach_numbers(const json& table, const MeanStd& floor, std::string& best_key) {
  ReachNumbers n;
  n.floor_mean = floor.mean;
  n.floor_std = floor.std;
  for (const auto& col : table.at("columns")) {
    const json& m = col.at("ours_mean");
    if (!m.is_number()) continue;
    const double mean = m.get<double>();
    if (col.at("key") == "none") {
      n.unshaped_mean = mean;
      n.unshaped_std = col.at("ours_std").get<double>();
    } else if (std::isfinite(mean) && !runs_unshaped(col) && (n.best_label.empty() || mean < n.best_mean)) {
      n.best_mean = mean;
      n.best_label = col.at("label").get<std::string>();
      best_key = col.at("key").get<std::string>();
    }
  }
  return n;
}

std::string trials_kind(const Context& c) {
  return c.source->kind().rfind("simulated", 0) == 0
             ? "on the simulated rig with the same seeded noise and run-to-run variation as every trial"
             : "measured on the " + c.source->description();
}

// Where the table's trials start their steady state (Eq. 5.1's k): the median over every trial
// of every column; the input's last move start when the rig tests were skipped.
double window_start_s(const json* rig, const InputSpec& in) {
  std::vector<double> starts;
  if (rig != nullptr) {
    for (const auto& col : rig->at("columns")) {
      for (const auto& v : col.value("start_time_s", json::array())) starts.push_back(v.get<double>());
    }
  }
  return starts.empty() ? in.last_move_start_s : median(starts);
}

// One rig table's floor (results.json sections.measurement_floor.tables.<id>).
json floor_of(const Context& c, const std::vector<Record>& rest, const json* rig, const InputSpec& in) {
  const double start_s = window_start_s(rig, in);
  const std::vector<double> md = floor_mean_deviations(rest, c.p.measure, start_s);
  const MeanStd ms = mean_std(md);
  std::vector<double> searched, searched_start;
  for (const Record& r : rest) {
    const auto mdr = run_mean_deviation(r, c.p.measure, in);
    searched.push_back(mdr.mean_deviation);
    searched_start.push_back(mdr.start_time_s);
  }
  return {{"input", in.name},
          {"start_time_s", start_s},
          {"start", rig != nullptr ? "median steady-state start of the table's trials" : "the input's last move start"},
          {"ours", md},
          {"ours_mean", ms.mean},
          {"ours_std", ms.std},
          {"searched_ours_mean", mean_std(searched).mean},
          {"searched_start_time_s_mean", mean_std(searched_start).mean}};
}

// The reach table's columns, one entry per rig table with a floor to compare (tabulate → table).
struct ReachRows {
  json rows = json::array(), unshaped_mean = json::array(), unshaped_std = json::array(), target = json::array(),
       floor_mean = json::array(), floor_std = json::array(), best_mean = json::array(), best_keys = json::array(),
       best_labels = json::array(), verdicts = json::array(), headline = json::object();
  std::string note;

  void add(const std::string& table_id, const InputSpec& in, const json& f, const ReachNumbers& num,
           const std::string& best_key, const ReachVerdict& v) {
    const std::string label = fmt::format("{} ({})", in.label, table_id);
    rows.push_back(label);
    unshaped_mean.push_back(num.unshaped_mean);
    unshaped_std.push_back(num.unshaped_std);
    target.push_back(v.target);
    floor_mean.push_back(num.floor_mean);
    floor_std.push_back(num.floor_std);
    best_mean.push_back(opt(best_key.empty() ? std::nullopt : std::optional<double>(num.best_mean)));
    best_keys.push_back(best_key.empty() ? json(nullptr) : json(best_key));
    best_labels.push_back(best_key.empty() ? json(nullptr) : json(num.best_label));
    verdicts.push_back(std::string(to_string(v.reach)));
    headline[table_id] = {{"input", in.name},
                          {"unshaped_mean", num.unshaped_mean},
                          {"unshaped_std", num.unshaped_std},
                          {"target", v.target},
                          {"floor_mean", num.floor_mean},
                          {"floor_std", num.floor_std},
                          {"floor_start_time_s", f.at("start_time_s")},
                          {"floor_improvement_percent", opt(std::isfinite(v.floor_improvement_percent)
                                                                ? std::optional<double>(v.floor_improvement_percent)
                                                                : std::nullopt)},
                          {"best_column", best_keys.back()},
                          {"best_mean", best_mean.back()},
                          {"verdict", verdicts.back()},
                          {"sentence", v.sentence}};
    note += fmt::format("{}: {}. ", label, v.sentence);
  }
};

json reach_table(const Context& c, const ReachRows& r, const std::string& unit) {
  const int n = c.p.rig_tests.floor_trials;
  json t = make_table("reach", "reach",
                      fmt::format("What a command can reach here: the {:g} % target against the measurement floor",
                                  kReachTargetImprovementPercent),
                      unit);
  t["row_labels"] = r.rows;
  t["columns"] = json::array(
      {{{"key", "unshaped_mean"}, {"label", "unshaped MD, mean"}, {"ours", r.unshaped_mean}},
       {{"key", "unshaped_std"}, {"label", "unshaped MD, std"}, {"ours", r.unshaped_std}},
       {{"key", "target"},
        {"label", fmt::format("{:g} % target ({:g} × unshaped mean)", kReachTargetImprovementPercent,
                              1.0 - kReachTargetImprovementPercent / 100.0)},
        {"ours", r.target}},
       {{"key", "floor_mean"}, {"label", "measurement floor, mean"}, {"ours", r.floor_mean}},
       {{"key", "floor_std"}, {"label", "measurement floor, std"}, {"ours", r.floor_std}},
       {{"key", "best_mean"},
        {"label", "best design's MD, mean"},
        {"ours", r.best_mean},
        {"best_column", r.best_keys},
        {"best_label", r.best_labels}}});
  t["verdicts"] = r.verdicts;  // per row: below-floor | reached | reachable (the sentences: headline, note)
  t["headline"] = r.headline;
  t["note"] = fmt::format(
      "{}The measurement floor is Eq. 5.1 on {} rest trials (a zero command for {} s, run ids rest/rNN), {}, "
      "through the same sensor chain and gyro-bias removal, over the window the table's trials used (from the "
      "median of their steady-state starts to the end): what the MD reads when nothing moves. A {:g} % "
      "improvement needs an MD of {:g} × the "
      "unshaped mean; where that target is below the floor's mean, no command can show it on this rig's sensors.",
      r.note, n, c.p.record_s, trials_kind(c), kReachTargetImprovementPercent,
      1.0 - kReachTargetImprovementPercent / 100.0);
  return t;
}

void tabulate_floor(Context& c, const std::vector<Record>& rest) {
  const std::string unit = md_unit_of(c);
  const int n = c.p.rig_tests.floor_trials;
  json section;
  section["trials"] = n;
  json ids = json::array();
  for (const auto& r : rest) ids.push_back(r.id);
  section["runs"] = ids;
  section["unit"] = unit;
  section["target_improvement_percent"] = kReachTargetImprovementPercent;
  json floors = json::object();
  std::vector<std::string> csv_names{"trial"};
  std::vector<std::vector<double>> csv{{}};
  for (int r = 1; r <= n; ++r) csv[0].push_back(r);
  ReachRows rows;
  for (const auto& table : c.p.rig_tests.tables) {
    const InputSpec& in = c.p.input(table.input);
    const json* rig = rig_table_json(c, table.id);
    const json f = floor_of(c, rest, rig, in);
    floors[table.id] = f;
    csv_names.push_back("md_" + table.id);
    csv.push_back(f.at("ours").get<std::vector<double>>());
    if (rig == nullptr) continue;  // the rig tests were skipped: a floor, but nothing to compare
    const MeanStd floor{f.at("ours_mean").get<double>(), f.at("ours_std").get<double>()};
    std::string best_key;
    const ReachNumbers num = reach_numbers(*rig, floor, best_key);
    rows.add(table.id, in, f, num, best_key, reach_verdict(num, unit));
  }
  section["tables"] = floors;
  c.sections["measurement_floor"] = section;
  std::vector<const std::vector<double>*> data;
  for (const auto& v : csv) data.push_back(&v);
  write_data_csv(c, "measurement_floor.csv", csv_names, data);
  if (!rows.rows.empty()) c.tables.push_back(reach_table(c, rows, unit));
}

}  // namespace

void stage_measurement_floor(Context& c) {
  if (c.p.rig_tests.floor_trials <= 0) return;
  const std::vector<Record> rest = c.run_all(plan_rest_trials(c), "measurement-floor");
  tabulate_floor(c, rest);
}

}  // namespace clearshape::study::detail
