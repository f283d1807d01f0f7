#pragma once
// Stage 6, the rig tests (internal), as plan → run → tabulate: the plan designs each column's
// shaper and lists its runs, Context::run_all obtains them from the run source, the tabulation
// turns them into Tables 5.1/B.1–B.5 and their figures, the summaries into Tables 5.2/B.6.
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "clearshape/shaping/shaper.hpp"
#include "context.hpp"

namespace clearshape::study::detail {

/// One table column: its shaper (nullopt: unshaped) and where its runs start in the requests.
struct PlannedColumn {
  const RigTable* table;
  const RigColumn* column;
  std::optional<shaping::Shaper> shaper;
  std::string note;
  std::size_t first = 0;
};

struct RigTestPlan {
  std::vector<PlannedColumn> columns;
  std::vector<RunRequest> requests;  ///< repetitions of each column, in column order
};

/// What the tables hold, for the summaries.
struct RigTestTables {
  std::map<std::string, std::map<std::string, std::vector<double>>> md;  ///< table → column → MDs
  std::map<std::string, json> table_json;                                ///< table → its JSON
};

inline std::string md_unit_of(const Context& c) {
  return c.p.measure.md_signal == MdSignal::link_angle_deg ? "deg" : "deg/s";
}

/// A rig table's improvement of `with` over `without` in percent; none when the unshaped MD is not
/// positive or the shaped one not finite.
std::optional<double> improvement(double without, double with);
/// An optional number as JSON (null when absent).
json opt(const std::optional<double>& v);

/// 95 % percentile bootstrap interval [lo, hi] of the improvement 100 (1 − mean(with)/mean(without))
/// of `groups` = {without, with} (minus that of {thesis without, thesis with} when four groups are
/// given: the interval of the difference ours − thesis). Each group is resampled with replacement on
/// its own (trials are not paired), kBootstrapResamples times, from an mt19937_64 seeded by `seed`;
/// null when a group has fewer than 2 trials or an unshaped resample mean is not positive.
inline constexpr int kBootstrapResamples = 4000;
json bootstrap_improvement_ci(const std::vector<const std::vector<double>*>& groups, std::uint64_t seed);

RigTestPlan plan_rig_tests(Context& c);
void tabulate_rig_table(Context& c, const RigTable& table, const RigTestPlan& plan, const std::vector<Record>& records,
                        RigTestTables& out);
void tabulate_rig_summaries(Context& c, RigTestTables& tables);

}  // namespace clearshape::study::detail
