// Stage 6, the summaries (thesis Table 5.2, B.6): the rig tables side by side and the mean
// improvements per table, from the MDs stage_rig_tests tabulated.
#include <algorithm>
#include <cmath>
#include <random>

#include <fmt/format.h>

#include "clearshape/metrics/improvement.hpp"
#include "clearshape/study/measures.hpp"
#include "context.hpp"
#include "rig_tests.hpp"

namespace clearshape::study::detail {

std::optional<double> improvement(double without, double with) {
  if (!(without > 0.0) || !std::isfinite(with)) return std::nullopt;
  return metrics::improvement_percent(without, with);
}

json opt(const std::optional<double>& v) { return v ? json(*v) : json(nullptr); }

json bootstrap_improvement_ci(const std::vector<const std::vector<double>*>& groups, std::uint64_t seed) {
  if (groups.size() != 2 && groups.size() != 4) return nullptr;
  for (const auto* g : groups) {
    if (g == nullptr || g->size() < 2) return nullptr;
  }
  std::mt19937_64 rng(seed);
  std::vector<double> stats;
  stats.reserve(kBootstrapResamples);
  std::vector<double> means(groups.size());
  for (int b = 0; b < kBootstrapResamples; ++b) {
    for (std::size_t k = 0; k < groups.size(); ++k) {
      const auto& g = *groups[k];
      double sum = 0.0;
      for (std::size_t i = 0; i < g.size(); ++i) {
        sum += g[static_cast<std::size_t>(((rng() >> 32) * g.size()) >> 32)];  // uniform index, portable
      }
      means[k] = sum / static_cast<double>(g.size());
    }
    if (!(means[0] > 0.0) || (groups.size() == 4 && !(means[2] > 0.0))) return nullptr;
    double stat = 100.0 * (1.0 - means[1] / means[0]);
    if (groups.size() == 4) stat -= 100.0 * (1.0 - means[3] / means[2]);
    stats.push_back(stat);
  }
  std::sort(stats.begin(), stats.end());
  const auto quantile = [&stats](double q) {
    const double pos = q * static_cast<double>(stats.size() - 1);
    const auto i = static_cast<std::size_t>(pos);
    const double f = pos - static_cast<double>(i);
    return i + 1 < stats.size() ? stats[i] * (1.0 - f) + stats[i + 1] * f : stats[i];
  };
  return json::array({quantile(0.025), quantile(0.975)});
}

void tabulate_rig_summaries(Context& c, RigTestTables& tables) {
  const std::string md_unit = md_unit_of(c);
for (const auto& s : c.p.rig_tests.summaries) {
  if (s.kind == "combine") {
    json t = make_table(s.id, "mean-deviation", s.title, md_unit);
    t["row_labels"] = tables.table_json.at(s.tables.front())["row_labels"];
    json cols = json::array();
    for (const auto& id : s.tables) {
      for (auto col : tables.table_json.at(id)["columns"]) {
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
    std::vector<json> ours, thesis, ci, significant;
    for (std::size_t i = 0; i < s.tables.size(); ++i) {
      const auto& id = s.tables[i];
      rows.push_back(c.p.input(c.p.table(id).input).label);
      const MeanStd w = mean_std(tables.md[id]["none"]);
      const MeanStd v = mean_std(tables.md[id][s.column]);
      ours.push_back(opt(improvement(w.mean, v.mean)));
      thesis.push_back(i < s.thesis.size() ? json(s.thesis[i]) : json(nullptr));
      // The trial table's own interval (same trials, same seed): B.6 repeats B.1–B.5's improvements.
      const json& col = *std::find_if(tables.table_json.at(id)["columns"].begin(), tables.table_json.at(id)["columns"].end(),
                                      [&](const json& x) { return x.at("key") == s.column; });
      ci.push_back(col.value("improvement_ci95_percent", json(nullptr)));
      significant.push_back(col.value("improvement_significant", json(nullptr)));
    }
    t["row_labels"] = rows;
    t["columns"] = {{{"key", "improvement"}, {"label", fmt::format("improvement ({})", s.column)},
                     {"ours", ours}, {"thesis", thesis}, {"improvement_ci95_percent", ci},
                     {"improvement_significant", significant}}};
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
                          {"role", s.column.substr(0, s.column.find('@'))},  // the bars' colour: the shaper's
                          {"ours_without", mean_std(tables.md[id]["none"]).mean},
                          {"thesis_without", thesis_mean("none")},
                          {"ours_with", mean_std(tables.md[id][s.column]).mean},
                          {"thesis_with", thesis_mean(s.column)},
                          {"ours_improvement", ours[i]},
                          {"ours_improvement_ci95", ci[i]},
                          {"thesis_improvement", thesis[i]}});
    }
    c.figures.push_back({{"id", fmt::format("summary-{}", s.id)},
                         {"thesis_figure", nullptr},
                         {"thesis_table", s.id},
                         {"kind", "md-summary"},
                         // Each quantity in its own unit: the table's title ends in its "%", which stood over
                         // the mean deviations' degrees (issue 22, item 10).
                         {"title", fmt::format("Table {}'s inputs: Eq. 5.1 mean deviation ({}) without and with {} "
                                               "and the improvement (%), clearshape beside the thesis",
                                               s.id, md_unit, s.column)},
                         {"unit", md_unit},
                         {"rows", fig_rows}});
  }
}
}

}  // namespace clearshape::study::detail
