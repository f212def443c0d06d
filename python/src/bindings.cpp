// pybind11 bindings of the funnel library: parameters in as dicts, results out as dicts and numpy arrays.
// The documented Python API is python/funnel/_api.py; this layer only converts and validates.
#include <pybind11/complex.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <charconv>
#include <complex>
#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "funnel/closed.hpp"
#include "funnel/engine.hpp"
#include "funnel/ensemble.hpp"
#include "funnel/geometry.hpp"
#include "funnel/grid.hpp"
#include "funnel/orbit.hpp"
#include "funnel/params.hpp"
#include "funnel/version.hpp"

namespace py = pybind11;

namespace {

using funnel::Params;

/// Python keyword (t_max) to the library's parameter name (t-max).
std::string library_name(std::string name) {
  for (char& c : name) {
    if (c == '_') c = '-';
  }
  return name;
}

/// Shortest text that reads back as the same double, as in the library's messages.
std::string number_text(double x) {
  char buf[32];
  const auto [ptr, ec] = std::to_chars(buf, buf + sizeof buf, x);
  return ec == std::errc() ? std::string(buf, ptr) : "?";
}

/// The parameters' defaults overridden by `model` ({python name: float}), validated.
/// Throws ValueError with funnel::ParamError::message() for an invalid set.
Params make_params(const std::map<std::string, double>& model) {
  Params p = funnel::default_params();
  for (const auto& [key, value] : model) {
    const std::string name = library_name(key);
    if (!funnel::set_parameter(p, name, value)) {
      if (name == "max-collisions") {  // not an integer: the library's message form, its range
        throw py::value_error(funnel::ParamError{name, number_text(value),
                                                 std::string(funnel::valid_range(name))}.message());
      }
      throw py::type_error("unknown model parameter '" + key + "'");
    }
  }
  if (const auto err = funnel::validate(p)) throw py::value_error(err->message());
  return p;
}

/// {"theta": ..., ..., "eps_rest": ...}: the same keys and order as the CLI's "params".
py::dict params_dict(const Params& p) {
  py::dict d;
  d["theta"] = p.theta;
  d["e"] = p.e;
  d["mu"] = p.mu;
  d["beta0"] = p.beta0;
  d["radius"] = p.radius;
  d["gap"] = p.gap;
  d["inertia"] = p.inertia;
  d["t_max"] = p.t_max;
  d["max_collisions"] = p.max_collisions;
  d["p_c"] = p.p_c;
  d["eps_rest"] = p.eps_rest;
  return d;
}

/// Observables of one trajectory: the CLI's keys from "status" to "contact_time".
void put_trajectory(py::dict& d, const funnel::Trajectory& t) {
  d["status"] = std::string(funnel::to_string(t.status));
  d["duration"] = t.duration;
  d["impulse"] = t.impulse;
  d["normal_impulse"] = t.normal_impulse;
  d["energy_loss"] = t.energy_loss;
  d["collisions"] = t.collisions;
  d["edge_collisions"] = t.edge_collisions;
  d["face_collisions"] = t.collisions - t.edge_collisions;
  d["contacts"] = t.contacts;
  d["contact_time"] = t.contact_time;
}

/// A 1-D numpy array filled from `n` values of `get(i)`.
template <typename T, typename Get>
py::array_t<T> column(std::size_t n, Get get) {
  py::array_t<T> a(static_cast<py::ssize_t>(n));
  auto w = a.template mutable_unchecked<1>();
  for (std::size_t i = 0; i < n; ++i) w(static_cast<py::ssize_t>(i)) = get(i);
  return a;
}

/// A list of str from `n` values of `get(i)` (the Python layer makes it a numpy str array).
template <typename Get>
py::list text_column(std::size_t n, Get get) {
  py::list l;
  for (std::size_t i = 0; i < n; ++i) l.append(std::string(get(i)));
  return l;
}

/// The event log as columns, named as in `funnel trajectory --events --format csv`.
py::dict events_dict(const std::vector<funnel::Event>& ev) {
  const std::size_t n = ev.size();
  py::dict d;
  d["time"] = column<double>(n, [&](std::size_t i) { return ev[i].time; });
  d["kind"] = text_column(n, [&](std::size_t i) { return funnel::to_string(ev[i].kind); });
  d["wall"] = text_column(n, [&](std::size_t i) {
    return ev[i].wall ? funnel::to_string(*ev[i].wall) : std::string_view("none");
  });
  d["x"] = column<double>(n, [&](std::size_t i) { return ev[i].position.x; });
  d["y"] = column<double>(n, [&](std::size_t i) { return ev[i].position.y; });
  d["u_before"] = column<double>(n, [&](std::size_t i) { return ev[i].velocity_before.x; });
  d["v_before"] = column<double>(n, [&](std::size_t i) { return ev[i].velocity_before.y; });
  d["omega_before"] = column<double>(n, [&](std::size_t i) { return ev[i].omega_before; });
  d["u_after"] = column<double>(n, [&](std::size_t i) { return ev[i].velocity_after.x; });
  d["v_after"] = column<double>(n, [&](std::size_t i) { return ev[i].velocity_after.y; });
  d["omega_after"] = column<double>(n, [&](std::size_t i) { return ev[i].omega_after; });
  d["slip_before"] = column<double>(n, [&](std::size_t i) { return ev[i].slip_before; });
  d["regime"] = text_column(n, [&](std::size_t i) { return funnel::to_string(ev[i].regime); });
  d["j_n"] = column<double>(n, [&](std::size_t i) { return ev[i].j_n; });
  d["j_t"] = column<double>(n, [&](std::size_t i) { return ev[i].j_t; });
  d["energy_lost"] = column<double>(n, [&](std::size_t i) { return ev[i].energy_lost; });
  return d;
}

/// Ensemble statistics, in the CLI's order: name and member of each summary.
struct NamedSummary {
  const char* name;
  funnel::Summary funnel::EnsembleResult::*member;
};
constexpr NamedSummary summaries[] = {
    {"duration", &funnel::EnsembleResult::duration},
    {"impulse", &funnel::EnsembleResult::impulse},
    {"normal_impulse", &funnel::EnsembleResult::normal_impulse},
    {"energy_loss", &funnel::EnsembleResult::energy_loss},
    {"collisions", &funnel::EnsembleResult::collisions},
    {"edge_collisions", &funnel::EnsembleResult::edge_collisions},
    {"contact_time", &funnel::EnsembleResult::contact_time},
};

funnel::EnsembleOptions ensemble_options(std::int64_t samples, const std::string& dist, int threads) {
  funnel::EnsembleOptions o;
  if (samples < 1 || samples > 1'000'000'000) {
    throw py::value_error("invalid samples = " + std::to_string(samples) +
                          ": valid range is an integer 1 <= samples <= 10^9");
  }
  const auto d = funnel::parse_release_dist(dist);
  if (!d) throw py::value_error("invalid release_dist = '" + dist + "': valid values are line, disk");
  if (threads < 0 || threads > 1024) {
    throw py::value_error("invalid threads = " + std::to_string(threads) +
                          ": valid range is an integer 0 <= threads <= 1024 (0 = all cores)");
  }
  o.samples = samples;
  o.dist = *d;
  o.threads = threads;
  return o;
}

// ---------------------------------------------------------------------------------------------
// Module functions

py::dict simulate(const std::map<std::string, double>& model, double release, bool events) {
  const Params params = make_params(model);
  if (!(release > -1.0 && release < 1.0)) {
    throw py::value_error("invalid release = " + number_text(release) + ": valid range is -1 < release < 1 (x0/L)");
  }
  const funnel::Geometry g = funnel::make_geometry(params);
  funnel::EventLog log;
  funnel::Trajectory t;
  {
    py::gil_scoped_release nogil;
    t = funnel::simulate_release(params, g, release, events ? &log : nullptr);
  }
  py::dict d;
  d["params"] = params_dict(params);
  d["release"] = release;
  d["x0"] = release * g.half_width;
  d["y0"] = g.y_release;
  put_trajectory(d, t);
  if (events) d["events"] = events_dict(log.events);
  return d;
}

py::dict ensemble(const std::map<std::string, double>& model, std::int64_t samples, const std::string& dist,
                  int threads, bool per_sample) {
  const Params params = make_params(model);
  funnel::EnsembleOptions options = ensemble_options(samples, dist, threads);
  options.keep_samples = per_sample;
  funnel::EnsembleResult r;
  {
    py::gil_scoped_release nogil;
    r = funnel::run_ensemble(params, options);
  }
  py::dict d;
  d["params"] = params_dict(params);
  d["release_dist"] = std::string(funnel::to_string(options.dist));
  d["samples"] = r.samples;
  for (const auto& s : summaries) {
    const funnel::Summary& v = r.*(s.member);
    py::dict sd;
    sd["mean"] = v.mean;
    sd["std"] = v.std;
    sd["sem"] = v.sem;
    sd["min"] = v.min;
    sd["max"] = v.max;
    d[s.name] = sd;
  }
  py::dict counts;
  counts["exited"] = r.exited;
  counts["rest"] = r.rest;
  counts["trapped"] = r.trapped;
  d["status_counts"] = counts;
  d["total_collisions"] = r.total_collisions;
  if (per_sample) {
    const auto& ps = r.per_sample;
    const std::size_t n = ps.size();
    py::dict s;
    s["release"] = column<double>(n, [&](std::size_t i) { return ps[i].fraction; });
    s["status"] = text_column(n, [&](std::size_t i) { return funnel::to_string(ps[i].trajectory.status); });
    s["duration"] = column<double>(n, [&](std::size_t i) { return ps[i].trajectory.duration; });
    s["impulse"] = column<double>(n, [&](std::size_t i) { return ps[i].trajectory.impulse; });
    s["normal_impulse"] = column<double>(n, [&](std::size_t i) { return ps[i].trajectory.normal_impulse; });
    s["energy_loss"] = column<double>(n, [&](std::size_t i) { return ps[i].trajectory.energy_loss; });
    s["collisions"] = column<std::int64_t>(n, [&](std::size_t i) { return ps[i].trajectory.collisions; });
    s["edge_collisions"] = column<std::int64_t>(n, [&](std::size_t i) { return ps[i].trajectory.edge_collisions; });
    s["face_collisions"] = column<std::int64_t>(
        n, [&](std::size_t i) { return ps[i].trajectory.collisions - ps[i].trajectory.edge_collisions; });
    s["contacts"] = column<std::int64_t>(n, [&](std::size_t i) { return ps[i].trajectory.contacts; });
    s["contact_time"] = column<double>(n, [&](std::size_t i) { return ps[i].trajectory.contact_time; });
    d["per_sample"] = s;
  }
  return d;
}

/// One ensemble per grid point. `axes` holds (python name, values) in any order; the grid uses
/// the library's axis order (funnel::sweep_parameter_names()), as `funnel sweep` does.
py::dict sweep(const std::vector<std::pair<std::string, std::vector<double>>>& axes_in, std::int64_t samples,
               const std::string& dist, int threads) {
  std::vector<funnel::Axis> axes;
  for (const std::string& name : funnel::sweep_parameter_names()) {
    for (const auto& [key, values] : axes_in) {
      if (library_name(key) != name) continue;
      if (values.empty()) {
        throw py::value_error("invalid " + name + ": no values; valid range is " +
                              std::string(funnel::valid_range(name)));
      }
      axes.push_back({name, values});
    }
  }
  for (const auto& [key, values] : axes_in) {
    bool known = false;
    for (const auto& a : axes) known = known || a.name == library_name(key);
    if (!known) throw py::type_error("unknown model parameter '" + key + "'");
  }
  // Each value must be settable (max-collisions integral) and every point valid, before any work.
  for (const auto& a : axes) {
    for (const double v : a.values) {
      Params probe = funnel::default_params();
      if (!funnel::set_parameter(probe, a.name, v)) {
        throw py::value_error(funnel::ParamError{a.name, number_text(v),
                                                 std::string(funnel::valid_range(a.name))}.message());
      }
    }
  }
  const std::vector<Params> points = funnel::expand_grid(funnel::default_params(), axes);
  for (const Params& p : points) {
    if (const auto err = funnel::validate(p)) throw py::value_error(err->message());
  }
  const funnel::EnsembleOptions options = ensemble_options(samples, dist, threads);
  std::vector<funnel::EnsembleResult> results;
  {
    py::gil_scoped_release nogil;
    results = funnel::run_sweep(points, options);
  }

  const std::size_t n = points.size();
  py::dict d;  // the CSV columns of `funnel sweep`, in order
  d["theta"] = column<double>(n, [&](std::size_t i) { return points[i].theta; });
  d["e"] = column<double>(n, [&](std::size_t i) { return points[i].e; });
  d["mu"] = column<double>(n, [&](std::size_t i) { return points[i].mu; });
  d["beta0"] = column<double>(n, [&](std::size_t i) { return points[i].beta0; });
  d["radius"] = column<double>(n, [&](std::size_t i) { return points[i].radius; });
  d["gap"] = column<double>(n, [&](std::size_t i) { return points[i].gap; });
  d["inertia"] = column<double>(n, [&](std::size_t i) { return points[i].inertia; });
  d["t_max"] = column<double>(n, [&](std::size_t i) { return points[i].t_max; });
  d["max_collisions"] = column<std::int64_t>(n, [&](std::size_t i) { return points[i].max_collisions; });
  d["release_dist"] = text_column(n, [&](std::size_t) { return funnel::to_string(options.dist); });
  d["samples"] = column<std::int64_t>(n, [&](std::size_t i) { return results[i].samples; });
  for (const auto& s : summaries) {
    const std::string base = s.name;
    d[py::str(base + "_mean")] = column<double>(n, [&](std::size_t i) { return (results[i].*(s.member)).mean; });
    d[py::str(base + "_std")] = column<double>(n, [&](std::size_t i) { return (results[i].*(s.member)).std; });
    d[py::str(base + "_sem")] = column<double>(n, [&](std::size_t i) { return (results[i].*(s.member)).sem; });
    d[py::str(base + "_min")] = column<double>(n, [&](std::size_t i) { return (results[i].*(s.member)).min; });
    d[py::str(base + "_max")] = column<double>(n, [&](std::size_t i) { return (results[i].*(s.member)).max; });
  }
  d["exited"] = column<std::int64_t>(n, [&](std::size_t i) { return results[i].exited; });
  d["rest"] = column<std::int64_t>(n, [&](std::size_t i) { return results[i].rest; });
  d["trapped"] = column<std::int64_t>(n, [&](std::size_t i) { return results[i].trapped; });
  d["total_collisions"] = column<std::int64_t>(n, [&](std::size_t i) { return results[i].total_collisions; });
  return d;
}

py::dict geometry(const std::map<std::string, double>& model) {
  const Params params = make_params(model);
  const funnel::Geometry g = funnel::make_geometry(params);
  py::dict d;
  d["theta"] = params.theta;
  d["sin_t"] = g.sin_t;
  d["cos_t"] = g.cos_t;
  d["tan_t"] = g.tan_t;
  d["radius"] = g.radius;
  d["half_gap"] = g.half_gap;
  d["closed"] = g.closed;
  d["y_bottom"] = g.y_bottom;
  d["y_release"] = g.y_release;
  d["half_width"] = g.half_width;
  d["y_face_end"] = g.y_face_end;
  d["x_face_end"] = g.x_face_end;
  return d;
}

/// Values of a list "a,b,c", a range "start:stop:step" or one number, for the parameter `key`;
/// ValueError with the CLI's message otherwise.
std::vector<double> parse_values(const std::string& key, const std::string& text) {
  const std::string name = library_name(key);
  std::string reason;
  auto values = funnel::parse_values(text, reason);
  if (!values) {
    throw py::value_error("invalid " + name + " = '" + text + "': " + reason + "; valid range is " +
                          std::string(funnel::valid_range(name)));
  }
  return *values;
}

py::dict default_params() { return params_dict(funnel::default_params()); }

/// Eigenvalues and stability of the period-2 orbit for each theta (paper Sec. IV, Fig. 10).
py::dict orbit(const std::vector<double>& thetas, double beta0, double inertia, double radius, double y_star) {
  if (!(y_star > 0.0)) throw py::value_error("invalid y-star = " + number_text(y_star) + ": valid range is y-star > 0");
  std::vector<funnel::orbit::OrbitAnalysis> out;
  for (const double theta : thetas) {
    make_params({{"theta", theta}, {"beta0", beta0}, {"inertia", inertia}, {"radius", radius}});  // validates
    out.push_back(funnel::orbit::analyse({theta, beta0, inertia, radius}, y_star));
  }
  const auto n = static_cast<py::ssize_t>(out.size());
  py::array_t<std::complex<double>> eig({n, py::ssize_t{4}});
  py::array_t<double> mod({n, py::ssize_t{4}});
  auto e = eig.mutable_unchecked<2>();
  auto m = mod.mutable_unchecked<2>();
  for (py::ssize_t i = 0; i < n; ++i) {
    for (py::ssize_t k = 0; k < 4; ++k) {
      e(i, k) = out[static_cast<std::size_t>(i)].eigenvalues[k];
      m(i, k) = std::abs(e(i, k));
    }
  }
  py::dict d;
  d["theta"] = py::array_t<double>(n, thetas.data());
  d["eigenvalues"] = eig;
  d["modulus"] = mod;
  d["stable"] = column<bool>(out.size(), [&](std::size_t i) { return out[i].stable; });
  d["jacobian_max_rel_diff"] = column<double>(out.size(), [&](std::size_t i) { return out[i].jacobian_max_rel_diff; });
  return d;
}

/// Final state of each release in a closed funnel (Figs. 11, 12).
py::dict closed(const std::map<std::string, double>& model, std::int64_t samples, const std::string& release_dist,
                int threads, double max_time, std::int64_t max_coll, int window, double slip_tol, double height_tol) {
  std::map<std::string, double> m = model;
  if (const auto it = m.find("gap"); it != m.end() && it->second != 0.0) {
    throw py::value_error("invalid gap = " + number_text(it->second) + ": closed() needs gap = 0 (the default here)");
  }
  m["gap"] = 0.0;
  const Params params = make_params(m);
  const auto dist = funnel::parse_release_dist(release_dist);
  if (!dist) throw py::value_error("invalid release-dist = '" + release_dist + "': valid values are line, disk");
  if (samples < 1) throw py::value_error("invalid samples = " + std::to_string(samples) + ": valid range is samples >= 1");
  if (!(max_time > 0.0) || max_coll < 1 || window < 1 || !(slip_tol > 0.0) || !(height_tol > 0.0)) {
    throw py::value_error("invalid closed() options: need max_time > 0, max_coll >= 1, window >= 1, slip_tol > 0, height_tol > 0");
  }
  funnel::ClosedOptions opt;
  opt.max_time = max_time;
  opt.max_collisions = max_coll;
  opt.window = window;
  opt.slip_tol = slip_tol;
  opt.height_tol = height_tol;
  funnel::ClosedResult r;
  {
    py::gil_scoped_release release;
    r = funnel::run_closed(params, {samples, *dist, threads, false}, opt);
  }
  const double L = funnel::make_geometry(params).half_width;
  const std::size_t n = r.samples.size();
  py::dict d;
  d["params"] = params_dict(params);
  d["periodic_fraction"] = r.periodic_fraction;
  d["state_counts"] = py::dict(py::arg("periodic") = r.periodic, py::arg("rest") = r.rest, py::arg("undecided") = r.undecided);
  d["release"] = column<double>(n, [&](std::size_t i) { return r.samples[i].fraction; });
  py::list states;
  for (const auto& s : r.samples) states.append(std::string(funnel::to_string(s.state)));
  d["state"] = states;
  d["x_last_over_L"] = column<double>(n, [&](std::size_t i) { return r.samples[i].x_last / L; });
  d["x_prev_over_L"] = column<double>(n, [&](std::size_t i) { return r.samples[i].x_prev / L; });
  d["y_last"] = column<double>(n, [&](std::size_t i) { return r.samples[i].y_last; });
  d["y_prev"] = column<double>(n, [&](std::size_t i) { return r.samples[i].y_prev; });
  d["collisions"] = column<std::int64_t>(n, [&](std::size_t i) { return r.samples[i].collisions; });
  d["time"] = column<double>(n, [&](std::size_t i) { return r.samples[i].time; });
  return d;
}

}  // namespace

void bind_retrace(py::module_& m);  // bind_retrace.cpp

PYBIND11_MODULE(_funnel, m) {
  m.doc() = "Compiled core of funnel (pybind11). Use the documented wrappers in the `funnel` package.";
  m.def("simulate", &simulate, py::arg("model"), py::arg("release"), py::arg("events"));
  m.def("ensemble", &ensemble, py::arg("model"), py::arg("samples"), py::arg("release_dist"), py::arg("threads"),
        py::arg("per_sample"));
  m.def("sweep", &sweep, py::arg("axes"), py::arg("samples"), py::arg("release_dist"), py::arg("threads"));
  m.def("geometry", &geometry, py::arg("model"));
  m.def("parse_values", &parse_values, py::arg("name"), py::arg("text"));
  m.def("default_params", &default_params);
  m.def("valid_range", [](const std::string& name) { return std::string(funnel::valid_range(library_name(name))); },
        py::arg("name"));
  m.def("sweep_parameter_names", [] {
    std::vector<std::string> names;
    for (std::string n : funnel::sweep_parameter_names()) {
      for (char& c : n) {
        if (c == '-') c = '_';
      }
      names.push_back(n);
    }
    return names;
  });
  m.def("version", [] { return std::string(funnel::version()); });
  m.def("git_commit", [] { return std::string(funnel::git_commit()); });
  m.attr("default_samples") = funnel::default_samples;

  m.def("orbit", &orbit, py::arg("thetas"), py::arg("beta0"), py::arg("inertia"), py::arg("radius"), py::arg("y_star"));
  m.def("closed", &closed, py::arg("model"), py::arg("samples"), py::arg("release_dist"), py::arg("threads"),
        py::arg("max_time"), py::arg("max_coll"), py::arg("window"), py::arg("slip_tol"), py::arg("height_tol"));
  bind_retrace(m);
}
