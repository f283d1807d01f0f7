// A protocol as JSON (results.json "protocol", every run's sidecar) and its content hash.
#include <fmt/format.h>

#include "clearshape/study/protocol.hpp"

namespace clearshape::study {

using json = nlohmann::ordered_json;

namespace {

json optional_json(const std::optional<double>& v) { return v ? json(*v) : json(nullptr); }

json column_json(const ThesisColumn& c) {
  json j;
  j["label"] = c.label;
  j["values"] = c.values;
  j["mean"] = optional_json(c.mean);
  return j;
}

json inputs_json(const Protocol& p) {
  json inputs = json::array();
  for (const auto& in : p.inputs) {
    json i;
    i["name"] = in.name;
    i["label"] = in.label;
    for (const auto& [k, v] : in.parameters.items()) i[k] = v;
    i["last_move_start_s"] = in.last_move_start_s;
    inputs.push_back(i);
  }
  return inputs;
}

json consistency_json(const ConsistencyStage& s) {
  json cons;
  cons["table"] = s.table;
  cons["inputs"] = s.inputs;
  cons["signal"] = s.signal;
  json th = json::object();
  for (const auto& [k, v] : s.thesis) th[k] = column_json(v);
  cons["thesis"] = th;
  return cons;
}

json identification_json(const IdentificationStage& id) {
  return {{"structure", id.structure},
          {"inputs", id.inputs},
          {"speed_chain", id.speed_chain},
          {"thesis",
           {{"selected_input", id.thesis.selected_input},
            {"kp", id.thesis.kp},
            {"tz_s", id.thesis.tz_s},
            {"zeta", id.thesis.zeta},
            {"tw_s", id.thesis.tw_s},
            {"tp3_s", id.thesis.tp3_s}}}};
}

json link_mode_json(const LinkModeStage& s) {
  return {{"input", s.input},
          {"start", s.start},
          {"settle_after_move_s", s.settle_after_move_s},
          {"window_s", s.window_s},
          {"max_damping_ratio", s.max_damping_ratio}};
}

json clearance_json(const ClearanceStage& c) {
  json j = {{"input", c.input},
          {"exponent", c.exponent},
          {"link_inertia_kg_m2", c.link_inertia_kg_m2},
          {"play_deg", c.play_deg},
          {"stiffness_n_m_per_rad_pow_n", c.stiffness_n_m_per_rad_pow_n},
          {"damping_n_m_s_per_rad", c.damping_n_m_s_per_rad},
          {"fit", c.fit},
          {"filter_gyro", c.filter_gyro},
          {"window_s", c.window_s},
          {"max_evaluations", c.max_evaluations},
          {"thesis",
           {{"stiffness", optional_json(c.thesis_stiffness)}, {"damping", optional_json(c.thesis_damping)},
            {"agreement", optional_json(c.thesis_agreement)}}}};
  if (c.contact_law != "dashpot") {  // the default writes nothing: older results stay byte-identical
    j["contact_law"] = c.contact_law;
    j["restitution"] = c.restitution;
  }
  return j;
}

json simulation_json(const SimulationStage& s) {
  return {{"inputs", s.inputs}, {"shapers", s.shapers}, {"mode_sources", s.mode_sources}, {"record_s", s.record_s}};
}

json rig_table_json(const RigTable& t) {
  json tj;
  tj["id"] = t.id;
  tj["title"] = t.title;
  tj["input"] = t.input;
  json cols = json::array();
  for (const auto& col : t.columns) {
    cols.push_back({{"key", col.key()},
                    {"shaper", col.shaper},
                    {"mode_source", col.mode_source},
                    {"label", col.label},
                    {"thesis", column_json(col.thesis)}});
    if (col.thesis_improvement) cols.back()["thesis_improvement"] = *col.thesis_improvement;
  }
  tj["columns"] = cols;
  return tj;
}

json rig_tests_json(const RigTestStage& s) {
  json tables = json::array();
  for (const auto& t : s.tables) tables.push_back(rig_table_json(t));
  json sums = json::array();
  for (const auto& sum : s.summaries) {
    sums.push_back({{"id", sum.id},
                    {"title", sum.title},
                    {"kind", sum.kind},
                    {"tables", sum.tables},
                    {"column", sum.column},
                    {"thesis", sum.thesis}});
  }
  json out = {{"tables", tables}, {"summaries", sums}};
  // Written only when set, so that the hash (and the finished runs) of a protocol without rest
  // trials stay what they were before the key existed.
  if (s.floor_trials > 0) out["floor_trials"] = s.floor_trials;
  return out;
}

}  // namespace

json to_json(const Protocol& p) {
  json j;
  j["format"] = kProtocolFormat;
  j["source"] = p.source.filename().string();
  j["name"] = p.name;
  j["title"] = p.title;
  j["mode"] = rig::to_string(p.mode);
  j["command_unit"] = p.command_unit();
  j["seed"] = p.seed;
  j["sample_rate_hz"] = p.sample_rate_hz;
  j["record_s"] = p.record_s;
  j["repetitions"] = p.repetitions;
  if (p.rig != "thesis") j["rig"] = p.rig;  // absent for the default (older hashes unchanged)
  j["quick"] = p.quick;
  j["measure"] = {{"md_signal", to_string(p.measure.md_signal)},
                  {"bias_window_s", p.measure.bias_window_s},
                  {"md_final_window_fraction", p.measure.md_final_window_fraction}};
  j["shaping"] = {{"grid_hz", p.shaping.grid_hz},
                  {"clearance_aware_max_duration_s", p.shaping.clearance_aware_max_duration_s},
                  {"clearance_aware_max_evaluations", p.shaping.clearance_aware_max_evaluations}};
  j["inputs"] = inputs_json(p);
  j["consistency"] = consistency_json(p.consistency);
  j["identification"] = identification_json(p.identification);
  j["link_mode"] = link_mode_json(p.link_mode);
  j["clearance"] = clearance_json(p.clearance);
  j["simulation"] = simulation_json(p.simulation);
  j["rig_tests"] = rig_tests_json(p.rig_tests);
  return j;
}

std::string protocol_hash(const Protocol& protocol, std::string_view rig_description) {
  // FNV-1a 64 (Fowler, Noll, Vo): a stable content hash, not a cryptographic one.
  std::uint64_t h = 0xcbf29ce484222325ULL;
  auto feed = [&h](std::string_view s) {
    for (const unsigned char ch : s) {
      h ^= ch;
      h *= 0x100000001b3ULL;
    }
  };
  json j = to_json(protocol);
  j.erase("source");
  feed(j.dump());
  feed("\n");
  feed(rig_description);
  return fmt::format("{:016x}", h);
}

}  // namespace clearshape::study
