// JSON (nlohmann) and CSV renderings; doubles are written so that they read back bit for bit.
#include "funnel/paper/records.hpp"

#include <charconv>
#include <cmath>

#include "funnel/funnel.hpp"
#include "funnel/observables.hpp"
#include "funnel/version.hpp"

namespace funnel::paper {

std::string number(double x) {
  if (x == 0.0) x = 0.0;  // no "-0" in outputs
  char buf[32];
  const auto [ptr, ec] = std::to_chars(buf, buf + sizeof buf, x);
  (void)ec;
  return std::string(buf, ptr);
}

std::string csv_number(double x) { return std::isnan(x) ? std::string() : number(x); }

namespace {

constexpr const char* summary_fields[] = {"mean", "std", "sem", "min", "max"};

/// A JSON number, or null for NaN (an observable that is not defined); -0 is written as 0.
nlohmann::ordered_json json_number(double x) {
  if (std::isnan(x)) return nullptr;
  return x == 0.0 ? 0.0 : x;
}

/// A CSV field: empty for NaN, an integer for counts, else the shortest round-trip text.
std::string field(double x, bool count) {
  if (count && !std::isnan(x)) return std::to_string(static_cast<std::int64_t>(x));
  return csv_number(x);
}

nlohmann::ordered_json summary_json(const Summary& s) {
  return {{"mean", json_number(s.mean)}, {"std", json_number(s.std)}, {"sem", json_number(s.sem)},
          {"min", json_number(s.min)},   {"max", json_number(s.max)}};
}

/// The statistics of an observable, or NaN throughout when no sample defines it.
Summary reported(const EnsembleResult& r, const ObservableInfo& o) {
  if (o.exited_only && r.exited == 0) {
    const double nan = std::nan("");
    return {nan, nan, nan, nan, nan};
  }
  return r[o.id];
}

std::string wall_text(const std::optional<Wall>& w) { return w ? std::string(to_string(*w)) : "none"; }

}  // namespace

nlohmann::ordered_json params_json(const Params& p, Space space) {
  nlohmann::ordered_json j;
  for (const ParameterInfo& info : parameters(space)) {
    if (info.integer) {
      j[info.key()] = static_cast<std::int64_t>(info.get(p));
    } else {
      j[info.key()] = json_number(reported_value(info, p));
    }
  }
  return j;
}

nlohmann::ordered_json geometry_json(const Params& p) {
  const Funnel f = make_funnel(p);
  nlohmann::ordered_json j;
  j["source"] = f.source;
  j["closed"] = f.closed;
  j["symmetric"] = f.symmetric;
  j["y_exit"] = json_number(f.y_exit);
  j["bottom"] = json_number(f.y_bottom);
  j["y_release"] = json_number(f.y_release);
  j["x_release_mid"] = json_number(f.x_release_mid);
  j["half_width"] = json_number(f.half_width);
  for (const int i : {0, 1}) {
    const char* side = i == 0 ? "left" : "right";
    auto& w = j["walls"][side];
    w = nlohmann::ordered_json::array();
    for (const Vec2 v : wall_surface(f, i, drawing_top(f))) w.push_back({json_number(v.x), json_number(v.y)});
    const Material& m = f.sides[i].material;
    j["materials"][side] = {{"e", json_number(m.e)}, {"mu", json_number(m.mu)}, {"beta0", json_number(m.beta0)}};
  }
  return j;
}

nlohmann::ordered_json provenance_json(const std::string& command_line) {
  return {{"version", version()}, {"git_commit", git_commit()}, {"command", command_line}};
}

nlohmann::ordered_json trajectory_json(const Trajectory& t) {
  nlohmann::ordered_json j;
  j["status"] = to_string(t.status);
  for (const ObservableInfo& o : observables()) {
    const double v = value(t, o.id);
    if (o.count) {
      j[std::string(o.name)] = static_cast<std::int64_t>(v);
    } else {
      j[std::string(o.name)] = json_number(v);
    }
  }
  return j;
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
  for (const ObservableInfo& o : observables()) {
    if (o.summarized) j[std::string(o.name)] = summary_json(reported(r, o));
  }
  j["status_counts"] = {{"exited", r.exited}, {"rest", r.rest}, {"trapped", r.trapped}};
  j["stalled"] = r.stalled;
  j["capped"] = r.capped;
  j["total_collisions"] = r.total_collisions;
  j["simulated_collisions"] = r.simulated_collisions;
  if (r.wear.bins > 0) j["wear"] = wear_json(r.wear);
  return j;
}

nlohmann::ordered_json wear_json(const Wear& w) {
  nlohmann::ordered_json j;
  for (const Wall wall : {Wall::Left, Wall::Right}) {
    const WallWear& ww = w[wall];
    nlohmann::ordered_json side;
    const double width = w.width(wall);
    std::vector<double> s;
    for (int k = 0; k < w.bins; ++k) s.push_back((k + 0.5) * width);
    side["s"] = s;
    side["bin_width"] = width;
    side["collisions"] = ww.collisions;
    side["normal_impulse"] = ww.normal_impulse;
    side["impulse"] = ww.impulse;
    side["edge"] = {{"collisions", ww.edge_collisions},
                    {"normal_impulse", ww.edge_normal_impulse},
                    {"impulse", ww.edge_impulse}};
    j[std::string(to_string(wall))] = side;
  }
  j["bin_width"] = w.width(Wall::Left);  // (kept from before each wall had its own)
  return j;
}

std::string wear_csv(const Wear& w) {
  std::string text = csv_line({"wall", "bin", "s", "collisions", "normal_impulse", "impulse"});
  for (const Wall wall : {Wall::Left, Wall::Right}) {
    const WallWear& ww = w[wall];
    const std::string name(to_string(wall));
    const double width = w.width(wall);
    for (int k = 0; k < w.bins; ++k) {
      const auto i = static_cast<std::size_t>(k);
      text += csv_line({name, std::to_string(k), number((k + 0.5) * width), number(ww.collisions[i]),
                        number(ww.normal_impulse[i]), number(ww.impulse[i])});
    }
    text += csv_line({name, "edge", "0", number(ww.edge_collisions), number(ww.edge_normal_impulse),
                      number(ww.edge_impulse)});
  }
  return text;
}

std::vector<std::string> param_columns(Space space) {
  std::vector<std::string> cols;
  for (const ParameterInfo& p : parameters(space)) {
    if (p.option) cols.push_back(p.key());
  }
  return cols;
}

std::vector<std::string> param_row(const Params& p, Space space) {
  std::vector<std::string> row;
  for (const ParameterInfo& info : parameters(space)) {
    if (info.option) row.push_back(field(info.integer ? info.get(p) : reported_value(info, p), info.integer));
  }
  return row;
}

std::vector<std::string> ensemble_columns() {
  std::vector<std::string> cols{"samples"};
  for (const ObservableInfo& o : observables()) {
    if (!o.summarized) continue;
    for (const char* f : summary_fields) cols.push_back(std::string(o.name) + "_" + f);
  }
  for (const char* c : {"exited", "rest", "trapped", "total_collisions"}) cols.emplace_back(c);
  return cols;
}

std::vector<std::string> ensemble_row(const EnsembleResult& r) {
  std::vector<std::string> row{std::to_string(r.samples)};
  for (const ObservableInfo& o : observables()) {
    if (!o.summarized) continue;
    const Summary v = reported(r, o);
    for (const double x : {v.mean, v.std, v.sem, v.min, v.max}) row.push_back(field(x, false));
  }
  for (const std::int64_t c : {r.exited, r.rest, r.trapped, r.total_collisions}) row.push_back(std::to_string(c));
  return row;
}

std::vector<std::string> trajectory_columns() {
  std::vector<std::string> cols{"status"};
  for (const ObservableInfo& o : observables()) cols.emplace_back(o.name);
  return cols;
}

std::vector<std::string> trajectory_row(const Trajectory& t) {
  std::vector<std::string> row{std::string(to_string(t.status))};
  for (const ObservableInfo& o : observables()) row.push_back(field(value(t, o.id), o.count));
  return row;
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

}  // namespace funnel::paper
