// The settled ambiguities and tables.md (human tables with the thesis beside ours).
#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>

#include <fmt/format.h>

#include "clearshape/metrics/mean_deviation.hpp"
#include "clearshape/rig/types.hpp"
#include "context.hpp"

namespace clearshape::study::detail {

namespace {

// One settled ambiguity: the question, how the study settles it, and why.
struct Ambiguities {
  json list = json::array();
  void add(const char* id, const char* question, std::string settled, const char* why) {
    list.push_back({{"id", id}, {"question", question}, {"settled", std::move(settled)}, {"why", why}});
  }
};

// What Eq. 5.1 is computed on, and from where.
void add_measure_ambiguities(Ambiguities& a, bool position) {
  a.add("md-signal", "On which signal is the mean deviation (Eq. 5.1) computed?",
        position ? "Position mode: on the link angle in degrees, the gyro rate integrated after its bias "
                   "(mean at rest before the move) is removed."
                 : "Speed mode: on the link rate in deg/s from the gyroscope.",
        "The thesis does not say. Position mode: Fig. 5.19 plots the link's angular position, the "
        "unshaped MDs grow in proportion to the step (0.085, 0.141, 0.303 deg for 5, 10, 20 deg), and "
        "the shaped MDs (0.007–0.073) lie below the gyro's rate-noise floor (about 0.1–0.2 deg/s) but "
        "above the integrated-angle floor. Speed mode: the controlled quantity is a speed and the "
        "angle has no steady state.");
  a.add("md-start", "Where does the steady state of Eq. 5.1 begin?",
        fmt::format("At the first sample, after the start of the input's last move, where the response meets "
                    "its own steady-state mean: it crosses M, or it enters a band of ±{:g} % of the last move "
                    "around M and stays inside for {:g} s, whichever comes first; M and the start are iterated "
                    "to a fixed point (metrics/mean_deviation.hpp). Every trial records which rule decided "
                    "(start_rule in the rig tables of results.json).",
                    100.0 * metrics::MeanDeviationOptions{}.band_move_fraction,
                    metrics::MeanDeviationOptions{}.band_dwell_s),
        "§5.1.2: 'the first coincide point of the system response and the mean data is taken as a start "
        "point'. A ringing response crosses its mean on its first swing; a well-shaped one approaches "
        "from one side and, on the smooth integrated gyro angle, may cross only when the gyro's drift "
        "carries it over M seconds later, leaving Eq. 5.1 a fraction of a second of record — so "
        "'coincide' is read as agreement within a small share of the move, the order of a settling tolerance.");
}

// Which mode the shapers are designed for, what the identification sees, units, the gyro filter.
void add_model_ambiguities(Ambiguities& a, bool position) {
  a.add("which-mode", "Which mode are the shapers designed for?",
        "Both, side by side: the drive model's ωn = 1/Tw, ζ = Zeta (the thesis's choice, §3.3) and the "
        "link's residual mode identified from the gyro's free response (docs/design.md §2). The tables name "
        "the source of every shaped column.",
        "The position-mode drive model has ζ = 0.9968: its ZV-family shapers collapse to one impulse and "
        "cannot give the published improvement; the vibration that matters is the link's.");
  a.add("identification-data", "What are the identification input and output?",
        position ? "Input: the position the driver received (the 30 Hz pulse train — a ramp for a step, "
                   "§4.1.2), output: the encoder angle."
                 : "Input: the D/A output (V), output: the encoder angle differentiated and filtered by the "
                   "4th-order 30 rad/s Butterworth (§3.3), causal as a real-time chain; the filter is part "
                   "of the identified model (§4.2).",
        "The thesis identified 'angular position input and angular position output' (position) and "
        "notes that the speed-mode model includes the low-pass filter.");
  a.add("model-selection", "How is the best model chosen?",
        "Each input's model is simulated on every input's record (fit %, zero initial state); the model "
        "with the best mean fit on the other records is selected.",
        "§4.2: every identified transfer function is tested on every input; the thesis selected the step model.");
  a.add("contact-units", "In which units are the contact parameters?",
        "Torsional play: K in N·m/rad^n, D in N·m·s/rad, δ in rad; the model's link inertia is fixed "
        "(only K/J and D/J are identifiable from the gyro).",
        "The thesis gives K and D without units (docs/design.md §2).");
  a.add("gyro-filter", "Which digital low-pass did the thesis's gyroscope use?",
        "The clearance fit compares the model's link rate through each ITG-3205 DLPF setting (none, "
        "256 … 5 Hz, first order) with the mean gyro record and keeps the setting that fits best "
        "(gyro_low_pass_hz in results.json).",
        "The thesis names the ITG-3205 but not its DLPF_CFG; left out, the filter's lag alone costs "
        "more Eq. 4.1 agreement than the whole published figure (0.0042 position).");
  a.add("input-timing", "What exactly were the inputs?",
        position ? "Moves start at 0.5 s (after a rest window for the gyro bias); a step is a ramp over one "
                   "30 Hz pulse update, the 56 deg 'low jerk' step a ramp over 0.1 s (three updates), and "
                   "the '16 deg double step' is read as two steps of 16 deg 0.5 s apart."
                 : "The speed-mode inputs' amplitudes (in V) and timing are in the protocol and are ours.",
        "The thesis gives the experimental amplitudes (Appendix B) but not the timing, the rise of the "
        "low-jerk step or the spacing and size of the double step.");
}

// What each kind of rig is (results.json "rig", the rig-truth ambiguity, the report's rig texts).
struct RigProfile {
  std::string_view kind;
  bool calibrated_to_thesis;
  bool scored_against_thesis;
  std::string_view summary;
  std::optional<double> contact_exponent;  ///< documented joint of a built-in what-if rig
  std::optional<double> play_deg;
};

constexpr std::string_view kUnknownSimulated =
    "a built-in simulated rig that is not the thesis's: its truth is not calibrated to the thesis's "
    "measurements, so the thesis's numbers beside ours are for scale only.";

const RigProfile* rig_profile(std::string_view kind) {
  static const RigProfile profiles[] = {
      {"simulated-thesis", true, true,
       "clearshape's simulated thesis rig: its hidden play, soft linear flank, damping and gyro noise were "
       "calibrated once (clearshape calibrate-rig) so that its unshaped responses reproduce the thesis's unshaped "
       "('without IS') means of Tables B.1–B.5, the spread of its trials and the repeatability of Tables 4.1–4.2; "
       "shaped results were never fitted and are predictions.",
       std::nullopt, std::nullopt},
      {"simulated-large-play", false, false,
       "the simulated large-play rig (docs/large-play.md): the calibrated thesis rig's drive, sensors and "
       "run-to-run variation with a 1° steel pin in a bored aluminium link — Hertz stiffness from the materials "
       "and geometry (n = 1.5), Flores restitution dissipation (e = 0.6), bearing friction. It is not fitted to "
       "any measurement, so the thesis's numbers beside ours are for scale only.",
       1.5, 1.0},
      {"simulated-worn-coupling", false, false,
       "the simulated worn-coupling rig: the thesis rig's drive and sensors with 1° of play on the calibrated "
       "soft linear flank (n = 1) and a 0.01 N·m bearing Coulomb torque. Only its flank comes from the thesis "
       "rig's calibration; the play and the friction do not, so its numbers are not calibrated to the thesis's "
       "and are shown beside them for scale only.",
       1.0, 1.0},
      {"simulated-config", false, false,
       "a simulated rig whose hidden truth comes from the rig configuration file given to --rig-config (named "
       "with its hash in the description): not calibrated to the thesis, so the thesis's numbers beside ours are "
       "for scale only.",
       std::nullopt, std::nullopt},
      {"physical", false, true,
       "a physical rig over its serial link (rig::SerialRig): every run, shaped or not, is a measurement of that "
       "rig, compared with the thesis's as a repetition of its experiment on another rig.",
       std::nullopt, std::nullopt},
      {"recordings", false, true,
       "runs recorded elsewhere (the recordings manifest): every run is a measurement of the rig that recorded "
       "it, compared with the thesis's as a repetition of its experiment on another rig.",
       std::nullopt, std::nullopt},
  };
  for (const auto& p : profiles) {
    if (p.kind == kind) return &p;
  }
  return nullptr;
}

std::string rig_summary(std::string_view kind) {
  const RigProfile* p = rig_profile(kind);
  return std::string(p ? p->summary : kUnknownSimulated);
}

// What rig gave the runs (RunSource::kind).
void add_rig_ambiguity(Ambiguities& a, std::string_view rig_kind) {
  const RigProfile* p = rig_profile(rig_kind);
  const bool measured = p != nullptr && p->scored_against_thesis && !p->calibrated_to_thesis;
  std::string settled = "The rig is " + rig_summary(rig_kind);
  settled += measured ? " Only the simulated tests (stage 5) are predictions of the identified model."
                      : " The study never reads the rig's truth.";
  a.add("rig-truth", measured ? "What rig gave the runs?" : "What is the simulated rig?", std::move(settled),
        p != nullptr && p->calibrated_to_thesis
            ? "docs/design.md §2: the simulated rig's truth is calibrated to the thesis's unshaped measurements, "
              "never to our results or to a shaped trial."
            : "The rig is not the thesis's: its numbers are compared with the thesis's, never fitted to them.");
}

}  // namespace

json ambiguities(const Protocol& p, std::string_view rig_kind) {
  const bool position = p.mode == rig::CommandMode::position;
  Ambiguities a;
  add_measure_ambiguities(a, position);
  add_model_ambiguities(a, position);
  add_rig_ambiguity(a, rig_kind);
  return a.list;
}

json rig_document(std::string_view kind, std::string_view description) {
  const RigProfile* p = rig_profile(kind);
  json doc = {{"kind", kind},
              {"description", description},
              {"summary", rig_summary(kind)},
              {"calibrated_to_thesis", p != nullptr && p->calibrated_to_thesis},
              {"scored_against_thesis", p != nullptr && p->scored_against_thesis}};
  if (p != nullptr && (p->contact_exponent || p->play_deg)) {
    doc["documented"] = {{"contact_exponent", p->contact_exponent ? json(*p->contact_exponent) : json(nullptr)},
                         {"play_deg", p->play_deg ? json(*p->play_deg) : json(nullptr)}};
  }
  return doc;
}

namespace {

// Fewest decimals (0 … 8) with which `v` prints back as itself.
int decimals_of(double v) {
  for (int d = 0; d < 8; ++d) {
    if (std::abs(std::stod(fmt::format("{:.{}f}", v, d)) - v) <= 1e-9 * std::max(1.0, std::abs(v))) return d;
  }
  return 8;
}

std::string superscript(int e) {
  static const char* digits[] = {"⁰", "¹", "²", "³", "⁴", "⁵", "⁶", "⁷", "⁸", "⁹"};
  std::string out = e < 0 ? "⁻" : "";
  for (const char ch : std::to_string(std::abs(e))) out += digits[ch - '0'];
  return out;
}

// A thesis column as printed: `uniform` (a column of trials and its mean) keeps one number of
// decimals for all; numbers all below 10⁻³ are printed m×10ⁿ with the largest one's exponent.
std::vector<std::string> printed(const std::vector<double>& v, bool uniform) {
  std::vector<std::string> out;
  if (v.empty()) return out;
  double top = 0.0;
  for (const double x : v) top = std::max(top, std::abs(x));
  if (top > 0.0 && top < 1e-3) {
    const int e = static_cast<int>(std::floor(std::log10(top)));
    const double scale = std::pow(10.0, e);
    for (const double x : v) {
      const double m = x / scale;
      out.push_back(fmt::format("{:.{}f}×10{}", m, decimals_of(m), superscript(e)));
    }
    return out;
  }
  int common = 0;
  for (const double x : v) common = std::max(common, decimals_of(x));
  for (const double x : v) out.push_back(fmt::format("{:.{}f}", x, uniform ? common : decimals_of(x)));
  return out;
}

}  // namespace

void add_thesis_printed(json& tables) {
  for (auto& t : tables) {
    const std::string kind = t.value("kind", std::string());
    const bool uniform = kind == "consistency" || kind == "mean-deviation" || kind == "improvement";
    for (auto& col : t["columns"]) {
      if (!col.contains("thesis") || !col["thesis"].is_array()) continue;
      std::vector<double> values;  // the column's numbers, then its mean: printed alike
      for (const auto& x : col["thesis"]) {
        if (x.is_number()) values.push_back(x.get<double>());
      }
      const bool has_mean = col.contains("thesis_mean") && col["thesis_mean"].is_number();
      if (has_mean) values.push_back(col["thesis_mean"].get<double>());
      if (values.empty()) continue;
      const std::vector<std::string> text = printed(values, uniform);
      json arr = json::array();
      std::size_t k = 0;
      for (const auto& x : col["thesis"]) arr.push_back(x.is_number() ? json(text[k++]) : json(nullptr));
      col["thesis_printed"] = arr;
      if (has_mean) col["thesis_mean_printed"] = text[k];
      if (col.contains("thesis_improvement_percent") && col["thesis_improvement_percent"].is_number()) {
        col["thesis_improvement_printed"] = printed({col["thesis_improvement_percent"].get<double>()}, false)[0];
      }
    }
  }
}

namespace {

std::string num(const json& v) {
  if (v.is_null()) return "—";  // missing is missing, never 0
  if (!v.is_number()) return v.is_string() ? v.get<std::string>() : v.dump();
  const double x = v.get<double>();
  if (!std::isfinite(x)) return "—";
  if (std::abs(x) < 1e-12) return "0";  // rounding noise of an exact zero
  const double ax = std::abs(x);
  if (ax >= 1e4 || ax < 1e-3) return fmt::format("{:.3e}", x);
  return fmt::format("{:.4g}", x);
}

// A column with at least one value: a column of nulls (a thesis column where the thesis gives
// nothing) is left out rather than printed as a column of dashes.
bool has_values(const json& col, const char* key) {
  if (!col.contains(key) || !col.at(key).is_array()) return false;
  const json& v = col.at(key);
  // In memory a missing number may still be NaN (written as null): neither counts as a value.
  return std::any_of(v.begin(), v.end(),
                     [](const json& x) { return !x.is_null() && !(x.is_number() && !std::isfinite(x.get<double>())); });
}

// An improvement % to one decimal, as the thesis prints them (a printed thesis string as it is).
std::string percent(const json& v) { return v.is_number() ? fmt::format("{:.1f}", v.get<double>()) : num(v); }

// The mark of a result worse than unshaped (a negative improvement, a shaped MD above the unshaped).
constexpr const char* kWorseMark = "▼ worse than unshaped";

// " [lo, hi]" of a 95 % bootstrap interval (per row of a summary when `row` is given), with
// "not significant" when it contains 0.
std::string interval(const json& ci, std::optional<std::size_t> row) {
  const json* c = &ci;
  if (row && ci.is_array() && *row < ci.size()) c = &ci[*row];
  if (!c->is_array() || c->size() != 2 || !(*c)[0].is_number() || !(*c)[1].is_number()) return "";
  const double lo = (*c)[0].get<double>(), hi = (*c)[1].get<double>();
  return fmt::format(" [{:.1f}, {:.1f}]{}", lo, hi, lo <= 0.0 && hi >= 0.0 ? " not significant" : "");
}

void row(std::ostringstream& out, const std::vector<std::string>& cells) {
  out << "|";
  for (const auto& c : cells) out << " " << c << " |";
  out << "\n";
}

// One printed column of a table: a table column's "ours" or "thesis" values.
struct Cell {
  const json* col;
  const char* key;
};

// The printed columns of a table and their header (ours and thesis side by side).
struct TableLayout {
  std::vector<std::string> header{""};
  std::vector<Cell> cells;
};

// `mine_only`: every column is ours (no thesis beside it), so no "— ours" in the header.
TableLayout layout_of(const json& cols, bool mine_only) {
  TableLayout l;
  for (const auto& col : cols) {
    const std::string label = col.value("label", col.value("key", std::string()));
    if (has_values(col, "ours")) {
      l.header.push_back(!mine_only && (cols.size() > 1 || has_values(col, "thesis")) ? label + " — ours" : label);
      l.cells.push_back({&col, "ours"});
    }
    if (has_values(col, "thesis")) {
      l.header.push_back(label + " — thesis");
      l.cells.push_back({&col, "thesis"});
    }
  }
  return l;
}

// The mean row (and, for a table of trials, the std and improvement rows) under the values.
void render_summary_rows(std::ostringstream& out, const std::string& kind, const json& rows, const TableLayout& l) {
  if (kind != "consistency" && kind != "mean-deviation") return;
  std::vector<std::string> mean{"**mean**"};
  std::vector<std::string> sd{"std (ours)"};
  std::vector<std::string> imp{"improvement %"};
  bool any_imp = false;
  std::vector<std::string> recomputed{"improvement % recomputed from the thesis's means"};
  bool any_recomputed = false;
  for (const auto& c : l.cells) {
    const bool ours = std::string(c.key) == "ours";
    const json mean_v = ours ? c.col->value("ours_mean", json(nullptr))
                             : c.col->value("thesis_mean_printed", c.col->value("thesis_mean", json(nullptr)));
    mean.push_back("**" + num(mean_v) + "**");
    sd.push_back(ours ? num(c.col->value("ours_std", json(nullptr))) : "");
    const char* ik = ours ? "improvement_percent" : "thesis_improvement_percent";
    if (c.col->contains(ik)) any_imp = true;
    const json iv = ours ? c.col->value(ik, json(nullptr))
                         : c.col->value("thesis_improvement_printed", c.col->value(ik, json(nullptr)));
    std::string cell = !c.col->contains(ik) ? "" : percent(iv);  // no improvement for the unshaped column
    if (iv.is_number() && iv.get<double>() < 0.0) cell += std::string(" ") + kWorseMark;
    if (ours) cell += interval(c.col->value("improvement_ci95_percent", json(nullptr)), std::nullopt);
    imp.push_back(cell);
    const json rv = ours ? json(nullptr) : c.col->value("thesis_improvement_recomputed_percent", json(nullptr));
    const json pv = c.col->value("thesis_improvement_percent", json(nullptr));  // the printed value
    if (rv.is_number() && (!pv.is_number() || std::abs(rv.get<double>() - pv.get<double>()) >= 0.05)) {
      any_recomputed = true;
      recomputed.push_back(fmt::format("{:.2f}", rv.get<double>()) +
                           (pv.is_number() ? fmt::format(" (printed {})", num(iv)) : " (not printed)"));
    } else {
      recomputed.push_back("");
    }
  }
  if (kind == "mean-deviation" && rows.size() > 0 && rows[0].is_string() && rows[0].get<std::string>() == "1") {
    row(out, mean);
    row(out, sd);
    if (any_imp) row(out, imp);
    if (any_recomputed) row(out, recomputed);
  } else if (kind == "consistency") {
    row(out, mean);
  }
}

// Each column's note, then where we differ: means and improvements next to the thesis's.
void render_column_notes(std::ostringstream& out, const json& cols) {
  for (const auto& col : cols) {
    if (col.contains("note")) {
      out << fmt::format("- {}: {}\n", col.value("label", std::string()), col.at("note").get<std::string>());
    }
  }
  for (const auto& col : cols) {
    const json om = col.value("ours_mean", json(nullptr));
    const json tm = col.value("thesis_mean", json(nullptr));
    if (om.is_number() && tm.is_number() && tm.get<double>() != 0.0) {
      const double o = om.get<double>(), th = tm.get<double>();
      out << fmt::format("- {}: ours {} vs thesis {} ({:+.0f} %).\n", col.value("label", std::string()), num(om),
                         num(col.value("thesis_mean_printed", tm)), 100.0 * (o - th) / std::abs(th));
    }
    const json oi = col.value("improvement_percent", json(nullptr));
    const json ti = col.value("thesis_improvement_printed", col.value("thesis_improvement_percent", json(nullptr)));
    if (oi.is_number()) {
      out << fmt::format("- {}: improvement ours {} %{}{} vs thesis {}.\n", col.value("label", std::string()), percent(oi),
                         interval(col.value("improvement_ci95_percent", json(nullptr)), std::nullopt),
                         oi.get<double>() < 0.0 ? std::string(" ") + kWorseMark : std::string(),
                         ti.is_null() ? std::string("— (not printed)") : num(ti) + " % (as printed)");
    }
  }
}

void render_table(std::ostringstream& out, const json& t) {
  out << fmt::format("### Table {} — {}\n\n", t.at("id").get<std::string>(), t.at("title").get<std::string>());
  const std::string unit = t.value("unit", std::string());
  if (!unit.empty()) out << fmt::format("Unit: {}.\n\n", unit);
  const json& cols = t.at("columns");
  const json rows = t.value("row_labels", json::array());
  const TableLayout l = layout_of(cols, t.value("kind", std::string()) == "reach");
  row(out, l.header);
  row(out, std::vector<std::string>(l.header.size(), "---"));
  const std::string kind = t.value("kind", std::string());
  const bool trials = kind == "mean-deviation" && !rows.empty() && rows[0] == "1";
  const json* unshaped = nullptr;  // a results table's unshaped column: a larger MD in its row is worse
  for (const auto& col : cols) {
    if (col.value("key", std::string()) == "none" && has_values(col, "ours")) unshaped = &col;
  }
  for (std::size_t r = 0; r < rows.size(); ++r) {
    std::vector<std::string> line{rows[r].is_string() ? rows[r].get<std::string>() : rows[r].dump()};
    for (const auto& c : l.cells) {
      const bool ours = std::string(c.key) == "ours";
      const json& v = c.col->at(!ours && c.col->contains("thesis_printed") ? "thesis_printed" : c.key);
      std::string cell = r < v.size() ? (ours && kind == "improvement" ? percent(v[r]) : num(v[r])) : "";
      if (ours && r < v.size() && v[r].is_number()) {
        const double x = v[r].get<double>();
        const bool worse = kind == "improvement" ? x < 0.0
                           : (!trials && kind == "mean-deviation" && unshaped != nullptr && unshaped != c.col &&
                              r < unshaped->at("ours").size() && unshaped->at("ours")[r].is_number() &&
                              x > unshaped->at("ours")[r].get<double>());
        if (worse) cell += std::string(" ") + kWorseMark;
        if (kind == "improvement") cell += interval(c.col->value("improvement_ci95_percent", json(nullptr)), r);
      }
      line.push_back(cell);
    }
    row(out, line);
  }
  render_summary_rows(out, t.value("kind", std::string()), rows, l);
  out << "\n";
  render_column_notes(out, cols);
  if (t.contains("note")) out << "\n" << t.at("note").get<std::string>() << "\n";
  out << "\n";
}

}  // namespace

std::string render_tables_markdown(const json& results) {
  std::ostringstream out;
  const json& s = results.at("study");
  out << fmt::format("# {} — tables\n\n", s.at("name").get<std::string>());
  out << fmt::format("{}. Mode: {}{}. Rig: {}. Protocol hash {}. Every table shows our numbers and, "
                     "where the thesis published them, the thesis's beside them.\n\n",
                     s.at("title").get<std::string>(), s.at("mode").get<std::string>(),
                     s.at("quick").get<bool>() ? " (quick variant: fewer repetitions, shorter records)" : "",
                     s.at("rig").get<std::string>(), s.at("protocol_hash").get<std::string>());
  if (results.contains("rig") && results.at("rig").contains("summary")) {
    out << fmt::format("The rig is {}\n\n", results.at("rig").at("summary").get<std::string>());
  }
  out << fmt::format("Thesis numbers are quoted as the thesis printed them; a value recomputed from them is labelled "
                     "so. \"{}\" marks a result worse than unshaped (a negative improvement, or a shaped mean "
                     "deviation above the unshaped one in its row); [lo, hi] after an improvement is its 95 % "
                     "bootstrap interval over the trials (seeded), \"not significant\" when it contains 0; \"—\" is a "
                     "missing value.\n\n", kWorseMark);
  out << "## Ambiguities settled\n\n";
  for (const auto& a : results.at("ambiguities")) {
    out << fmt::format("- **{}** {} — {}\n", a.at("question").get<std::string>(), a.at("settled").get<std::string>(),
                       a.at("why").get<std::string>());
  }
  out << "\n## Tables\n\n";
  for (const auto& t : results.at("tables")) render_table(out, t);
  return out.str();
}

}  // namespace clearshape::study::detail
