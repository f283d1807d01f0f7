// Stage 6: rig tests (thesis §5.1.2, §5.2.2, Appendix B): repeated trials of each table column on
// the rig, Eq. 5.1 per trial, means, improvements (Table 5.1, 5.2, B.1–B.6).
#include <cmath>

#include <fmt/format.h>

#include "clearshape/core/error.hpp"
#include "clearshape/metrics/improvement.hpp"
#include "clearshape/shaping/apply.hpp"
#include "clearshape/study/measures.hpp"
#include "context.hpp"
#include "rig_tests.hpp"

namespace clearshape::study::detail {

namespace {

// Figure data of a rig table: trial 1 of every column (command, link rate, MD signal).
struct RigFigureData {
  std::vector<std::string> names{"time_s"};
  std::vector<std::vector<double>> fig;
  json fig_series = json::array(), cmd_series = json::array(), annotations = json::object();
};

// What the trials are, for the tables' notes: the simulated rig's shaped columns are predictions
// of the study's own model; recorded or physical trials are measurements of that rig.
std::string trials_note(const Context& c) {
  const std::string kind = c.source->kind();
  if (kind.rfind("simulated", 0) == 0) return "Trials on the simulated rig; shaped columns are predictions, not fitted.";
  return fmt::format("Trials measured on the {} ({}), not the thesis's rig.", kind == "recordings" ? "recorded rig" : "physical rig",
                     c.source->description());
}

}  // namespace

RigTestPlan plan_rig_tests(Context& c) {
  RigTestPlan plan;
  for (const auto& table : c.p.rig_tests.tables) {
    const InputSpec& in = c.p.input(table.input);
    const UniformSeries command = c.command_of(in, c.p.record_s);
    for (const auto& col : table.columns) {
      PlannedColumn pl{&table, &col, std::nullopt, "", plan.requests.size()};
      if (col.shaper == kTakeUpShaper) {  // per input: the profile depends on the move
        pl.shaper = take_up_for(c, in, pl.note);
        if (!pl.shaper) pl.note = "identity shaper (runs unshaped): " + pl.note;
      } else if (col.shaper != "none") {
        pl.shaper = design_for(c, col.shaper, col.mode_source, pl.note);
        if (!pl.shaper) pl.note = "identity shaper (runs unshaped): " + pl.note;
      }
      const UniformSeries shaped = pl.shaper ? shaping::shape_offline(*pl.shaper, command, false) : command;
      for (int r = 1; r <= c.p.repetitions; ++r) {
        RunRequest req;
        req.id = rig_test_run_id(table.id, col.key(), r);
        req.stage = "rig-tests";
        req.input = table.input;
        req.column = col.key();
        req.repetition = r;
        req.seed = run_seed(c.p.seed, req.id);
        req.shaper = pl.shaper;
        req.command = shaped;
        req.record_s = c.p.record_s;
        plan.requests.push_back(std::move(req));
      }
      plan.columns.push_back(std::move(pl));
    }
  }
  return plan;
}

// Figures of one rig table (thesis Figs. 5.3/5.8/5.18–5.20, the Eq. 5.1 illustration of Fig. 5.9)
// and their data file data/rig_<table>.csv: trial 1 of every column.
void write_rig_figures(Context& c, const RigTable& table, const RigTestPlan& plan, RigFigureData& fd) {
  const InputSpec& in = c.p.input(table.input);
  const std::string md_unit = md_unit_of(c);
  auto& names = fd.names;
  auto& fig = fd.fig;
  auto& fig_series = fd.fig_series;
  auto& cmd_series = fd.cmd_series;
  auto& annotations = fd.annotations;
  std::vector<const std::vector<double>*> data;
  for (const auto& v : fig) data.push_back(&v);
  const std::string file = fmt::format("rig_{}.csv", table.id);
  write_data_csv(c, file, names, data);
  const bool speed = c.p.mode == rig::CommandMode::speed;
  const std::string type(in.signal.type());
  c.figures.push_back({{"id", fmt::format("rig-{}", table.id)},
                       {"thesis_figure", speed ? "5.8" : (type == "double-step" ? "5.20" : "5.19")},
                       {"kind", "time-series"},
                       {"title", fmt::format("Rig trial 1, {}: {} ({})", in.label,
                                             speed ? "link rate" : "link angle", md_unit)},
                       {"file", c.data_file(file)},
                       {"x", {{"column", "time_s"}, {"label", "time (s)"}}},
                       {"y_label", speed ? "link rate (deg/s)" : "link angle (deg)"},
                       {"series", fig_series},
                       {"mean_deviation", annotations}});
  c.figures.push_back({{"id", fmt::format("rig-inputs-{}", table.id)},
                       {"thesis_figure", speed ? "5.3" : "5.18"},
                       {"kind", "time-series"},
                       {"title", fmt::format("Unshaped and shaped commands, {}", in.label)},
                       {"file", c.data_file(file)},
                       {"x", {{"column", "time_s"}, {"label", "time (s)"}}},
                       {"y_label", fmt::format("command ({})", c.p.command_unit())},
                       {"series", cmd_series}});
  if (&table == &c.p.rig_tests.tables.front()) {
    const auto& a = annotations["none"];
    c.figures.push_back({{"id", "mean-deviation-illustration"},
                         {"thesis_figure", "5.9"},
                         {"kind", "mean-deviation"},
                         {"title", fmt::format("Eq. 5.1 on trial 1 of the {} without shaping: steady-state mean M "
                                               "and where the response first meets it", in.label)},
                         {"file", c.data_file(file)},
                         {"x", {{"column", "time_s"}, {"label", "time (s)"}}},
                         {"y_label", fmt::format("{} ({})", speed ? "link rate" : "link angle", md_unit)},
                         {"series", {{{"column", "md_signal_none"}, {"label", "response"}}}},
                         {"steady_mean", a.at("steady_mean")},
                         {"start_time_s", a.at("start_time_s")},
                         {"start_rule", a.at("start_rule")},
                         {"band_half_width", a.at("band_half_width")}});
    // The same on a shaped trial whose start is a band entry (the one-sided approach the band
    // rule is for, metrics/mean_deviation.hpp), when trial 1 of a shaped column has one.
    for (const auto& pl : plan.columns) {
      if (pl.table != &table || pl.column->key() == "none") continue;
      const auto& s = annotations[pl.column->key()];
      if (s.at("start_rule") != "band-entry") continue;
      c.figures.push_back({{"id", "mean-deviation-illustration-shaped"},
                           {"thesis_figure", nullptr},
                           {"kind", "mean-deviation"},
                           {"title", fmt::format("Eq. 5.1 on trial 1 of the {} {}: the response approaches M from "
                                                 "one side; the steady state starts where it enters ±b around M",
                                                 in.label, pl.column->label)},
                           {"file", c.data_file(file)},
                           {"x", {{"column", "time_s"}, {"label", "time (s)"}}},
                           {"y_label", fmt::format("{} ({})", speed ? "link rate" : "link angle", md_unit)},
                           {"series", {{{"column", fmt::format("md_signal_{}", pl.column->key())},
                                        {"label", "response"}}}},
                           {"steady_mean", s.at("steady_mean")},
                           {"start_time_s", s.at("start_time_s")},
                           {"start_rule", s.at("start_rule")},
                           {"band_half_width", s.at("band_half_width")}});
      break;
    }
  }
}

void tabulate_rig_table(Context& c, const RigTable& table, const RigTestPlan& plan, const std::vector<Record>& records,
                        RigTestTables& out) {
  const std::string md_unit = md_unit_of(c);
  const InputSpec& in = c.p.input(table.input);
  json t = make_table(table.id, "mean-deviation", table.title, md_unit);
  json rows = json::array();
  for (int r = 1; r <= c.p.repetitions; ++r) rows.push_back(std::to_string(r));
  t["row_labels"] = rows;
  json cols = json::array();
  json headline = json::object();
  double without_mean = std::numeric_limits<double>::quiet_NaN();
  std::optional<double> thesis_without;
  std::vector<double> without_values, thesis_without_values;
  // Figure data: trial 1 of every column (command, link rate, MD signal).
  RigFigureData fd;
  auto& names = fd.names;
  auto& fig = fd.fig;
  auto& fig_series = fd.fig_series;
  auto& cmd_series = fd.cmd_series;
  auto& annotations = fd.annotations;
  std::map<std::string, int> start_rules;  // rule → number of trials it decided
  for (const auto& pl : plan.columns) {
    if (pl.table != &table) continue;
    std::vector<double> values;
    std::vector<double> starts_s;
    json rules = json::array();
    for (int r = 0; r < c.p.repetitions; ++r) {
      const auto mdr = run_mean_deviation(records[pl.first + static_cast<std::size_t>(r)], c.p.measure, in);
      values.push_back(mdr.mean_deviation);
      starts_s.push_back(mdr.start_time_s);
      rules.push_back(std::string(metrics::to_string(mdr.start_rule)));
      ++start_rules[std::string(metrics::to_string(mdr.start_rule))];
    }
    out.md[table.id][pl.column->key()] = values;
    const MeanStd ms = mean_std(values);
    json col;
    col["key"] = pl.column->key();
    col["label"] = pl.column->label;
    col["ours"] = values;
    col["ours_mean"] = ms.mean;
    col["ours_std"] = ms.std;
    col["start_time_s"] = starts_s;  // Eq. 5.1 steady-state start of each trial
    col["start_rule"] = rules;       // which rule put it: crossing, band-entry, window-start
    col["thesis"] = pl.column->thesis.values;
    col["thesis_mean"] = opt(pl.column->thesis.mean);
    if (!pl.note.empty()) col["note"] = pl.note;
    if (pl.shaper) {
      json imps = json::array();
      for (const auto& i : pl.shaper->impulses()) imps.push_back({{"time_s", i.time_s}, {"amplitude", i.amplitude}});
      col["shaper"] = {{"method", pl.shaper->method()}, {"impulses", imps}};
    }
    if (pl.column->key() == "none") {
      without_mean = ms.mean;
      without_values = values;
      thesis_without_values = pl.column->thesis.values;
      thesis_without = pl.column->thesis.mean;
      if (!thesis_without && !thesis_without_values.empty()) thesis_without = mean_std(thesis_without_values).mean;
    } else {
      const auto ours = improvement(without_mean, ms.mean);
      // The thesis's improvement as it printed it (verbatim), and apart from it the value recomputed
      // from its means (its printed means, else the mean of its trials): the two differ where the
      // thesis rounded or miscalculated (5.1: printed 52.1 %, recomputed 51.3 %).
      const std::vector<double>& thesis_with_values = pl.column->thesis.values;
      std::optional<double> thesis_with = pl.column->thesis.mean;
      if (!thesis_with && !thesis_with_values.empty()) thesis_with = mean_std(thesis_with_values).mean;
      std::optional<double> recomputed;
      if (thesis_without && thesis_with) recomputed = improvement(*thesis_without, *thesis_with);
      const std::string seed_id = fmt::format("bootstrap/{}/{}", table.id, pl.column->key());
      const json ci = bootstrap_improvement_ci({&without_values, &values}, run_seed(c.p.seed, seed_id));
      col["improvement_percent"] = opt(ours);
      col["improvement_ci95_percent"] = ci;  // seeded bootstrap over the trials (rig_tests.hpp)
      col["improvement_significant"] = ci.is_array() ? json(ci[0].get<double>() > 0.0 || ci[1].get<double>() < 0.0)
                                                     : json(nullptr);
      col["thesis_improvement_percent"] = opt(pl.column->thesis_improvement);
      col["thesis_improvement_recomputed_percent"] = opt(recomputed);
      col["thesis_improvement_ci95_percent"] =
          bootstrap_improvement_ci({&thesis_without_values, &thesis_with_values}, run_seed(c.p.seed, seed_id + "/thesis"));
      col["improvement_difference_ci95_percent"] = bootstrap_improvement_ci(
          {&without_values, &values, &thesis_without_values, &thesis_with_values}, run_seed(c.p.seed, seed_id + "/diff"));
      headline[pl.column->key()] = {{"ours_mean", ms.mean}, {"thesis_mean", opt(pl.column->thesis.mean)},
                                    {"improvement_percent", opt(ours)},
                                    {"thesis_improvement_percent", opt(pl.column->thesis_improvement)}};
    }
    if (pl.column->key() == "none") {
      headline["none"] = {{"ours_mean", ms.mean}, {"thesis_mean", opt(pl.column->thesis.mean)}};
    }
    cols.push_back(col);

    const Record& first = records[pl.first];
    if (fig.empty()) fig.push_back(first.time_s);
    const UniformSeries s = md_series(first, c.p.measure);
    names.push_back(fmt::format("command_{}", pl.column->key()));
    fig.push_back(first.command);
    cmd_series.push_back({{"column", names.back()}, {"label", pl.column->label}});
    names.push_back(fmt::format("link_rate_deg_s_{}", pl.column->key()));
    fig.push_back(first.link_rate_deg_s);
    names.push_back(fmt::format("md_signal_{}", pl.column->key()));
    fig.push_back(s.values);
    if (pl.column->key() == "none" && c.p.mode == rig::CommandMode::position) {
      // The reference beside the responses, as in Figs. 5.19/5.20 (the step input in blue there);
      // position mode only: there the command is an angle on the responses' axis.
      fig_series.push_back({{"column", fmt::format("command_{}", pl.column->key())},
                            {"label", "command (unshaped input)"}, {"role", "command"}});
    }
    fig_series.push_back({{"column", names.back()}, {"label", pl.column->label}});
    const auto mdr = run_mean_deviation(first, c.p.measure, in);
    annotations[pl.column->key()] = {{"steady_mean", mdr.steady_mean}, {"start_time_s", mdr.start_time_s},
                                     {"mean_deviation", mdr.mean_deviation},
                                     {"start_rule", metrics::to_string(mdr.start_rule)},
                                     {"band_half_width", mdr.band_half_width}};
  }
  t["columns"] = cols;
  t["headline"] = headline;
  std::string decided;
  for (const auto& [rule, count] : start_rules) {
    decided += fmt::format("{}{} {}", decided.empty() ? "" : ", ", count, rule);
  }
  t["note"] = fmt::format("Eq. 5.1 on the {} ({}), steady state from where it first meets its mean after the "
                          "last move starts ({} s): a crossing of M, or entry into ±{:g} % of the move around M "
                          "for {:g} s (start rule per trial: {}). {}",
                          c.p.measure.md_signal == MdSignal::link_angle_deg ? "link angle (gyro integrated)"
                                                                            : "link rate (gyro)",
                          md_unit, in.last_move_start_s, 100.0 * metrics::MeanDeviationOptions{}.band_move_fraction,
                          metrics::MeanDeviationOptions{}.band_dwell_s, decided, trials_note(c));
  out.table_json[table.id] = t;
  c.tables.push_back(t);

  write_rig_figures(c, table, plan, fd);
}

void stage_rig_tests(Context& c) {
  if (c.p.rig_tests.tables.empty()) return;
  ensure_clearance_aware(c);
  const RigTestPlan plan = plan_rig_tests(c);
  const std::vector<Record> records = c.run_all(plan.requests, "rig-tests");
  RigTestTables tables;
  for (const auto& table : c.p.rig_tests.tables) tabulate_rig_table(c, table, plan, records, tables);
  tabulate_rig_summaries(c, tables);
}

}  // namespace clearshape::study::detail
