// pybind11 binding of funnel::retrace (self-retracing frictionless orbits); documented in python/funnel/_api.py.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <string>
#include <vector>

#include "funnel/params.hpp"
#include "funnel/retrace.hpp"
#include "convert.hpp"

namespace py = pybind11;

namespace {


using funnel::py_convert::column;
using funnel::py_convert::text_column;

void check_int(const char* name, int value, int lo, int hi) {
  if (value < lo || value > hi) {
    throw py::value_error(std::string("invalid ") + name + " = " + std::to_string(value) + ": valid range is an integer " +
                          std::to_string(lo) + " <= " + name + " <= " + std::to_string(hi));
  }
}

/// Every self-retracing orbit at each angle, with the engine's return check, and the windows.
py::dict retrace(const std::vector<double>& thetas, double radius, double gap, int max_bounces, int scan_points,
                 bool rest_turns, int threads) {
  funnel::Params base = funnel::retrace::frictionless(funnel::default_params());
  base.radius = radius;
  base.gap = gap;
  if (thetas.empty()) throw py::value_error("invalid theta: no values; valid range is 0 < theta < 90 (degrees)");
  for (const double t : thetas) {
    funnel::Params p = base;
    p.theta = t;
    if (const auto err = funnel::validate(p)) throw py::value_error(err->message());
  }
  check_int("max_bounces", max_bounces, 1, 20);
  check_int("scan_points", scan_points, 16, 1'000'000);
  check_int("threads", threads, 0, 1024);
  funnel::retrace::Options opt;
  opt.max_bounces = max_bounces;
  opt.scan_points = scan_points;
  opt.rest_turns = rest_turns;
  opt.threads = threads;
  std::vector<funnel::retrace::Orbit> orbits;
  std::vector<funnel::retrace::ReturnCheck> checks;
  std::vector<funnel::retrace::Window> wins;
  std::atomic<bool> cancel{false};
  opt.cancel = &cancel;
  // Ctrl-C skips the angles not yet begun and raises KeyboardInterrupt (it ran to the end).
  funnel::py_convert::run_reporting(py::none(), cancel, [&](const funnel::Progress&) {
    orbits = funnel::retrace::scan(base, thetas, opt);
    if (cancel.load()) return;
    for (const auto& o : orbits) checks.push_back(funnel::retrace::check_return(base, o));
    wins = funnel::retrace::windows(orbits, thetas);
  });
  const std::size_t n = orbits.size();
  py::dict o;  // the columns of `funnel retrace --format csv`
  o["theta"] = column<double>(n, [&](std::size_t i) { return orbits[i].theta; });
  o["release"] = column<double>(n, [&](std::size_t i) { return orbits[i].release; });
  o["sequence"] = text_column(n, [&](std::size_t i) { return orbits[i].sequence; });
  o["turn"] = text_column(n, [&](std::size_t i) { return funnel::retrace::to_string(orbits[i].turn); });
  o["bounces"] = column<std::int64_t>(n, [&](std::size_t i) { return orbits[i].bounces; });
  o["collisions_per_period"] = column<std::int64_t>(n, [&](std::size_t i) { return orbits[i].collisions_per_period; });
  o["period"] = column<double>(n, [&](std::size_t i) { return orbits[i].period; });
  o["trace"] = column<double>(n, [&](std::size_t i) { return orbits[i].trace; });
  o["stable"] = column<bool>(n, [&](std::size_t i) { return orbits[i].stable; });
  o["y0"] = column<double>(n, [&](std::size_t i) { return orbits[i].y0; });
  o["turn_x"] = column<double>(n, [&](std::size_t i) { return orbits[i].turn_x; });
  o["min_height"] = column<double>(n, [&](std::size_t i) { return orbits[i].min_height; });
  o["residual"] = column<double>(n, [&](std::size_t i) { return orbits[i].residual; });
  o["return_position_error"] = column<double>(n, [&](std::size_t i) { return checks[i].position_error; });
  o["return_speed"] = column<double>(n, [&](std::size_t i) { return checks[i].speed; });
  const std::size_t m = wins.size();
  py::dict w;
  w["sequence"] = text_column(m, [&](std::size_t i) { return wins[i].sequence; });
  w["turn"] = text_column(m, [&](std::size_t i) { return funnel::retrace::to_string(wins[i].turn); });
  w["bounces"] = column<std::int64_t>(m, [&](std::size_t i) { return static_cast<std::int64_t>(wins[i].sequence.size()); });
  w["window"] = text_column(m, [&](std::size_t i) { return wins[i].stable ? "stable" : "exists"; });
  w["theta_from"] = column<double>(m, [&](std::size_t i) { return wins[i].theta_from; });
  w["theta_to"] = column<double>(m, [&](std::size_t i) { return wins[i].theta_to; });
  w["points"] = column<std::int64_t>(m, [&](std::size_t i) { return wins[i].points; });
  py::dict d;
  d["radius"] = base.radius;
  d["gap"] = base.gap;
  d["orbits"] = o;
  d["windows"] = w;
  return d;
}

}  // namespace

/// Adds `retrace` to the compiled module (called from bindings.cpp).
void bind_retrace(py::module_& m) {
  m.def("retrace", &retrace, py::arg("thetas"), py::arg("radius"), py::arg("gap"), py::arg("max_bounces"),
        py::arg("scan_points"), py::arg("rest_turns"), py::arg("threads"));
}
