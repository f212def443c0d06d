// pybind11 bindings of the funnel library: parameters in as dicts, results out as dicts and numpy arrays.
// The documented Python API is python/funnel/_api.py; this layer only converts and validates.
#include <pybind11/complex.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <charconv>
#include <cmath>
#include <complex>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "funnel/closed.hpp"
#include "funnel/engine.hpp"
#include "funnel/ensemble.hpp"
#include "funnel/funnel.hpp"
#include "funnel/geometry.hpp"
#include "funnel/grid.hpp"
#include "funnel/observables.hpp"
#include "funnel/simd.hpp"
#include "funnel/wear.hpp"
#include "convert.hpp"
#include "funnel/orbit.hpp"
#include "funnel/params.hpp"
#include "funnel/version.hpp"

namespace py = pybind11;

namespace {

using funnel::Params;
using funnel::py_convert::add_param_columns;
using funnel::py_convert::check_sweep_axes;
using funnel::py_convert::column;
using funnel::py_convert::params_dict;
using funnel::py_convert::run_interruptible;
using funnel::py_convert::text_column;

/// Python keyword (t_max) to the library's parameter name (t-max).
std::string library_name(std::string name) {
  for (char& c : name) {
    if (c == '_') c = '-';
  }
  return name;
}

/// True for Python's and numpy's bools (numpy's type looked up once; the handle is kept for the
/// interpreter's life).
bool is_bool(const py::handle& h) {
  static const py::handle numpy_bool = py::object(py::module_::import("numpy").attr("bool_")).release();
  return py::isinstance<py::bool_>(h) || py::isinstance(h, numpy_bool);
}

/// "invalid geometry KEY = VALUE: valid range is RANGE", the value as Python shows it (cut to
/// 60 characters), as every other error names the parameter, its value and the valid range.
py::value_error geometry_error(const std::string& key, const py::handle& value, const std::string& range) {
  std::string shown = py::str(py::repr(value));
  if (shown.size() > 60) shown = shown.substr(0, 57) + "...";
  return py::value_error("invalid geometry " + key + " = " + shown + ": valid range is " + range);
}

/// A number of a geometry dict; ValueError naming the key otherwise.
double geometry_number(const py::handle& h, const std::string& key) {
  // Any real number: Python's, or numpy's scalars (np.float32(0.1), np.int64(1)) and 0-d arrays
  // of reals (np.array(0.3), as the model's parameters take them), not a bool.
  static const py::handle numbers_real = py::object(py::module_::import("numbers").attr("Real")).release();
  static const py::handle ndarray = py::object(py::module_::import("numpy").attr("ndarray")).release();
  py::object v = py::reinterpret_borrow<py::object>(h);
  if (py::isinstance(v, ndarray) && v.attr("ndim").cast<int>() == 0 &&
      std::string_view("iuf").find(py::str(v.attr("dtype").attr("kind")).cast<std::string>()) != std::string_view::npos) {
    v = v.attr("item")();
  }
  if (is_bool(v) || !py::isinstance(v, numbers_real)) throw geometry_error(key, h, "a number");
  return py::float_(v).cast<double>();
}

/// The vertices [[x, y], ...] of one side of a geometry dict.
std::vector<funnel::Vec2> geometry_vertices(const py::handle& h, const std::string& key) {
  std::vector<funnel::Vec2> out;
  if (!py::isinstance<py::sequence>(h) || py::isinstance<py::str>(h)) {
    throw geometry_error(key, h, "a list of [x, y] pairs of numbers");
  }
  std::size_t k = 0;
  for (const py::handle item : h) {
    const std::string at = key + "[" + std::to_string(k++) + "]";
    if (!py::isinstance<py::sequence>(item) || py::isinstance<py::str>(item) || py::len(item) != 2) {
      throw geometry_error(at, item, "a pair [x, y] of numbers");
    }
    const py::sequence pair = py::reinterpret_borrow<py::sequence>(item);
    out.push_back({geometry_number(pair[0], at), geometry_number(pair[1], at)});
  }
  return out;
}

/// A profile from a geometry dict laid out as the CLI's TOML file (docs/cli.md, "Geometry
/// files"): {"left": {"vertices": [...], "e", "mu", "beta0"}, "right": {...}, "mirror", "bottom"};
/// None for the V.
std::shared_ptr<const funnel::ProfileSpec> profile_of(const py::object& geometry) {
  if (geometry.is_none()) return nullptr;
  if (!py::isinstance<py::dict>(geometry)) throw py::type_error("geometry must be a dict, a path or None");
  const py::dict g = geometry.cast<py::dict>();
  for (const auto& [k, v] : g) {
    const std::string key = py::str(k);
    if (key != "left" && key != "right" && key != "mirror" && key != "bottom" && key != "source") {
      throw py::value_error("invalid geometry: unknown key '" + key + "' (left, right, mirror, bottom, source)");
    }
  }
  auto side_of = [](const py::dict& g, const char* name) -> std::optional<funnel::WallSpec> {
    if (!g.contains(name)) return std::nullopt;
    const py::object o = g[name];
    if (!py::isinstance<py::dict>(o)) throw geometry_error(name, o, "a dict {\"vertices\": [[x, y], ...], and e, mu, beta0 if the wall has its own}");
    funnel::WallSpec s;
    for (const auto& [k, v] : o.cast<py::dict>()) {
      const std::string key = py::str(k);
      const std::string at = std::string(name) + "." + key;
      if (key == "vertices") {
        s.vertices = geometry_vertices(v, at);
      } else if (key == "e" || key == "mu" || key == "beta0") {
        (key == "e" ? s.e : key == "mu" ? s.mu : s.beta0) = geometry_number(v, at);
      } else {
        throw py::value_error("invalid geometry: unknown key '" + at + "' (vertices, e, mu, beta0)");
      }
    }
    return s;
  };
  const std::optional<funnel::WallSpec> left = side_of(g, "left"), right = side_of(g, "right");
  bool mirror = false;
  if (g.contains("mirror")) {
    // true or false only, as in a geometry file (a string or a number was a cast error, or true).
    const py::object m = g["mirror"];
    if (!is_bool(m)) {
      throw py::value_error("invalid geometry mirror = " + std::string(py::str(py::repr(m))) + ": valid values are true, false");
    }
    mirror = m.cast<bool>();
  }
  auto spec = std::make_shared<funnel::ProfileSpec>();
  try {
    *spec = funnel::assemble_profile(left, right, mirror);
  } catch (const std::invalid_argument& err) {
    throw py::value_error(std::string("invalid geometry: ") + err.what());
  }
  if (g.contains("bottom")) spec->bottom = geometry_number(g["bottom"], "bottom");
  spec->source = g.contains("source") ? std::string(py::str(g["source"])) : std::string("profile");
  return spec;
}

/// The parameters' defaults overridden by `model` ({python name: float}) on the funnel of
/// `geometry` (a dict, or None for the V), validated. Throws ValueError with
/// funnel::ParamError::message() for an invalid set.
Params make_params(const std::map<std::string, double>& model, const py::object& geometry = py::none()) {
  Params p = funnel::default_params();
  p.profile = profile_of(geometry);
  std::vector<funnel::GivenParameter> given;
  for (const auto& [key, value] : model) {
    const funnel::ParameterInfo* info = funnel::find_parameter(key);
    if (info == nullptr || !info->option) throw py::type_error("unknown model parameter '" + key + "'");
    given.push_back({key, funnel::format_number(value)});
  }
  if (const auto err = funnel::unused_given(given, p.profile.get())) throw py::value_error(err->message());
  for (const auto& [key, value] : model) {
    const funnel::ParameterInfo* info = funnel::find_parameter(key);
    if (const auto err = funnel::set_parameter_checked(p, info->name, value)) throw py::value_error(err->message());
  }
  if (const auto err = funnel::validate(p, funnel::Space::TwoD)) throw py::value_error(err->message());
  return p;
}

/// The funnel of a run, as the CLI's JSON "geometry": source, closed, symmetric, exit level,
/// the height the release is measured from, release line, the walls' surfaces (top down) and each wall's material.
py::dict geometry_record(const Params& params) {
  const funnel::Funnel f = funnel::make_funnel(params);
  py::dict d, walls, materials;
  d["source"] = f.source;
  d["closed"] = f.closed;
  d["symmetric"] = f.symmetric;
  d["y_exit"] = f.y_exit;
  d["bottom"] = f.y_bottom;
  d["y_release"] = f.y_release;
  d["x_release_mid"] = f.x_release_mid;
  d["half_width"] = f.half_width;
  for (const int i : {0, 1}) {
    const char* side = i == 0 ? "left" : "right";
    py::list w;
    for (const funnel::Vec2 v : funnel::wall_surface(f, i, funnel::drawing_top(f))) {
      py::list point;
      point.append(v.x);
      point.append(v.y);
      w.append(point);
    }
    walls[side] = w;
    const funnel::Material& m = f.sides[i].material;
    py::dict mat;
    mat["e"] = m.e;
    mat["mu"] = m.mu;
    mat["beta0"] = m.beta0;
    materials[side] = mat;
  }
  d["walls"] = walls;
  d["materials"] = materials;
  return d;
}


/// A Python number for an observable's value: int for counts, None where undefined (NaN).
py::object observable_value(const funnel::ObservableInfo& o, double v) {
  if (std::isnan(v)) return py::none();
  if (o.count) return py::int_(static_cast<std::int64_t>(v));
  return py::float_(v);
}

/// Observables of one trajectory: the CLI's keys from "status" on.
void put_trajectory(py::dict& d, const funnel::Trajectory& t) {
  d["status"] = std::string(funnel::to_string(t.status));
  for (const funnel::ObservableInfo& o : funnel::observables()) {
    d[py::str(std::string(o.name))] = observable_value(o, funnel::value(t, o.id));
  }
}

/// The wear record: per wall numpy arrays s, collisions, normal_impulse, impulse and the edge's
/// totals, as the CLI's "wear".
py::dict wear_dict(const funnel::Wear& w) {
  py::dict d;
  for (const funnel::Wall wall : {funnel::Wall::Left, funnel::Wall::Right}) {
    const funnel::WallWear& ww = w[wall];
    const auto n = static_cast<std::size_t>(w.bins);
    py::dict side;
    const double width = w.widths[wall == funnel::Wall::Left ? 0 : 1];  // each wall's own bins
    side["s"] = column<double>(n, [&](std::size_t k) { return (static_cast<double>(k) + 0.5) * width; });
    side["bin_width"] = width;
    side["collisions"] = column<double>(n, [&](std::size_t k) { return ww.collisions[k]; });
    side["normal_impulse"] = column<double>(n, [&](std::size_t k) { return ww.normal_impulse[k]; });
    side["impulse"] = column<double>(n, [&](std::size_t k) { return ww.impulse[k]; });
    py::dict edge;
    edge["collisions"] = ww.edge_collisions;
    edge["normal_impulse"] = ww.edge_normal_impulse;
    edge["impulse"] = ww.edge_impulse;
    side["edge"] = edge;
    d[py::str(std::string(funnel::to_string(wall)))] = side;
  }
  d["bin_width"] = w.width(funnel::Wall::Left);  // (kept from before each wall had its own)
  return d;
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

/// The statistics of an observable as the CLI reports them (None throughout where no sample
/// defines it, e.g. exit observables when nothing exited).
py::dict summary_dict(const funnel::EnsembleResult& r, const funnel::ObservableInfo& o) {
  const funnel::Summary& v = r[o.id];
  const bool undefined = o.exited_only && r.exited == 0;
  py::dict sd;
  for (const auto& [name, x] : {std::pair<const char*, double>{"mean", v.mean}, {"std", v.std}, {"sem", v.sem},
                                {"min", v.min}, {"max", v.max}}) {
    sd[name] = undefined ? py::object(py::none()) : py::object(py::float_(x));
  }
  return sd;
}

/// Ensemble options from the Python arguments, validated by the library.
funnel::EnsembleOptions ensemble_options(std::int64_t samples, const std::string& dist, int threads,
                                         std::uint64_t seed, double release, double release_sd, double velocity_sd,
                                         int wear_bins) {
  funnel::EnsembleOptions o;
  const auto d = funnel::parse_release_dist(dist);
  if (!d) throw py::value_error("invalid release_dist = '" + dist + "': valid values are line, disk, uniform, gaussian");
  o.samples = samples;
  o.dist = *d;
  o.threads = threads;
  o.seed = seed;
  o.release_mean = release;
  o.release_sd = release_sd;
  o.velocity_sd = velocity_sd;
  o.wear_bins = wear_bins;
  if (const auto err = funnel::validate(o)) throw py::value_error(err->message());
  return o;
}

/// The release distribution of a run into `d`: release_dist, the seed of random releases, and
/// for gaussian ones the mean (under `mean_key`) and release_sd.
void put_releases(py::dict& d, const funnel::EnsembleOptions& options, const char* mean_key) {
  d["release_dist"] = std::string(funnel::to_string(options.dist));
  if (funnel::is_random(options)) d["seed"] = options.seed;
  if (options.dist == funnel::ReleaseDist::Gaussian) {
    d[mean_key] = options.release_mean;
    d["release_sd"] = options.release_sd;
  }
}

// ---------------------------------------------------------------------------------------------
// Module functions

py::dict simulate(const std::map<std::string, double>& model, double release, bool events, int wear_bins,
                  const py::object& geometry) {
  const Params params = make_params(model, geometry);
  if (!(release > -1.0 && release < 1.0)) {
    throw py::value_error("invalid release = " + funnel::format_number(release) +
                          ": valid range is -1 < release < 1 (x0/L)");
  }
  funnel::EnsembleOptions check;
  check.wear_bins = wear_bins;
  if (const auto err = funnel::validate(check)) throw py::value_error(err->message());
  const funnel::Funnel g = funnel::make_funnel(params);
  funnel::EventLog log;
  funnel::Wear wear = funnel::Wear::make(g, wear_bins);
  funnel::Trajectory t;
  funnel::py_convert::InterruptSink<funnel::EventSink, funnel::Event> sink(events ? &log : nullptr);
  {
    py::gil_scoped_release nogil;
    t = funnel::simulate_release(params, g, release, &sink, wear_bins > 0 ? &wear : nullptr);
  }
  sink.raise_if_interrupted();
  py::dict d;
  d["params"] = params_dict(params);
  d["geometry"] = geometry_record(params);
  d["release"] = release;
  d["x0"] = funnel::release_point(g, release).x;
  d["y0"] = g.y_release;
  d["u0"] = params.release_u;
  d["v0"] = params.release_v;
  d["omega0"] = params.release_spin;
  put_trajectory(d, t);
  if (wear_bins > 0) d["wear"] = wear_dict(wear);
  if (events) d["events"] = events_dict(log.events);
  d["_capped"] = t.capped;  // not a CLI key: for funnel.simulate's CappedWarning, which removes it
  return d;
}

py::dict ensemble(const std::map<std::string, double>& model, std::int64_t samples, const std::string& dist,
                  int threads, bool per_sample, std::uint64_t seed, double release, double release_sd,
                  double velocity_sd, int wear_bins, const py::object& progress, const py::object& geometry) {
  const Params params = make_params(model, geometry);
  funnel::EnsembleOptions options =
      ensemble_options(samples, dist, threads, seed, release, release_sd, velocity_sd, wear_bins);
  options.keep_samples = per_sample;
  if (const auto err = funnel::validate(params, options)) throw py::value_error(err->message());
  funnel::EnsembleResult r;
  run_interruptible(options, progress, [&](const funnel::Progress& report) {
    r = funnel::run_ensemble(params, options, report);
  });
  py::dict d;
  d["params"] = params_dict(params);
  d["geometry"] = geometry_record(params);
  put_releases(d, options, "release");
  d["velocity_sd"] = options.velocity_sd;
  d["samples"] = r.samples;
  for (const funnel::ObservableInfo& o : funnel::observables()) {
    if (o.summarized) d[py::str(std::string(o.name))] = summary_dict(r, o);
  }
  py::dict counts;
  counts["exited"] = r.exited;
  counts["rest"] = r.rest;
  counts["trapped"] = r.trapped;
  d["status_counts"] = counts;
  d["stalled"] = r.stalled;
  d["capped"] = r.capped;
  d["total_collisions"] = r.total_collisions;
  d["simulated_collisions"] = r.simulated_collisions;
  if (wear_bins > 0) d["wear"] = wear_dict(r.wear);
  if (per_sample) {
    const auto& ps = r.per_sample;
    const std::size_t n = ps.size();
    py::dict s;
    s["release"] = column<double>(n, [&](std::size_t i) { return ps[i].fraction; });
    s["u0"] = column<double>(n, [&](std::size_t i) { return ps[i].release.v.x; });
    s["v0"] = column<double>(n, [&](std::size_t i) { return ps[i].release.v.y; });
    s["status"] = text_column(n, [&](std::size_t i) { return funnel::to_string(ps[i].trajectory.status); });
    for (const funnel::ObservableInfo& o : funnel::observables()) {
      if (o.count) {
        s[py::str(std::string(o.name))] = column<std::int64_t>(
            n, [&](std::size_t i) { return static_cast<std::int64_t>(funnel::value(ps[i].trajectory, o.id)); });
      } else {
        s[py::str(std::string(o.name))] =
            column<double>(n, [&](std::size_t i) { return funnel::value(ps[i].trajectory, o.id); });
      }
    }
    d["per_sample"] = s;
  }
  return d;
}

/// One ensemble per grid point. `axes` holds (python name, values) in any order; the grid uses
/// the library's axis order (funnel::sweep_parameter_names()), as `funnel sweep` does.
py::dict sweep(const std::vector<std::pair<std::string, std::vector<double>>>& axes_in, std::int64_t samples,
               const std::string& dist, int threads, std::uint64_t seed, double release, double release_sd,
               double velocity_sd, const py::object& progress, const py::object& geometry) {
  const Params base = make_params({}, geometry);
  std::vector<funnel::Axis> axes;
  std::vector<funnel::GivenParameter> given;  // each axis given, named by its first value
  for (const auto& [key, values] : axes_in) {
    if (!values.empty()) given.push_back({key, funnel::format_number(values.front())});
  }
  if (const auto err = funnel::unused_given(given, base.profile.get())) throw py::value_error(err->message());
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
  check_sweep_axes(axes);
  const std::vector<Params> points = funnel::expand_grid(base, axes);
  funnel::EnsembleOptions options = ensemble_options(samples, dist, threads, seed, release, release_sd, velocity_sd, 0);
  for (const Params& p : points) {
    if (auto err = funnel::validate(p); err || (err = funnel::validate(p, options))) throw py::value_error(err->message());
  }
  std::vector<funnel::EnsembleResult> results;
  run_interruptible(options, progress, [&](const funnel::Progress& report) {
    results = funnel::run_sweep(points, options, report);
  });

  const std::size_t n = points.size();
  py::dict d;  // the CSV columns of `funnel sweep`, in order
  add_param_columns(d, points, funnel::Space::TwoD);
  d["release_dist"] = text_column(n, [&](std::size_t) { return funnel::to_string(options.dist); });
  d["samples"] = column<std::int64_t>(n, [&](std::size_t i) { return results[i].samples; });
  for (const funnel::ObservableInfo& o : funnel::observables()) {
    if (!o.summarized) continue;
    const std::string base(o.name);
    const auto stat = [&](std::size_t i, double funnel::Summary::*member) {
      return o.exited_only && results[i].exited == 0 ? std::nan("") : results[i][o.id].*member;
    };
    d[py::str(base + "_mean")] = column<double>(n, [&](std::size_t i) { return stat(i, &funnel::Summary::mean); });
    d[py::str(base + "_std")] = column<double>(n, [&](std::size_t i) { return stat(i, &funnel::Summary::std); });
    d[py::str(base + "_sem")] = column<double>(n, [&](std::size_t i) { return stat(i, &funnel::Summary::sem); });
    d[py::str(base + "_min")] = column<double>(n, [&](std::size_t i) { return stat(i, &funnel::Summary::min); });
    d[py::str(base + "_max")] = column<double>(n, [&](std::size_t i) { return stat(i, &funnel::Summary::max); });
  }
  d["exited"] = column<std::int64_t>(n, [&](std::size_t i) { return results[i].exited; });
  d["rest"] = column<std::int64_t>(n, [&](std::size_t i) { return results[i].rest; });
  d["trapped"] = column<std::int64_t>(n, [&](std::size_t i) { return results[i].trapped; });
  d["total_collisions"] = column<std::int64_t>(n, [&](std::size_t i) { return results[i].total_collisions; });
  // Not a CSV column: the runs the collision cap ended, for funnel.sweep's CappedWarning (which
  // removes the key).
  std::int64_t capped = 0;
  for (const funnel::EnsembleResult& r : results) capped += r.capped;
  d["_capped"] = capped;
  return d;
}

/// The parameter table: one dict per parameter (name, key, meaning, unit, range, default, integer, option).
py::list parameter_table() {
  py::list l;
  for (const funnel::ParameterInfo& p : funnel::parameters()) {
    py::dict d;
    d["name"] = std::string(p.name);
    d["key"] = p.key();
    d["meaning"] = std::string(p.meaning);
    d["unit"] = std::string(p.unit);
    d["range"] = std::string(p.range);
    d["default"] = p.get(funnel::default_params());
    d["integer"] = p.integer;
    d["option"] = p.option;
    l.append(d);
  }
  return l;
}

/// The observable table: one dict per observable (name, meaning, unit, count, exited_only, summarized).
py::list observable_table() {
  py::list l;
  for (const funnel::ObservableInfo& o : funnel::observables()) {
    py::dict d;
    d["name"] = std::string(o.name);
    d["meaning"] = std::string(o.meaning);
    d["unit"] = std::string(o.unit);
    d["count"] = o.count;
    d["exited_only"] = o.exited_only;
    d["summarized"] = o.summarized;
    l.append(d);
  }
  return l;
}

py::dict geometry(const std::map<std::string, double>& model, const py::object& profile) {
  const Params params = make_params(model, profile);
  // A V whose two wall angles are set equal is the symmetric V of that angle: its theta, sines
  // and edge height are that angle's (they were theta's, and a 45-degree V was drawn at 60).
  Params v = params;
  if (!v.profile && v.left_angle() == v.right_angle()) {
    v.theta = v.left_angle();
    v.theta_left = v.theta_right = Params::unset;
  }
  const funnel::Geometry g = funnel::make_geometry(v);
  py::dict d;
  d["theta"] = v.theta;
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
  // Any funnel: its walls' surfaces, the exit level, the release line's middle (the V: 0).
  for (const auto& [k, v] : geometry_record(params)) d[k] = v;
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
  if (!(y_star > 0.0 && std::isfinite(y_star))) {
    throw py::value_error("invalid y-star = " + funnel::format_number(y_star) + ": valid range is y-star > 0 (finite)");
  }
  std::vector<funnel::orbit::OrbitAnalysis> out;
  for (const double theta : thetas) {
    Params p = funnel::default_params();
    p.theta = theta;
    p.beta0 = beta0;
    p.inertia = inertia;
    p.radius = radius;
    if (const auto err = funnel::validate_orbit(p)) throw py::value_error(err->message());
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
                int threads, double max_time, std::int64_t max_coll, int window, double slip_tol, double height_tol,
                std::uint64_t seed, double release, double release_sd, const py::object& geometry) {
  std::map<std::string, double> m = model;
  if (const auto it = m.find("gap"); it != m.end() && it->second != 0.0) {
    throw py::value_error("invalid gap = " + funnel::format_number(it->second) + ": closed() needs gap = 0 (the default here)");
  }
  if (geometry.is_none()) m["gap"] = 0.0;  // a geometry's own walls must close (below)
  Params params = make_params(m, geometry);
  // e = 1 where not given, as in the paper's Figs. 11 and 12 (a default, so not refused with a
  // geometry whose walls all set their own e: it then changes nothing).
  if (!m.contains("e")) params.e = 1.0;
  if (params.profile && !funnel::make_funnel(params).closed) {
    throw py::value_error("invalid geometry: closed() needs a closed funnel (the two walls' lower ends at one point)");
  }
  if (samples < 1) throw py::value_error("invalid samples = " + std::to_string(samples) + ": valid range is samples >= 1");
  funnel::EnsembleOptions ensemble = ensemble_options(samples, release_dist, threads, seed, release, release_sd, 0.0, 0);
  const auto check = [](bool ok, const char* name, double value, const char* range) {
    if (!ok) throw py::value_error(std::string("invalid ") + name + " = " + funnel::format_number(value) + ": valid range is " + range);
  };
  check(max_time > 0.0 && std::isfinite(max_time), "max_time", max_time, "max_time > 0 (finite)");
  check(max_coll >= 1, "max_coll", static_cast<double>(max_coll), "an integer max_coll >= 1");
  check(window >= 1 && window <= 1000000, "window", window, "an integer 1 <= window <= 10^6");
  check(slip_tol > 0.0 && std::isfinite(slip_tol), "slip_tol", slip_tol, "slip_tol > 0 (finite)");
  check(height_tol > 0.0 && std::isfinite(height_tol), "height_tol", height_tol, "height_tol > 0 (finite)");
  // The caps are the run's t_max and max_collisions, and its params say so (as funnel closed's).
  params.t_max = max_time;
  params.max_collisions = max_coll;
  if (const auto err = funnel::validate(params)) throw py::value_error(err->message());  // e.g. max_time = inf
  if (const auto err = funnel::validate(params, ensemble)) throw py::value_error(err->message());
  funnel::ClosedOptions opt;
  opt.max_time = max_time;
  opt.max_collisions = max_coll;
  opt.window = window;
  opt.slip_tol = slip_tol;
  opt.height_tol = height_tol;
  funnel::ClosedResult r;
  run_interruptible(ensemble, py::none(), [&](const funnel::Progress&) { r = funnel::run_closed(params, ensemble, opt); });
  const double L = funnel::make_geometry(params).half_width;
  const std::size_t n = r.samples.size();
  py::dict d;
  d["params"] = params_dict(params);
  d["geometry"] = geometry_record(params);
  put_releases(d, ensemble, "release_mean");  // "release" is the column of the releases
  d["samples"] = ensemble.samples;
  d["options"] = py::dict(py::arg("max_time") = opt.max_time, py::arg("max_collisions") = opt.max_collisions,
                          py::arg("window") = opt.window, py::arg("slip_tol") = opt.slip_tol,
                          py::arg("height_tol") = opt.height_tol);
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
void bind_3d(py::module_& m);       // bind_3d.cpp
void bind_paper(py::module_& m);    // bind_paper.cpp

PYBIND11_MODULE(_funnel, m) {
  m.doc() = "Compiled core of funnel (pybind11). Use the documented wrappers in the `funnel` package.";
  m.def("simulate", &simulate, py::arg("model"), py::arg("release"), py::arg("events"), py::arg("wear_bins"),
        py::arg("geometry") = py::none());
  m.def("ensemble", &ensemble, py::arg("model"), py::arg("samples"), py::arg("release_dist"), py::arg("threads"),
        py::arg("per_sample"), py::arg("seed"), py::arg("release"), py::arg("release_sd"), py::arg("velocity_sd"),
        py::arg("wear_bins"), py::arg("progress"), py::arg("geometry") = py::none());
  m.def("sweep", &sweep, py::arg("axes"), py::arg("samples"), py::arg("release_dist"), py::arg("threads"),
        py::arg("seed"), py::arg("release"), py::arg("release_sd"), py::arg("velocity_sd"), py::arg("progress"), py::arg("geometry") = py::none());
  m.def("parameters", &parameter_table);
  m.def("observables", &observable_table);
  m.def("geometry", &geometry, py::arg("model"), py::arg("profile") = py::none());
  m.def("parse_values", &parse_values, py::arg("name"), py::arg("text"));
  m.def("default_params", &default_params);
  m.def("simd_paths", &funnel::simd_paths);
  m.def("simd_path", &funnel::simd_path);
  m.def("set_simd_path", [](const std::string& name) { return funnel::set_simd_path(name); }, py::arg("name"));
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
        py::arg("max_time"), py::arg("max_coll"), py::arg("window"), py::arg("slip_tol"), py::arg("height_tol"),
        py::arg("seed"), py::arg("release"), py::arg("release_sd"), py::arg("geometry"));
  bind_retrace(m);
  bind_3d(m);
  bind_paper(m);
}
