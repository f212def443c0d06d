// JSON and CSV renderings of the 3D engine's results; doubles read back bit for bit.
#include "output3d.hpp"

#include <cmath>

#include "cli_common.hpp"
#include "funnel/observables.hpp"

namespace funnel::cli {

namespace {

constexpr const char* summary_fields[] = {"mean", "std", "sem", "min", "max"};

/// A JSON number, or null for NaN; -0 is written as 0 (as in 2D outputs).
nlohmann::ordered_json json_number(double x) {
  if (std::isnan(x)) return nullptr;
  return x == 0.0 ? 0.0 : x;
}

/// A CSV field: empty for NaN, an integer for counts, else the shortest round-trip text.
std::string field(double x, bool count) {
  if (std::isnan(x)) return "";
  if (count) return std::to_string(static_cast<std::int64_t>(x));
  return number(x);
}

/// The statistics of an observable, or NaN throughout when no sample defines it.
Summary reported(const Ensemble3Result& r, const ObservableInfo& o) {
  if (o.exited_only && r.exited == 0) {
    const double nan = std::nan("");
    return {nan, nan, nan, nan, nan};
  }
  return r[o.id];
}

}  // namespace

nlohmann::ordered_json trajectory_json(const Trajectory3& t) {
  nlohmann::ordered_json j;
  j["status"] = to_string(t.status);
  for (const ObservableInfo& o : observables_3d()) {
    const double v = value(t, o.id);
    if (o.count) {
      j[std::string(o.name)] = static_cast<std::int64_t>(v);
    } else {
      j[std::string(o.name)] = json_number(v);
    }
  }
  j["orbits_signed"] = json_number(t.orbits);
  j["periodic"] = t.periodic;
  j["stalled"] = t.stalled;
  return j;
}

std::vector<std::string> trajectory_columns_3d() {
  std::vector<std::string> cols{"status"};
  for (const ObservableInfo& o : observables_3d()) cols.emplace_back(o.name);
  cols.emplace_back("periodic");
  cols.emplace_back("stalled");
  return cols;
}

std::vector<std::string> trajectory_row(const Trajectory3& t) {
  std::vector<std::string> row{std::string(to_string(t.status))};
  for (const ObservableInfo& o : observables_3d()) row.push_back(field(value(t, o.id), o.count));
  row.emplace_back(t.periodic ? "1" : "0");
  row.emplace_back(t.stalled ? "1" : "0");
  return row;
}

std::vector<std::string> event_columns_3d() {
  return {"time",         "kind",         "wall",         "x",           "y",           "z",
          "u_before",     "v_before",     "w_before",     "omega_before", "u_after",    "v_after",
          "w_after",      "omega_after",  "omega_x_before", "omega_y_before", "omega_z_before",
          "omega_x_after", "omega_y_after", "omega_z_after", "slip_before", "regime",   "j_n",
          "j_t",          "energy_lost"};
}

std::vector<std::string> event_row(const Event3& e) {
  return {number(e.time),
          std::string(to_string(e.kind)),
          "none",
          number(e.position.x),
          number(e.position.y),
          number(e.position.z),
          number(e.velocity_before.x),
          number(e.velocity_before.y),
          number(e.velocity_before.z),
          number(e.omega_before.z),
          number(e.velocity_after.x),
          number(e.velocity_after.y),
          number(e.velocity_after.z),
          number(e.omega_after.z),
          number(e.omega_before.x),
          number(e.omega_before.y),
          number(e.omega_before.z),
          number(e.omega_after.x),
          number(e.omega_after.y),
          number(e.omega_after.z),
          number(norm(e.slip_before)),
          std::string(to_string(e.regime)),
          number(e.j_n),
          number(norm(e.j_t)),
          number(e.energy_lost)};
}

nlohmann::ordered_json event_json(const Event3& e) {
  nlohmann::ordered_json j;
  j["time"] = e.time;
  j["kind"] = to_string(e.kind);
  j["wall"] = nullptr;  // the cone has one wall
  j["x"] = e.position.x;
  j["y"] = e.position.y;
  j["z"] = e.position.z;
  j["u_before"] = e.velocity_before.x;
  j["v_before"] = e.velocity_before.y;
  j["w_before"] = e.velocity_before.z;
  j["omega_before"] = e.omega_before.z;
  j["u_after"] = e.velocity_after.x;
  j["v_after"] = e.velocity_after.y;
  j["w_after"] = e.velocity_after.z;
  j["omega_after"] = e.omega_after.z;
  j["omega_x_before"] = e.omega_before.x;
  j["omega_y_before"] = e.omega_before.y;
  j["omega_z_before"] = e.omega_before.z;
  j["omega_x_after"] = e.omega_after.x;
  j["omega_y_after"] = e.omega_after.y;
  j["omega_z_after"] = e.omega_after.z;
  j["slip_before"] = norm(e.slip_before);
  j["regime"] = to_string(e.regime);
  j["j_n"] = e.j_n;
  j["j_t"] = norm(e.j_t);
  j["energy_lost"] = e.energy_lost;
  j["normal"] = {e.normal.x, e.normal.y, e.normal.z};
  j["slip_before_vector"] = {e.slip_before.x, e.slip_before.y, e.slip_before.z};
  j["j_t_vector"] = {e.j_t.x, e.j_t.y, e.j_t.z};
  return j;
}

nlohmann::ordered_json ensemble_json(const Ensemble3Result& r) {
  nlohmann::ordered_json j;
  j["samples"] = r.samples;
  for (const ObservableInfo& o : observables_3d()) {
    if (!o.summarized) continue;
    const Summary s = reported(r, o);
    j[std::string(o.name)] = {{"mean", json_number(s.mean)}, {"std", json_number(s.std)},
                              {"sem", json_number(s.sem)},   {"min", json_number(s.min)},
                              {"max", json_number(s.max)}};
  }
  j["status_counts"] = {{"exited", r.exited}, {"rest", r.rest}, {"trapped", r.trapped}};
  j["periodic"] = r.periodic;
  j["stalled"] = r.stalled;
  j["capped"] = r.capped;
  j["total_collisions"] = r.total_collisions;
  j["ode_steps"] = r.ode_steps;
  return j;
}

std::vector<std::string> ensemble_columns_3d() {
  std::vector<std::string> cols{"samples"};
  for (const ObservableInfo& o : observables_3d()) {
    if (!o.summarized) continue;
    for (const char* f : summary_fields) cols.push_back(std::string(o.name) + "_" + f);
  }
  for (const char* c : {"exited", "rest", "trapped", "periodic", "stalled", "total_collisions"}) cols.emplace_back(c);
  return cols;
}

std::vector<std::string> ensemble_row(const Ensemble3Result& r) {
  std::vector<std::string> row{std::to_string(r.samples)};
  for (const ObservableInfo& o : observables_3d()) {
    if (!o.summarized) continue;
    const Summary v = reported(r, o);
    for (const double x : {v.mean, v.std, v.sem, v.min, v.max}) row.push_back(field(x, false));
  }
  for (const std::int64_t c : {r.exited, r.rest, r.trapped, r.periodic, r.stalled, r.total_collisions}) {
    row.push_back(std::to_string(c));
  }
  return row;
}

}  // namespace funnel::cli
