// pybind11 bindings of the 3D engine (the axisymmetric funnel): simulate_3d, ensemble_3d,
// sweep_3d; documented in python/funnel/_api.py (space="3d").
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "convert.hpp"
#include "funnel/cone.hpp"
#include "funnel/engine3d.hpp"
#include "funnel/ensemble3d.hpp"
#include "funnel/grid.hpp"
#include "funnel/observables.hpp"
#include "funnel/params.hpp"

namespace py = pybind11;

namespace {

using funnel::py_convert::add_param_columns;
using funnel::py_convert::check_sweep_axes;
using funnel::py_convert::column;
using funnel::py_convert::params_dict;
using funnel::py_convert::run_interruptible;
using funnel::py_convert::text_column;

/// The defaults overridden by `model` ({python name: float}), validated for 3D.
funnel::Params make_params_3d(const std::map<std::string, double>& model) {
  funnel::Params p = funnel::default_params();
  for (const auto& [key, value] : model) {
    const funnel::ParameterInfo* info = funnel::find_parameter(key);
    if (info == nullptr || !info->option) throw py::type_error("unknown model parameter '" + key + "'");
    if (const auto err = funnel::set_parameter_checked(p, info->name, value)) throw py::value_error(err->message());
  }
  if (const auto err = funnel::validate(p, funnel::Space::ThreeD)) throw py::value_error(err->message());
  return p;
}

py::object observable_value(const funnel::ObservableInfo& o, double v) {
  if (std::isnan(v)) return py::none();
  if (o.count) return py::int_(static_cast<std::int64_t>(v));
  return py::float_(v);
}

funnel::Ensemble3Options options_3d(std::int64_t samples, const std::string& dist, int threads, std::uint64_t seed,
                                    double velocity_sd) {
  funnel::Ensemble3Options o;
  const auto d = funnel::parse_release_dist(dist);
  if (!d || (*d != funnel::ReleaseDist::Line && *d != funnel::ReleaseDist::Disk)) {
    throw py::value_error("invalid release_dist = '" + dist + "': valid values in 3d are disk and line");
  }
  funnel::EnsembleOptions check;  // the same checks as in 2D for the shared options
  check.samples = samples;
  check.threads = threads;
  check.velocity_sd = velocity_sd;
  if (const auto err = funnel::validate(check)) throw py::value_error(err->message());
  o.samples = samples;
  o.dist = *d;
  o.threads = threads;
  o.seed = seed;
  o.velocity_sd = velocity_sd;
  return o;
}

py::dict events_dict_3d(const std::vector<funnel::Event3>& ev) {
  const std::size_t n = ev.size();
  py::dict d;
  auto col = [&](const char* name, auto get) { d[name] = column<double>(n, [&](std::size_t i) { return get(ev[i]); }); };
  col("time", [](const funnel::Event3& e) { return e.time; });
  d["kind"] = text_column(n, [&](std::size_t i) { return funnel::to_string(ev[i].kind); });
  col("x", [](const funnel::Event3& e) { return e.position.x; });
  col("y", [](const funnel::Event3& e) { return e.position.y; });
  col("z", [](const funnel::Event3& e) { return e.position.z; });
  col("u_before", [](const funnel::Event3& e) { return e.velocity_before.x; });
  col("v_before", [](const funnel::Event3& e) { return e.velocity_before.y; });
  col("w_before", [](const funnel::Event3& e) { return e.velocity_before.z; });
  col("u_after", [](const funnel::Event3& e) { return e.velocity_after.x; });
  col("v_after", [](const funnel::Event3& e) { return e.velocity_after.y; });
  col("w_after", [](const funnel::Event3& e) { return e.velocity_after.z; });
  col("omega_before", [](const funnel::Event3& e) { return e.omega_before.z; });
  col("omega_after", [](const funnel::Event3& e) { return e.omega_after.z; });
  col("omega_x_before", [](const funnel::Event3& e) { return e.omega_before.x; });
  col("omega_y_before", [](const funnel::Event3& e) { return e.omega_before.y; });
  col("omega_z_before", [](const funnel::Event3& e) { return e.omega_before.z; });
  col("omega_x_after", [](const funnel::Event3& e) { return e.omega_after.x; });
  col("omega_y_after", [](const funnel::Event3& e) { return e.omega_after.y; });
  col("omega_z_after", [](const funnel::Event3& e) { return e.omega_after.z; });
  col("slip_before", [](const funnel::Event3& e) { return std::sqrt(funnel::dot(e.slip_before, e.slip_before)); });
  d["regime"] = text_column(n, [&](std::size_t i) { return funnel::to_string(ev[i].regime); });
  col("j_n", [](const funnel::Event3& e) { return e.j_n; });
  col("j_t", [](const funnel::Event3& e) { return std::sqrt(funnel::dot(e.j_t, e.j_t)); });
  col("energy_lost", [](const funnel::Event3& e) { return e.energy_lost; });
  return d;
}

void put_trajectory_3d(py::dict& d, const funnel::Trajectory3& t) {
  d["status"] = std::string(funnel::to_string(t.status));
  for (const funnel::ObservableInfo& o : funnel::observables_3d()) {
    d[py::str(std::string(o.name))] = observable_value(o, funnel::value(t, o.id));
  }
  d["orbits_signed"] = t.orbits;
  d["periodic"] = t.periodic;
  d["stalled"] = t.stalled;
}

void put_summaries_3d(py::dict& d, const funnel::Ensemble3Result& r) {
  d["samples"] = r.samples;
  for (const funnel::ObservableInfo& o : funnel::observables_3d()) {
    if (!o.summarized) continue;
    const funnel::Summary& v = r[o.id];
    const bool undefined = o.exited_only && r.exited == 0;
    py::dict sd;
    for (const auto& [name, x] : {std::pair<const char*, double>{"mean", v.mean}, {"std", v.std}, {"sem", v.sem},
                                  {"min", v.min}, {"max", v.max}}) {
      sd[name] = undefined ? py::object(py::none()) : py::object(py::float_(x));
    }
    d[py::str(std::string(o.name))] = sd;
  }
  py::dict counts;
  counts["exited"] = r.exited;
  counts["rest"] = r.rest;
  counts["trapped"] = r.trapped;
  d["status_counts"] = counts;
  d["periodic"] = r.periodic;
  d["stalled"] = r.stalled;
  d["capped"] = r.capped;
  d["total_collisions"] = r.total_collisions;
  d["ode_steps"] = r.ode_steps;
}

py::dict simulate_3d(const std::map<std::string, double>& model, double release, bool events) {
  const funnel::Params params = make_params_3d(model);
  if (!(release > -1.0 && release < 1.0)) {
    throw py::value_error("invalid release = " + funnel::format_number(release) +
                          ": valid range is -1 < release < 1 (x0/L)");
  }
  const funnel::Cone cone = funnel::make_cone(params);
  const funnel::State3 s = funnel::release_state_3d(params, cone, release);
  funnel::EventLog3 log;
  funnel::Trajectory3 t;
  funnel::py_convert::InterruptSink<funnel::EventSink3, funnel::Event3> sink(events ? &log : nullptr);
  {
    py::gil_scoped_release nogil;
    t = funnel::simulate_3d(params, cone, s, &sink);
  }
  sink.raise_if_interrupted();
  py::dict d;
  d["space"] = "3d";
  d["params"] = params_dict(params, funnel::Space::ThreeD);
  d["release"] = release;
  d["x0"] = s.r.x;
  d["y0"] = s.r.y;
  d["z0"] = s.r.z;
  d["u0"] = s.v.x;
  d["v0"] = s.v.y;
  d["w0"] = s.v.z;
  d["omega0"] = std::vector<double>{s.omega.x, s.omega.y, s.omega.z};
  put_trajectory_3d(d, t);
  if (events) d["events"] = events_dict_3d(log.events);
  d["_capped"] = t.capped;  // not a CLI key: for funnel.simulate's CappedWarning, which removes it
  return d;
}

py::dict ensemble_3d(const std::map<std::string, double>& model, std::int64_t samples, const std::string& dist,
                     int threads, bool per_sample, std::uint64_t seed, double velocity_sd, const py::object& progress) {
  const funnel::Params params = make_params_3d(model);
  funnel::Ensemble3Options o = options_3d(samples, dist, threads, seed, velocity_sd);
  o.keep_samples = per_sample;
  funnel::Ensemble3Result r;
  run_interruptible(o, progress, [&](const funnel::Progress& report) { r = funnel::run_ensemble_3d(params, o, report); });
  py::dict d;
  d["space"] = "3d";
  d["params"] = params_dict(params, funnel::Space::ThreeD);
  d["release_dist"] = std::string(funnel::to_string(o.dist));
  if (o.velocity_sd > 0.0) d["seed"] = o.seed;
  d["velocity_sd"] = o.velocity_sd;
  put_summaries_3d(d, r);
  if (per_sample) {
    const auto& ps = r.per_sample;
    const std::size_t n = ps.size();
    py::dict s;
    s["release"] = column<double>(n, [&](std::size_t i) { return ps[i].fraction; });
    s["u0"] = column<double>(n, [&](std::size_t i) { return ps[i].velocity.x; });
    s["v0"] = column<double>(n, [&](std::size_t i) { return ps[i].velocity.y; });
    s["w0"] = column<double>(n, [&](std::size_t i) { return ps[i].velocity.z; });
    s["status"] = text_column(n, [&](std::size_t i) { return funnel::to_string(ps[i].trajectory.status); });
    for (const funnel::ObservableInfo& o3 : funnel::observables_3d()) {
      const auto get = [&](std::size_t i) { return funnel::value(ps[i].trajectory, o3.id); };
      // Counts as int64, as in 2D and the CLI's JSON.
      s[py::str(std::string(o3.name))] =
          o3.count ? py::object(column<std::int64_t>(n, [&](std::size_t i) { return static_cast<std::int64_t>(get(i)); }))
                   : py::object(column<double>(n, get));
    }
    s["periodic"] = column<bool>(n, [&](std::size_t i) { return ps[i].trajectory.periodic; });
    s["stalled"] = column<bool>(n, [&](std::size_t i) { return ps[i].trajectory.stalled; });
    d["per_sample"] = s;
  }
  return d;
}

/// One 3D ensemble per grid point; axes in the 3D parameter table's order.
py::dict sweep_3d(const std::vector<std::pair<std::string, std::vector<double>>>& axes_in, std::int64_t samples,
                  const std::string& dist, int threads, std::uint64_t seed, double velocity_sd,
                  const py::object& progress) {
  std::vector<funnel::Axis> axes;
  for (const auto& [key, values] : axes_in) {
    const funnel::ParameterInfo* info = funnel::find_parameter(key);
    if (info == nullptr || !info->option) throw py::type_error("unknown model parameter '" + key + "'");
  }
  for (const funnel::ParameterInfo& info : funnel::parameters(funnel::Space::ThreeD)) {
    for (const auto& [key, values] : axes_in) {
      if (funnel::find_parameter(key) != &info) continue;
      if (values.empty()) {
        throw py::value_error("invalid " + std::string(info.name) + ": no values; valid range is " +
                              std::string(info.range));
      }
      axes.push_back({std::string(info.name), values});
    }
  }
  check_sweep_axes(axes);  // settable values (1.5 max-collisions ran uncapped) and the size cap
  const std::vector<funnel::Params> points = funnel::expand_grid(funnel::default_params(), axes);
  for (const funnel::Params& p : points) {
    if (const auto err = funnel::validate(p, funnel::Space::ThreeD)) throw py::value_error(err->message());
  }
  funnel::Ensemble3Options o = options_3d(samples, dist, threads, seed, velocity_sd);
  std::vector<funnel::Ensemble3Result> results;
  run_interruptible(o, progress, [&](const funnel::Progress& report) { results = funnel::run_sweep_3d(points, o, report); });
  py::dict d;
  const std::size_t n = points.size();
  add_param_columns(d, points, funnel::Space::ThreeD);
  // As funnel sweep --space 3d's CSV: the distribution and the sample count after the parameters.
  d["release_dist"] = text_column(n, [&](std::size_t) { return funnel::to_string(o.dist); });
  d["samples"] = column<std::int64_t>(n, [&](std::size_t i) { return results[i].samples; });
  for (const funnel::ObservableInfo& obs : funnel::observables_3d()) {
    if (!obs.summarized) continue;
    for (const char* stat : {"mean", "std", "sem", "min", "max"}) {
      const std::string key = std::string(obs.name) + "_" + stat;
      d[py::str(key)] = column<double>(n, [&](std::size_t i) {
        const funnel::Ensemble3Result& r = results[i];
        if (obs.exited_only && r.exited == 0) return std::nan("");
        const funnel::Summary& s = r[obs.id];
        const std::string st = stat;
        return st == "mean" ? s.mean : st == "std" ? s.std : st == "sem" ? s.sem : st == "min" ? s.min : s.max;
      });
    }
  }
  d["exited"] = column<std::int64_t>(n, [&](std::size_t i) { return results[i].exited; });
  d["rest"] = column<std::int64_t>(n, [&](std::size_t i) { return results[i].rest; });
  d["trapped"] = column<std::int64_t>(n, [&](std::size_t i) { return results[i].trapped; });
  d["periodic"] = column<std::int64_t>(n, [&](std::size_t i) { return results[i].periodic; });
  d["stalled"] = column<std::int64_t>(n, [&](std::size_t i) { return results[i].stalled; });
  d["total_collisions"] = column<std::int64_t>(n, [&](std::size_t i) { return results[i].total_collisions; });
  // Not a CSV column: the runs the collision cap ended, for funnel.sweep's CappedWarning (which
  // removes the key).
  std::int64_t capped = 0;
  for (const funnel::Ensemble3Result& r : results) capped += r.capped;
  d["_capped"] = capped;
  return d;
}

}  // namespace

void bind_3d(py::module_& m) {
  m.def("simulate_3d", &simulate_3d, py::arg("model"), py::arg("release"), py::arg("events"));
  m.def("ensemble_3d", &ensemble_3d, py::arg("model"), py::arg("samples"), py::arg("release_dist"),
        py::arg("threads"), py::arg("per_sample"), py::arg("seed"), py::arg("velocity_sd"), py::arg("progress"));
  m.def("sweep_3d", &sweep_3d, py::arg("axes"), py::arg("samples"), py::arg("release_dist"), py::arg("threads"),
        py::arg("seed"), py::arg("velocity_sd"), py::arg("progress"));
  m.def("parameters_3d", [] {
    py::list out;
    for (const funnel::ParameterInfo& info : funnel::parameters(funnel::Space::ThreeD)) {
      if (funnel::only_3d(info)) out.append(info.key());
    }
    return out;
  });
  m.def("observables_3d", [] {
    py::list out;
    for (const funnel::ObservableInfo& o : funnel::observables_3d()) out.append(std::string(o.name));
    return out;
  });
}
