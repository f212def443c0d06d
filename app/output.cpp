// JSON (nlohmann) and CSV renderings; doubles are written so that they read back bit for bit.
#include "output.hpp"

#include "cli_common.hpp"
#include "funnel/version.hpp"

namespace funnel::cli {

namespace {

nlohmann::ordered_json summary_json(const Summary& s) {
  return {{"mean", s.mean}, {"std", s.std}, {"sem", s.sem}, {"min", s.min}, {"max", s.max}};
}

/// Statistics reported for an ensemble, in column order.
struct NamedSummary {
  const char* name;
  const Summary EnsembleResult::*member;
};
constexpr NamedSummary summaries[] = {
    {"duration", &EnsembleResult::duration},
    {"impulse", &EnsembleResult::impulse},
    {"normal_impulse", &EnsembleResult::normal_impulse},
    {"energy_loss", &EnsembleResult::energy_loss},
    {"collisions", &EnsembleResult::collisions},
    {"edge_collisions", &EnsembleResult::edge_collisions},
    {"contact_time", &EnsembleResult::contact_time},
};
constexpr const char* summary_fields[] = {"mean", "std", "sem", "min", "max"};

std::string wall_text(const std::optional<Wall>& w) { return w ? std::string(to_string(*w)) : "none"; }

}  // namespace

nlohmann::ordered_json params_json(const Params& p) {
  return {{"theta", p.theta},   {"e", p.e},           {"mu", p.mu},
          {"beta0", p.beta0},   {"radius", p.radius}, {"gap", p.gap},
          {"inertia", p.inertia}, {"t_max", p.t_max}, {"max_collisions", p.max_collisions},
          {"p_c", p.p_c},       {"eps_rest", p.eps_rest}};
}

nlohmann::ordered_json provenance_json(const std::string& command_line) {
  return {{"version", version()}, {"git_commit", git_commit()}, {"command", command_line}};
}

nlohmann::ordered_json trajectory_json(const Trajectory& t) {
  return {{"status", to_string(t.status)},
          {"duration", t.duration},
          {"impulse", t.impulse},
          {"normal_impulse", t.normal_impulse},
          {"energy_loss", t.energy_loss},
          {"collisions", t.collisions},
          {"edge_collisions", t.edge_collisions},
          {"face_collisions", t.collisions - t.edge_collisions},
          {"contacts", t.contacts},
          {"contact_time", t.contact_time}};
}

std::vector<std::string> event_columns() {
  return {"time", "kind", "wall", "x", "y", "u_before", "v_before", "omega_before", "u_after", "v_after",
          "omega_after", "slip_before", "regime", "j_n", "j_t", "energy_lost"};
}

std::vector<std::string> event_row(const Event& e) {
  return {number(e.time),
          std::string(to_string(e.kind)),
          wall_text(e.wall),
          number(e.position.x),
          number(e.position.y),
          number(e.velocity_before.x),
          number(e.velocity_before.y),
          number(e.omega_before),
          number(e.velocity_after.x),
          number(e.velocity_after.y),
          number(e.omega_after),
          number(e.slip_before),
          std::string(to_string(e.regime)),
          number(e.j_n),
          number(e.j_t),
          number(e.energy_lost)};
}

nlohmann::ordered_json event_json(const Event& e) {
  nlohmann::ordered_json j;
  j["time"] = e.time;
  j["kind"] = to_string(e.kind);
  j["wall"] = e.wall ? nlohmann::ordered_json(to_string(*e.wall)) : nlohmann::ordered_json(nullptr);
  j["x"] = e.position.x;
  j["y"] = e.position.y;
  j["u_before"] = e.velocity_before.x;
  j["v_before"] = e.velocity_before.y;
  j["omega_before"] = e.omega_before;
  j["u_after"] = e.velocity_after.x;
  j["v_after"] = e.velocity_after.y;
  j["omega_after"] = e.omega_after;
  j["slip_before"] = e.slip_before;
  j["regime"] = to_string(e.regime);
  j["j_n"] = e.j_n;
  j["j_t"] = e.j_t;
  j["energy_lost"] = e.energy_lost;
  return j;
}

nlohmann::ordered_json ensemble_json(const EnsembleResult& r) {
  nlohmann::ordered_json j;
  j["samples"] = r.samples;
  for (const auto& s : summaries) j[s.name] = summary_json(r.*(s.member));
  j["status_counts"] = {{"exited", r.exited}, {"rest", r.rest}, {"trapped", r.trapped}};
  j["total_collisions"] = r.total_collisions;
  return j;
}

std::vector<std::string> param_columns() {
  return {"theta", "e", "mu", "beta0", "radius", "gap", "inertia", "t_max", "max_collisions"};
}

std::vector<std::string> param_row(const Params& p) {
  return {number(p.theta),  number(p.e),   number(p.mu),      number(p.beta0),
          number(p.radius), number(p.gap), number(p.inertia), number(p.t_max),
          std::to_string(p.max_collisions)};
}

std::vector<std::string> ensemble_columns() {
  std::vector<std::string> cols{"samples"};
  for (const auto& s : summaries) {
    for (const char* f : summary_fields) cols.push_back(std::string(s.name) + "_" + f);
  }
  for (const char* c : {"exited", "rest", "trapped", "total_collisions"}) cols.emplace_back(c);
  return cols;
}

std::vector<std::string> ensemble_row(const EnsembleResult& r) {
  std::vector<std::string> row{std::to_string(r.samples)};
  for (const auto& s : summaries) {
    const Summary& v = r.*(s.member);
    for (const double x : {v.mean, v.std, v.sem, v.min, v.max}) row.push_back(number(x));
  }
  for (const std::int64_t c : {r.exited, r.rest, r.trapped, r.total_collisions}) row.push_back(std::to_string(c));
  return row;
}

std::vector<std::string> trajectory_columns() {
  return {"status", "duration", "impulse", "normal_impulse", "energy_loss", "collisions",
          "edge_collisions", "face_collisions", "contacts", "contact_time"};
}

std::vector<std::string> trajectory_row(const Trajectory& t) {
  return {std::string(to_string(t.status)), number(t.duration), number(t.impulse), number(t.normal_impulse),
          number(t.energy_loss), std::to_string(t.collisions), std::to_string(t.edge_collisions),
          std::to_string(t.collisions - t.edge_collisions), std::to_string(t.contacts), number(t.contact_time)};
}

std::string csv_line(const std::vector<std::string>& fields) {
  std::string line;
  for (std::size_t i = 0; i < fields.size(); ++i) {
    if (i > 0) line += ',';
    line += fields[i];
  }
  line += '\n';
  return line;
}

}  // namespace funnel::cli
