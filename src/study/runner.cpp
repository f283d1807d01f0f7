#include "clearshape/study/runner.hpp"

#include <algorithm>
#include <atomic>
#include <exception>
#include <memory>
#include <ostream>
#include <thread>

#include <fmt/format.h>

#include "clearshape/core/error.hpp"
#include "clearshape/core/parallel.hpp"
#include "clearshape/io/json.hpp"
#include "clearshape/io/atomic_file.hpp"
#include "clearshape/io/table.hpp"
#include "clearshape/rig/builtin_truths.hpp"
#include "clearshape/rig/sim_rig.hpp"
#include "clearshape/signal/signal.hpp"
#include "context.hpp"
#include "output_folder.hpp"

namespace clearshape::study {

using json = nlohmann::ordered_json;

namespace {

// FNV-1a over a value's bytes (Fowler–Noll–Vo): the fingerprint below only has to change when
// the rig's behaviour does.
void fnv1a(std::uint64_t& h, const void* data, std::size_t size) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < size; ++i) h = (h ^ p[i]) * 0x100000001b3ULL;
}

// A fingerprint of what a rig does, not of its hidden parameters: the measurements of a short
// seeded probe per mode (a step, a second run for the run-to-run draw). It enters the protocol
// hash through the rig description, so a study never resumes from runs of another rig.
std::string behaviour_fingerprint(const RigFactory& f) {
  std::uint64_t h = 0xcbf29ce484222325ULL;
  for (const rig::CommandMode mode : {rig::CommandMode::position, rig::CommandMode::speed}) {
    const auto r = f.make(mode, 1000.0, 7);
    if (r->configure() != Status::ok) throw RuntimeError("rig fingerprint: configure failed");
    for (int run = 0; run < 2; ++run) {
      if (r->activate() != Status::ok) throw RuntimeError("rig fingerprint: activate failed");
      rig::Measurement m;
      for (int k = 0; k < 300; ++k) {
        const double target = k >= 50 ? 1.0 : 0.0;
        (void)r->write(mode == rig::CommandMode::position ? rig::Command::position_deg(20.0 * target)
                                                          : rig::Command::speed_v(2.0 * target));
        if (r->read(m) != Status::ok) throw RuntimeError("rig fingerprint: read failed");
        fnv1a(h, &m.encoder_counts, sizeof m.encoder_counts);
        fnv1a(h, &m.gyro_raw, sizeof m.gyro_raw);
        fnv1a(h, &m.command_applied, sizeof m.command_applied);
      }
      (void)r->deactivate();
    }
  }
  return fmt::format("{:016x}", h);
}

}  // namespace

RigFactory sim_rig_factory() {
  RigFactory f;
  f.parallel_runs = 64;
  // SimRig's built-in truth is the calibrated thesis rig (rig/truth.hpp); nobody here reads it.
  f.make = [](rig::CommandMode mode, double rate_hz, std::uint64_t seed) -> std::unique_ptr<rig::Rig> {
    rig::SimRigOptions o;
    o.mode = mode;
    o.sample_rate_hz = rate_hz;
    o.seed = seed;
    return std::make_unique<rig::SimRig>(o);
  };
  f.description = "sim (rig::SimRig, calibrated thesis truth, behaviour " + behaviour_fingerprint(f) + ")";
  return f;
}

decltype(RigFactory::make) sim_rig_maker(std::shared_ptr<const rig::RigTruth> truth) {
  return [truth](rig::CommandMode mode, double rate_hz, std::uint64_t seed) -> std::unique_ptr<rig::Rig> {
    rig::SimRigOptions o;
    o.mode = mode;
    o.sample_rate_hz = rate_hz;
    o.seed = seed;
    return rig::make_sim_rig_with_truth(o, *truth);
  };
}

RigFactory sim_rig_factory(std::string_view truth_name) {
  if (truth_name == "thesis") return sim_rig_factory();
  auto truth = std::make_shared<const rig::RigTruth>(rig::builtin_truth(truth_name));
  RigFactory f;
  f.parallel_runs = 64;
  f.kind = "simulated-" + std::string(truth_name);
  f.make = sim_rig_maker(truth);
  f.description = fmt::format("sim (rig::SimRig, built-in {} truth, behaviour {})", truth_name,
                              behaviour_fingerprint(f));
  return f;
}

const json& StudyResult::table(std::string_view id) const {
  for (const auto& t : results.at("tables")) {
    if (t.at("id").get<std::string>() == id) return t;
  }
  throw InvalidArgument(fmt::format("the study has no table '{}'", id));
}

json StudyResult::summary() const {
  json s = io::make_document();
  s["study"] = results.at("study");
  json key = json::array();
  for (const auto& t : results.at("tables")) {
    json row;
    row["id"] = t.at("id");
    row["title"] = t.at("title");
    if (t.contains("headline")) row["headline"] = t.at("headline");
    key.push_back(row);
  }
  s["tables"] = key;
  json timing_json = json::array();
  for (const auto& t : timing) {
    timing_json.push_back({{"stage", t.stage}, {"seconds", t.seconds},
                           {"runs_executed", t.runs_executed}, {"runs_reused", t.runs_reused}});
  }
  s["timing"] = timing_json;
  return s;
}

namespace detail {

Context::Context(const Protocol& protocol, const StudyOptions& opts)
    : p(protocol),
      options(opts),
      source(opts.source ? opts.source : rig_run_source(opts.rig, protocol.mode, protocol.sample_rate_hz)),
      start(std::chrono::steady_clock::now()) {
  hash = protocol_hash(p, source->description());
  out = opts.out_dir;
  runs_dir = out / "runs";
  data_dir = out / "data";
  const int hw = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  threads = opts.threads > 0 ? opts.threads : std::min(std::max(1, source->parallel_runs()), hw);
}

void Context::log(const std::string& line) {
  if (!options.progress) return;
  const std::lock_guard<std::mutex> lock(progress_mutex);
  *options.progress << fmt::format("[{} {:7.1f} s] {}\n", p.name, elapsed_s(), line);
  options.progress->flush();
}

double Context::elapsed_s() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

StageTiming& Context::begin_stage(const std::string& name) {
  timing.push_back(StageTiming{name, 0.0, 0, 0});
  log(fmt::format("stage {}", name));
  return timing.back();
}

UniformSeries Context::command_of(const InputSpec& input, double record_s) const {
  return signal::sample(input.signal, p.sample_rate_hz, record_s);
}

namespace {

// Obtains the pending requests from the run source on `threads` workers (the caller is one),
// writing each run's record as it finishes. An error stops the runs after it; the one rethrown is
// the first failing run in request order (parallel_for), so it does not depend on thread timing.
void obtain_pending(Context& c, const std::vector<RunRequest>& requests, const std::vector<std::size_t>& pending,
                    std::vector<std::optional<Record>>& found, const std::string& stage) {
  io::create_folder(c.runs_dir);
  std::atomic<std::size_t> done{0};
  parallel_for(pending.size(), c.threads, [&](std::size_t j) {
    const RunRequest& req = requests[pending[j]];
    const auto t0 = std::chrono::steady_clock::now();
    ObtainedRun obtained = c.source->obtain(req);
    Record& rec = obtained.record;
    write_record(c.runs_dir, rec, req, c.hash, c.source->description(), obtained.counters);
    const double dt = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const std::size_t d = done.fetch_add(1) + 1;
    c.log(fmt::format("{}: {} done in {:.2f} s ({}/{})", stage, req.id, dt, d, pending.size()));
    found[pending[j]] = std::move(rec);
  });
}

}  // namespace

std::vector<Record> Context::run_all(const std::vector<RunRequest>& requests, const std::string& stage) {
  std::vector<std::optional<Record>> found(requests.size());
  std::vector<std::size_t> pending;
  for (std::size_t i = 0; i < requests.size(); ++i) {
    found[i] = options.fresh || !source->reuse_finished_runs() ? std::nullopt
                                                               : read_record(runs_dir, requests[i], p.mode, hash);
    if (!found[i]) pending.push_back(i);
  }
  const int reused = static_cast<int>(requests.size() - pending.size());
  if (!timing.empty()) {
    timing.back().runs_reused += reused;
    timing.back().runs_executed += static_cast<int>(pending.size());
  }
  if (reused > 0) log(fmt::format("{}: reused {} finished run(s) from {}", stage, reused, runs_dir.string()));
  if (!pending.empty()) obtain_pending(*this, requests, pending, found, stage);
  std::vector<Record> records;
  records.reserve(found.size());
  for (auto& r : found) records.push_back(std::move(*r));
  return records;
}

const std::vector<Record>& Context::unshaped_runs(const std::string& input) {
  const auto it = unshaped.find(input);
  if (it != unshaped.end()) return it->second;
  const InputSpec& in = p.input(input);
  const UniformSeries command = command_of(in, p.record_s);
  std::vector<RunRequest> requests;
  for (int r = 1; r <= p.repetitions; ++r) {
    RunRequest req;
    req.id = unshaped_run_id(input, r);
    req.stage = "unshaped";
    req.input = input;
    req.repetition = r;
    req.seed = run_seed(p.seed, req.id);
    req.command = command;
    req.record_s = p.record_s;
    requests.push_back(std::move(req));
  }
  return unshaped.emplace(input, run_all(requests, "unshaped")).first->second;
}

json make_table(const std::string& id, const std::string& kind, const std::string& title,
                const std::string& unit) {
  json t;
  t["id"] = id;
  t["kind"] = kind;
  t["title"] = title;
  t["unit"] = unit;
  return t;
}

bool skip_for_missing_runs(Context& c, const std::vector<StagePlan>& plan, const std::string& stage) {
  std::vector<std::string> missing;
  for (const auto& sp : plan) {
    if (sp.stage != stage) continue;
    for (const auto& run : sp.runs) {
      if (!c.source->has(run) && std::find(missing.begin(), missing.end(), run.id) == missing.end()) {
        missing.push_back(run.id);
      }
    }
  }
  if (missing.empty()) return false;
  std::string shown;
  for (std::size_t i = 0; i < missing.size() && i < 6; ++i) shown += (i ? ", " : "") + missing[i];
  if (missing.size() > 6) shown += fmt::format(", … ({} more)", missing.size() - 6);
  c.log(fmt::format("stage {} SKIPPED: {} run(s) missing from {}: {}", stage, missing.size(),
                    c.source->description(), shown));
  c.skipped.push_back({{"stage", stage},
                       {"reason", fmt::format("{} run(s) missing from the source", missing.size())},
                       {"missing_runs", missing}});
  return true;
}

void write_data_csv(const Context& c, const std::string& name, const std::vector<std::string>& columns,
                    const std::vector<const std::vector<double>*>& data) {
  io::write_csv(c.data_dir / name, columns, data);
  const std::lock_guard<std::mutex> lock(c.written_mutex);
  c.data_written.push_back(name);
}

}  // namespace detail

namespace {

// Plan → run → tabulate of every stage, in order, each timed; a stage that needs runs the source
// lacks is skipped (results.json "skipped_stages").
void run_stages(detail::Context& c, const Protocol& protocol) {
  using Stage = void (*)(detail::Context&);
  const std::pair<const char*, Stage> stages[] = {
      {"consistency", detail::stage_consistency},   {"identification", detail::stage_identification},
      {"link-mode", detail::stage_link_mode},       {"clearance", detail::stage_clearance},
      {"simulation", detail::stage_simulation},     {"rig-tests", detail::stage_rig_tests},
      {"measurement-floor", detail::stage_measurement_floor},
  };
  const std::vector<StagePlan> plan = plan_runs(protocol);
  for (const auto& [name, fn] : stages) {
    // A protocol without rest trials has no floor stage (its outputs stay as they were).
    if (std::string_view(name) == "measurement-floor" && protocol.rig_tests.floor_trials == 0) continue;
    const double t0 = c.elapsed_s();
    c.begin_stage(name);
    if (!detail::skip_for_missing_runs(c, plan, name)) fn(c);
    auto& st = c.timing.back();
    st.seconds = c.elapsed_s() - t0;
    c.log(fmt::format("stage {} finished in {:.1f} s ({} run(s) executed, {} reused)", name, st.seconds,
                      st.runs_executed, st.runs_reused));
  }
}

json units_json(const Protocol& protocol) {
  return {{"time", "s"},
          {"command", protocol.command_unit()},
          {"motor_angle", "deg"},
          {"motor_speed", "deg/s"},
          {"link_rate", "deg/s"},
          {"link_angle", "deg"},
          {"mean_deviation", protocol.measure.md_signal == MdSignal::link_angle_deg ? "deg" : "deg/s"},
          {"consistency_error", "dimensionless (Eq. 4.1)"},
          {"improvement", "%"},
          {"natural_frequency", "rad/s"},
          {"contact_stiffness", "N·m/rad^n"},
          {"contact_damping", "N·m·s/rad"}};
}

// results.json: the study, its rig and protocol, the stages' sections and tables.
json results_document(const detail::Context& c, const Protocol& protocol) {
  json doc = io::make_document();
  doc["results_schema_version"] = kResultsSchemaVersion;
  doc["study"] = {{"name", protocol.name},
                  {"title", protocol.title},
                  {"mode", rig::to_string(protocol.mode)},
                  {"quick", protocol.quick},
                  {"protocol_hash", c.hash},
                  {"seed", protocol.seed},
                  {"rig", c.source->description()}};
  doc["rig"] = detail::rig_document(c.source->kind(), c.source->description());
  doc["protocol"] = to_json(protocol);
  doc["units"] = units_json(protocol);
  doc["ambiguities"] = detail::ambiguities(protocol, c.source->kind());
  doc["skipped_stages"] = c.skipped;
  doc["sections"] = c.sections;
  doc["tables"] = c.tables;
  detail::add_thesis_printed(doc["tables"]);
  doc["figures_index"] = "figures.json";
  return doc;
}

// timing.json: seconds and runs per stage, their total, the parallel runs.
json timing_document(const detail::Context& c) {
  json timing = io::make_document();
  json stages_json = json::array();
  double total = 0.0;
  for (const auto& t : c.timing) {
    stages_json.push_back({{"stage", t.stage}, {"seconds", t.seconds},
                           {"runs_executed", t.runs_executed}, {"runs_reused", t.runs_reused}});
    total += t.seconds;
  }
  timing["stages"] = stages_json;
  timing["total_s"] = total;
  timing["parallel_runs"] = c.threads;
  return timing;
}

void write_study_outputs(detail::Context& c, const StudyResult& result) {
  io::write_json(c.out / "results.json", result.results);
  io::write_text_atomic(c.out / "tables.md", result.tables_markdown);
  io::write_json(c.out / "figures.json", result.figures);
  io::write_json(c.out / "timing.json", timing_document(c));
  detail::write_outputs_manifest(c.out, c.data_written);
  c.log(fmt::format("done in {:.1f} s: {}, {}, {}", c.elapsed_s(), (c.out / "results.json").string(),
                    (c.out / "tables.md").string(), (c.out / "figures.json").string()));
}

}  // namespace

StudyResult run_study(const Protocol& protocol, const StudyOptions& options) {
  if (!options.source && !options.rig.make) {
    throw InvalidArgument("StudyOptions.rig.make is empty; give a rig factory or a run source");
  }
  detail::Context c(protocol, options);
  detail::prepare_output_folder(c.out, options.fresh, [&c](const std::string& line) { c.log(line); });
  io::create_folder(c.data_dir);
  c.log(fmt::format("study '{}' ({} mode{}), protocol hash {}, rig {}, {} parallel run(s), out {}",
                    protocol.name, rig::to_string(protocol.mode), protocol.quick ? ", quick" : "",
                    c.hash, c.source->description(), c.threads, c.out.string()));
  run_stages(c, protocol);

  StudyResult result;
  result.results = results_document(c, protocol);
  result.tables_markdown = detail::render_tables_markdown(result.results);
  json figs = io::make_document();
  figs["study"] = protocol.name;
  figs["figures"] = c.figures;
  result.figures = figs;
  result.timing = c.timing;
  write_study_outputs(c, result);
  return result;
}

}  // namespace clearshape::study
