// Stage 1: repeatability (thesis Eq. 4.1, Tables 4.1/4.2): the unshaped runs of each input, their
// encoder signals, Eq. 4.1 per run and the figures of every run (Figs. 4.2–4.5, 4.7–4.8).
#include <fmt/format.h>

#include "clearshape/core/error.hpp"
#include "clearshape/metrics/consistency.hpp"
#include "identification.hpp"

namespace clearshape::study::detail {

namespace {

json column(const std::string& key, const std::string& label, const std::vector<double>& ours,
            const ThesisColumn* thesis) {
  json col;
  col["key"] = key;
  col["label"] = label;
  col["ours"] = ours;
  const MeanStd ms = mean_std(ours);
  col["ours_mean"] = ms.mean;
  col["ours_std"] = ms.std;
  if (thesis) {
    col["thesis"] = thesis->values;
    col["thesis_mean"] = thesis->mean ? json(*thesis->mean) : json(nullptr);
  } else {
    col["thesis"] = json::array();
    col["thesis_mean"] = nullptr;
  }
  return col;
}

// Run: the input's unshaped runs (from the run source) and Eq. 4.1 on their encoder signals.
ConsistencyInput measure_consistency(Context& c, const std::string& name) {
  ConsistencyInput out;
  out.name = name;
  out.runs = &c.unshaped_runs(name);
  for (const auto& r : *out.runs) out.signals.push_back(encoder_signal(c, r));
  try {
    const metrics::ConsistencyResult res = metrics::consistency_errors(out.signals);
    out.errors = res.errors;
  } catch (const InvalidArgument& e) {
    out.note = e.what();
  }
  return out;
}

std::string consistency_figure(const Context& c, const std::string& name) {
  if (!speed_mode(c)) return name.find("double") != std::string::npos ? "4.8" : "4.7";
  const std::string type(c.p.input(name).signal.type());
  return type == "step" ? "4.2" : type == "ramp" ? "4.3" : type == "sine" ? "4.4" : "4.5";
}

// Figure data: every run's encoder signal (data/consistency_<input>.csv).
void write_consistency_figure(Context& c, const ConsistencyInput& in) {
  std::vector<std::string> names{"time_s"};
  std::vector<const std::vector<double>*> data{&in.runs->front().time_s};
  for (std::size_t i = 0; i < in.signals.size(); ++i) {
    names.push_back(fmt::format("run{:02d}_{}", i + 1, speed_mode(c) ? "motor_speed_deg_s" : "motor_angle_deg"));
    data.push_back(&in.signals[i]);
  }
  const std::string file = fmt::format("consistency_{}.csv", in.name);
  write_data_csv(c, file, names, data);
  json series = json::array();
  for (std::size_t i = 1; i < names.size(); ++i) series.push_back({{"column", names[i]}, {"label", fmt::format("run {}", i)}});
  c.figures.push_back({{"id", fmt::format("consistency-{}", in.name)},
                       {"thesis_figure", consistency_figure(c, in.name)},
                       {"kind", "time-series"},
                       {"title", fmt::format("{} runs of the {} (encoder, {})", in.runs->size(),
                                             c.p.input(in.name).label, encoder_unit(c))},
                       {"file", c.data_file(file)},
                       {"x", {{"column", "time_s"}, {"label", "time (s)"}}},
                       {"y_label", speed_mode(c) ? "motor speed (deg/s)" : "motor angle (deg)"},
                       {"series", series}});
}

// What makes the simulated rig's runs differ, and where we differ from the thesis.
std::string consistency_note(const Context& c) {
  return std::string(
      "Eq. 4.1: E_i = RMS(m − t_i)/r over the record, m the mean of the runs, r its range. The "
      "simulated rig's runs differ only by what its truth models (rig/variation.hpp), drawn afresh "
      "for every run from the run's seed: ") +
      (speed_mode(c)
           ? "a scatter of the drive gain Kp, a start latency of the D/A updates (uniform, under one "
             "sample) and the D/A's offset (per run) and white output noise (per sample)"
           : "a scatter of the drive gain Kp (small: the servo's encoder loop holds the position) "
             "and the phase of the 30 Hz pulse-update clock relative to the command (a start "
             "latency drawn uniformly per run)") +
      ", besides the link's initial position in the play, the flank damping and the gyro noise, "
      "which the encoder does not see. Their sizes were calibrated (clearshape calibrate-rig, "
      "studies/sim-rig-truth.toml) so that the mean E of this table and the trials' spread of the "
      "unshaped Eq. 5.1 come near the thesis's. Where we differ: the thesis does not say what made "
      "its runs differ, so the per-input pattern is ours only as far as these mechanisms reproduce "
      "it, and the encoder's 0.03° counts make a small variation read as whole-count flips." +
      std::string(speed_mode(c)
                      ? ""
                      : " The thesis's double step repeats 20 times worse than its step; none of the "
                        "modelled causes singles out a second move, so ours stays near the step's.");
}

}  // namespace

void stage_consistency(Context& c) {
  const auto& cs = c.p.consistency;
  if (cs.inputs.empty()) {
    c.log("consistency: no inputs in the protocol, skipped");
    return;
  }
  json table = make_table(cs.table, "consistency",
                          fmt::format("Eq. 4.1 error of each of {} repeated runs ({})", c.p.repetitions,
                                      speed_mode(c) ? "encoder speed through the §3.3 chain" : "encoder angle"),
                          "dimensionless");
  json rows = json::array();
  for (int r = 1; r <= c.p.repetitions; ++r) rows.push_back(std::to_string(r));
  table["row_labels"] = rows;
  json cols = json::array();
  json headline = json::object();
  for (const auto& name : cs.inputs) {
    const ConsistencyInput in = measure_consistency(c, name);
    const auto th = cs.thesis.find(name);
    json col = column(name, c.p.input(name).label, in.errors, th == cs.thesis.end() ? nullptr : &th->second);
    if (!in.note.empty()) col["note"] = in.note;
    headline[name] = {{"ours_mean", col["ours_mean"]}, {"thesis_mean", col["thesis_mean"]}};
    cols.push_back(col);
    write_consistency_figure(c, in);
  }
  table["columns"] = cols;
  table["headline"] = headline;
  table["note"] = consistency_note(c);
  c.tables.push_back(table);
}

}  // namespace clearshape::study::detail
