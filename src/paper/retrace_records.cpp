// CSV and JSON renderings of self-retracing orbits and their windows.
#include "funnel/paper/retrace_records.hpp"

#include "funnel/paper/records.hpp"

namespace funnel::paper {

std::vector<CheckedOrbit> check_orbits(const Params& params, const std::vector<retrace::Orbit>& orbits) {
  std::vector<CheckedOrbit> out;
  out.reserve(orbits.size());
  for (const retrace::Orbit& o : orbits) out.push_back({o, retrace::check_return(params, o)});
  return out;
}

std::vector<std::string> orbit_columns() {
  return {"theta",     "release",    "sequence", "turn",  "bounces", "collisions_per_period",
          "period",    "trace",      "stable",   "y0",    "turn_x",  "min_height",
          "residual",  "return_position_error", "return_speed"};
}

std::vector<std::string> orbit_row(const CheckedOrbit& c) {
  const retrace::Orbit& o = c.orbit;
  return {number(o.theta),
          number(o.release),
          o.sequence,
          std::string(retrace::to_string(o.turn)),
          std::to_string(o.bounces),
          std::to_string(o.collisions_per_period),
          number(o.period),
          number(o.trace),
          o.stable ? "1" : "0",
          number(o.y0),
          number(o.turn_x),
          number(o.min_height),
          number(o.residual),
          number(c.check.position_error),
          number(c.check.speed)};
}

nlohmann::ordered_json orbit_json(const CheckedOrbit& c) {
  const retrace::Orbit& o = c.orbit;
  return {{"theta", o.theta},
          {"release", o.release},
          {"sequence", o.sequence},
          {"turn", std::string(retrace::to_string(o.turn))},
          {"bounces", o.bounces},
          {"collisions_per_period", o.collisions_per_period},
          {"period", o.period},
          {"trace", o.trace},
          {"stable", o.stable},
          {"y0", o.y0},
          {"turn_x", o.turn_x},
          {"min_height", o.min_height},
          {"residual", o.residual},
          {"return_position_error", c.check.position_error},
          {"return_speed", c.check.speed}};
}

std::vector<std::string> window_columns() {
  return {"sequence", "turn", "bounces", "window", "theta_from", "theta_to", "points"};
}

std::vector<std::string> window_row(const retrace::Window& w) {
  return {w.sequence,
          std::string(retrace::to_string(w.turn)),
          std::to_string(w.sequence.size()),
          w.stable ? "stable" : "exists",
          number(w.theta_from),
          number(w.theta_to),
          std::to_string(w.points)};
}

nlohmann::ordered_json window_json(const retrace::Window& w) {
  return {{"sequence", w.sequence},
          {"turn", std::string(retrace::to_string(w.turn))},
          {"bounces", w.sequence.size()},
          {"window", w.stable ? "stable" : "exists"},
          {"theta_from", w.theta_from},
          {"theta_to", w.theta_to},
          {"points", w.points}};
}

bool parse_turns(const std::string& text) {
  if (text == "wall") return false;
  if (text == "wall,rest" || text == "rest,wall" || text == "all") return true;
  throw InputError("invalid turns = '" + text + "': valid values are wall, wall,rest (or all)");
}

}  // namespace funnel::paper
