// Stage 6: rig tests (thesis §5.1.2, §5.2.2, Appendix B): repeated trials of each table column on
// the rig, Eq. 5.1 per trial, means, improvements (Table 5.1, 5.2, B.1–B.6).
#include <cmath>

#include <fmt/format.h>

#include "clearshape/core/error.hpp"
#include "clearshape/metrics/improvement.hpp"
#include "clearshape/shaping/apply.hpp"
#include "clearshape/study/measures.hpp"
#include "context.hpp"

namespace clearshape::study::detail {

namespace {

struct Planned {
  const RigTable* table;
  const RigColumn* column;
  std::optional<shaping::Shaper> shaper;
  std::string note;
  std::size_t first = 0;  // index of its first request
};

std::optional<double> improvement(double without, double with) {
  if (!(without > 0.0) || !std::isfinite(with)) return std::nullopt;
  return metrics::improvement_percent(without, with);
}

json opt(const std::optional<double>& v) { return v ? json(*v) : json(nullptr); }

}  // namespace

void stage_rig_tests(Context& c) {
  const auto& rt = c.p.rig_tests;
  if (rt.tables.empty()) return;
  const std::string md_unit = c.p.measure.md_signal == MdSignal::link_angle_deg ? "deg" : "deg/s";
  std::vector<Planned> plan;
  std::vector<RunRequest> requests;
  for (const auto& table : rt.tables) {
    const InputSpec& in = c.p.input(table.input);
    const UniformSeries command = c.command_of(in, c.p.record_s);
    for (const auto& col : table.columns) {
      Planned pl{&table, &col, std::nullopt, "", requests.size()};
      if (col.shaper != "none") {
        pl.shaper = design_for(c, col.shaper, col.mode_source, pl.note);
        if (!pl.shaper) pl.note = "identity shaper (runs unshaped): " + pl.note;
      }
      const UniformSeries shaped = pl.shaper ? shaping::shape_offline(*pl.shaper, command, false) : command;
      for (int r = 1; r <= c.p.repetitions; ++r) {
        RunRequest req;
        req.id = fmt::format("rig/{}/{}/r{:02d}", table.id, col.key(), r);
        req.stage = "rig-tests";
        req.input = table.input;
        req.column = col.key();
        req.repetition = r;
        req.seed = run_seed(c.p.seed, req.id);
        req.shaper = pl.shaper;
        req.command = shaped;
        req.record_s = c.p.record_s;
        requests.push_back(std::move(req));
      }
      plan.push_back(std::move(pl));
    }
  }
  const std::vector<Record> records = c.run_all(requests, "rig-tests");

  std::map<std::string, std::map<std::string, std::vector<double>>> md;  // table → column → MD
  std::map<std::string, json> table_json;
  for (const auto& table : rt.tables) {
    const InputSpec& in = c.p.input(table.input);
    json t = make_table(table.id, "mean-deviation", table.title, md_unit);
    json rows = json::array();
    for (int r = 1; r <= c.p.repetitions; ++r) rows.push_back(std::to_string(r));
    t["row_labels"] = rows;
    json cols = json::array();
    json headline = json::object();
    double without_mean = std::numeric_limits<double>::quiet_NaN();
    std::optional<double> thesis_without;
    // Figure data: trial 1 of every column (command, link rate, MD signal).
    std::vector<std::string> names{"time_s"};
    std::vector<std::vector<double>> fig;
    json fig_series = json::array(), cmd_series = json::array(), annotations = json::object();
    std::map<std::string, int> start_rules;  // rule → number of trials it decided
    for (const auto& pl : plan) {
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
      md[table.id][pl.column->key()] = values;
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
        thesis_without = pl.column->thesis.mean;
      } else {
        const auto ours = improvement(without_mean, ms.mean);
        std::optional<double> thesis;
        if (thesis_without && pl.column->thesis.mean) thesis = improvement(*thesis_without, *pl.column->thesis.mean);
        col["improvement_percent"] = opt(ours);
        col["thesis_improvement_percent"] = opt(thesis);
        headline[pl.column->key()] = {{"ours_mean", ms.mean}, {"thesis_mean", opt(pl.column->thesis.mean)},
                                      {"improvement_percent", opt(ours)}, {"thesis_improvement_percent", opt(thesis)}};
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
                            "for {:g} s (start rule per trial: {}). Trials on the simulated rig; shaped columns are "
                            "predictions, not fitted.",
                            c.p.measure.md_signal == MdSignal::link_angle_deg ? "link angle (gyro integrated)"
                                                                              : "link rate (gyro)",
                            md_unit, in.last_move_start_s, 100.0 * metrics::MeanDeviationOptions{}.band_move_fraction,
                            metrics::MeanDeviationOptions{}.band_dwell_s, decided);
    table_json[table.id] = t;
    c.tables.push_back(t);

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
    if (&table == &rt.tables.front()) {
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
      for (const auto& pl : plan) {
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

  for (const auto& s : rt.summaries) {
    if (s.kind == "combine") {
      json t = make_table(s.id, "mean-deviation", s.title, md_unit);
      t["row_labels"] = table_json.at(s.tables.front())["row_labels"];
      json cols = json::array();
      for (const auto& id : s.tables) {
        for (auto col : table_json.at(id)["columns"]) {
          col["key"] = fmt::format("{}:{}", id, col["key"].get<std::string>());
          col["label"] = fmt::format("{} — {}", c.p.input(c.p.table(id).input).label, col["label"].get<std::string>());
          cols.push_back(col);
        }
      }
      t["columns"] = cols;
      t["note"] = fmt::format("The same trials as Tables {} (the thesis prints them twice).", fmt::format("{}", s.tables.front()) +
                                                                                                   (s.tables.size() > 1 ? " and " + s.tables.back() : ""));
      c.tables.push_back(t);
    } else {
      json t = make_table(s.id, "improvement", s.title, "%");
      json rows = json::array();
      std::vector<json> ours, thesis;
      for (std::size_t i = 0; i < s.tables.size(); ++i) {
        const auto& id = s.tables[i];
        rows.push_back(c.p.input(c.p.table(id).input).label);
        const MeanStd w = mean_std(md[id]["none"]);
        const MeanStd v = mean_std(md[id][s.column]);
        ours.push_back(opt(improvement(w.mean, v.mean)));
        thesis.push_back(i < s.thesis.size() ? json(s.thesis[i]) : json(nullptr));
      }
      t["row_labels"] = rows;
      t["columns"] = {{{"key", "improvement"}, {"label", fmt::format("improvement ({})", s.column)},
                       {"ours", ours}, {"thesis", thesis}}};
      t["headline"] = {{"ours", ours}, {"thesis", thesis}};
      t["note"] = "improvement = (without − with)/without · 100 (Appendix B), from the mean MDs.";
      c.tables.push_back(t);
      // Summary figure: means without/with shaping and improvements, ours beside the thesis's.
      json fig_rows = json::array();
      for (std::size_t i = 0; i < s.tables.size(); ++i) {
        const auto& id = s.tables[i];
        const RigTable& table = c.p.table(id);
        auto thesis_mean = [&](const std::string& key) -> json {
          for (const auto& col : table.columns) {
            if (col.key() == key && col.thesis.mean) return *col.thesis.mean;
          }
          return nullptr;
        };
        fig_rows.push_back({{"table", id},
                            {"label", c.p.input(table.input).label},
                            {"ours_without", mean_std(md[id]["none"]).mean},
                            {"thesis_without", thesis_mean("none")},
                            {"ours_with", mean_std(md[id][s.column]).mean},
                            {"thesis_with", thesis_mean(s.column)},
                            {"ours_improvement", ours[i]},
                            {"thesis_improvement", thesis[i]}});
      }
      c.figures.push_back({{"id", fmt::format("summary-{}", s.id)},
                           {"thesis_figure", nullptr},
                           {"thesis_table", s.id},
                           {"kind", "md-summary"},
                           {"title", fmt::format("{}: mean deviations without and with {} and the improvement, "
                                                 "clearshape beside the thesis", s.title, s.column)},
                           {"unit", md_unit},
                           {"rows", fig_rows}});
    }
  }
}

}  // namespace clearshape::study::detail
