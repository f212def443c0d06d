// Model options, validation messages and atomic file output for the CLI.
#include "cli_common.hpp"

#include <unistd.h>

#include <cerrno>
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "geometry_file.hpp"

namespace funnel::cli {

namespace {

double parse_single(const std::string& name, const std::string& text) {
  const auto v = parse_number(text);
  if (!v) {
    // A list or a range (which funnel sweep takes for its grid): say so, not only that it is no number.
    std::string reason;
    const auto values = parse_values(text, reason);
    const std::string what = values && values->size() > 1 ? "a list or range of " + std::to_string(values->size()) +
                                                                 " values, where one value is taken"
                                                           : "not a finite number";
    throw UsageError("invalid " + name + " = '" + text + "': " + what + "; valid range is " +
                     std::string(valid_range(name)));
  }
  return *v;
}

void set_or_throw(Params& p, const std::string& name, double value, const std::string& text) {
  if (!set_parameter(p, name, value)) {
    // The table's integers are held as int64: a whole number beyond 9e18 is out of range.
    const bool whole = value == std::floor(value);
    throw UsageError("invalid " + name + " = '" + text + "': " +
                     (whole ? "out of range" : number(value) + " is not an integer") + "; valid range is " +
                     std::string(valid_range(name)));
  }
}

}  // namespace

void add_model_options(CLI::App& app, ModelOptions& options, bool lists, Space space) {
  for (const ParameterInfo& p : parameters(space)) {
    if (!p.option) continue;
    std::string help = std::string(p.meaning);
    if (!p.unit.empty()) help += " [" + std::string(p.unit) + "]";
    help += "; " + std::string(p.range) + " (default " + std::string(p.default_text) + ")";
    if (lists) help += "; a list a,b,c or a range start:stop:step sweeps it";
    const std::string name(p.name);
    // In 3D the 2D spin is the spin about z.
    const std::string flags = "--" + name + (space == Space::ThreeD && name == "release-spin" ? ",--release-spin-z" : "");
    app.add_option_function<std::string>(
           flags, [&options, name](const std::string& value) { options.given[name] = value; }, help)
        ->type_name(lists ? "LIST" : "NUM");
  }
}

CLI::Option* nonempty(CLI::Option* option, const std::string& name, const std::string& valid) {
  return option->each([name, valid](const std::string& value) {
    if (value.empty()) throw UsageError("invalid " + name + " = '': an empty value; valid values are " + valid);
  });
}

void add_geometry_option(CLI::App& app, ModelOptions& options) {
  nonempty(app.add_option("--geometry", options.geometry,
                          "the funnel's walls from a TOML file (vertex lists in units of H; see docs/cli.md, 'Geometry "
                          "files') instead of the V of --theta/--gap"),
           "geometry", "a file path")
      ->type_name("FILE.toml");
}

Params base_params(const ModelOptions& options) {
  Params p = default_params();
  // The file's walls replace the V, and their own materials the parameters'.
  if (!options.geometry.empty()) p.profile = read_geometry(options.geometry);
  std::vector<GivenParameter> given;
  for (const auto& [name, text] : options.given) given.push_back({name, text});
  if (const auto err = unused_given(given, p.profile.get())) throw UsageError(err->message());
  return p;
}

Params to_params(const ModelOptions& options, Space space) {
  Params p = base_params(options);
  for (const auto& [name, text] : options.given) set_or_throw(p, name, parse_single(name, text), text);
  if (const auto err = validate(p, space)) throw UsageError(err->message());
  return p;
}

void add_space_option(CLI::App& app, std::string& space) {
  app.add_option("--space", space,
                 "2d: the paper's 2D funnel; 3d: the funnel revolved about its vertical axis (a cone with a circular "
                 "outlet of diameter --gap; sideways velocity, spin vector, orbits about the axis); default 2d")
      ->type_name("SPACE");
}

Space to_space(const std::string& text) {
  const auto s = parse_space(text);
  if (!s) throw UsageError("invalid space = '" + text + "': valid values are 2d, 3d");
  return *s;
}

std::vector<Axis> to_axes(const ModelOptions& options, double max_points, const std::string& why) {
  std::vector<Axis> axes;
  for (const ParameterInfo& info : parameters(Space::ThreeD)) {
    // 3D parameters too: in 2D, validate_all then rejects any value but their default.
    if (!info.option) continue;
    const std::string name(info.name);
    const auto it = options.given.find(name);
    if (it == options.given.end()) continue;
    std::string reason;
    auto values = parse_values(it->second, reason);
    if (!values) {
      throw UsageError("invalid " + name + " = '" + it->second + "': " + reason + "; valid range is " +
                       std::string(valid_range(name)));
    }
    // expand_grid ignores a value set_parameter refuses: a non-integral max-collisions (1.5)
    // silently ran with the default instead (found writing fuzz/fuzz_parse).
    for (const double v : *values) {
      Params probe = default_params();
      set_or_throw(probe, name, v, it->second);
    }
    axes.push_back({name, std::move(*values)});
    check_grid_cap(axes, max_points, why);
  }
  return axes;
}

std::string grid_dims(const std::vector<Axis>& axes) {
  std::string dims;
  for (const Axis& a : axes) {
    if (a.values.size() > 1) dims += (dims.empty() ? "" : " x ") + a.name + " " + std::to_string(a.values.size());
  }
  return dims;
}

std::string count_text(double n) {
  if (n < 1e15) return std::to_string(static_cast<std::int64_t>(n));
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", n);
  return buf;
}

void check_grid_cap(const std::vector<Axis>& axes, double max_points, const std::string& why) {
  const double points = grid_points(axes);
  if (points <= max_points) return;
  const std::string dims = grid_dims(axes);
  throw UsageError("invalid grid = " + dims + ": " + count_text(points) + " points; valid range is at most " +
                   count_text(max_points) + " points (" + why + "): use a coarser grid, or split it into several runs");
}

void validate_all(const std::vector<Params>& points, Space space) {
  for (const Params& p : points) {
    if (const auto err = validate(p, space)) throw UsageError(err->message());
  }
}

void validate_all(const std::vector<Params>& points, Space space, const EnsembleOptions& options) {
  validate_all(points, space);
  if (space == Space::ThreeD) return;  // the 3D funnel is a cone: disk releases are its own
  for (const Params& p : points) {
    const auto err = validate(p, options);
    if (!err) continue;
    // The refusal is the funnel's, not the option's: in a grid, say at which point (the
    // parameters that vary over the grid).
    std::string at;
    for (const ParameterInfo& info : parameters(Space::TwoD)) {
      const auto varies = [&](const Params& q) {
        const double a = info.get(q), b = info.get(points.front());
        return a != b && !(std::isnan(a) && std::isnan(b));
      };
      if (info.option && std::any_of(points.begin(), points.end(), varies)) {
        if (!at.empty()) at += ", ";
        at.append(info.name).append(" = ").append(format_number(info.get(p)));
      }
    }
    throw UsageError(err->message() + (at.empty() ? "" : " (at the grid point " + at + ")"));
  }
}

std::int64_t to_samples(const std::string& text) {
  // Written as an integer or as a whole number in any form (4e3, as --max-collisions 1e8).
  const auto v = parse_number(text);
  if (!v || !(*v >= 1.0 && *v <= 1e9) || *v != std::floor(*v)) {
    throw UsageError("invalid samples = '" + text + "': valid range is an integer 1 <= samples <= 10^9");
  }
  return static_cast<std::int64_t>(*v);
}

ReleaseDist to_release_dist(const std::string& text) {
  const auto d = parse_release_dist(text);
  if (!d) throw UsageError("invalid release-dist = '" + text + "': valid values are line, disk, uniform, gaussian");
  return *d;
}

int to_threads(const std::string& text) {
  int n = 0;
  const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), n);
  if (ec != std::errc() || ptr != text.data() + text.size() || n < 0 || n > 1024) {
    throw UsageError("invalid threads = '" + text + "': valid range is an integer 0 <= threads <= 1024 (0 = all cores)");
  }
  return n;
}

void add_ensemble_options(CLI::App& app, EnsembleText& text, bool velocity, bool wear) {
  text.velocity = velocity;
  app.add_option("--samples", text.samples, "release positions N; integer 1 <= N <= 10^9 (default 4000)")->type_name("N");
  app.add_option("--release-dist", text.release_dist,
                 "release distribution: line (2D funnel, x0 uniformly spaced, the paper's), disk (cone, "
                 "uniform over the disk), uniform (x0/L uniform random), gaussian (x0/L normal, mean --release, "
                 "sd --release-sd, truncated to (-1, 1)); default line (3d: disk; only line and disk)")
      ->type_name("DIST");
  app.add_option("--seed", text.seed,
                 "seed of the random releases and velocities (a counter-based generator keyed by seed and sample "
                 "index: the same samples for any thread count); integer 0 <= seed < 2^64 (default 1); only with "
                 "random releases or velocities")
      ->type_name("S")
      ->each([&text](const std::string&) { text.seed_given = true; });
  app.add_option("--release", text.release, "gaussian: mean release position x0/L; -1 < X < 1 (default 0)")
      ->type_name("X")
      ->each([&text](const std::string&) { text.gaussian_given.emplace_back("release"); });
  app.add_option("--release-sd", text.release_sd, "gaussian: standard deviation of x0/L; 0 < SD <= 10 (default 0.1)")
      ->type_name("SD")
      ->each([&text](const std::string&) { text.gaussian_given.emplace_back("release-sd"); });
  if (velocity) {
    app.add_option("--velocity-sd", text.velocity_sd,
                   "standard deviation of a random initial velocity added to each component (u, v; in 3d the "
                   "horizontal u, w), units "
                   "sqrt(gH); 0 <= SIGMA <= 1000 (default 0)")
        ->type_name("SIGMA");
  }
  if (wear) {
    app.add_option("--wear-bins", text.wear_bins,
                   "record where the walls wear in N equal bins along each wall (JSON key 'wear', per-sample "
                   "means; with csv the output is the wear table, one row per wall and bin, instead of the "
                   "summary); integer 0 <= N <= 10^4 (default 0: none)")
        ->type_name("N");
  }
  app.add_option("--threads", text.threads, "worker threads; integer 1 to 1024, or 0 = all cores (default 0)")
      ->type_name("T");
}

namespace {

double option_number(const char* name, const std::string& text, const char* range) {
  const auto v = parse_number(text);
  if (!v) throw UsageError("invalid " + std::string(name) + " = '" + text + "': not a finite number; valid range is " + range);
  return *v;
}

/// A whole number written in any form (1000, 1e3, 1000.0), as --samples and --max-collisions
/// take it, up to 2^53 (where every whole number is still a double); nothing when it is not one.
std::optional<double> whole_number(const std::string& text) {
  const auto v = parse_number(text);
  if (!v || !(std::fabs(*v) <= 0x1p53) || *v != std::floor(*v)) return std::nullopt;
  return *v;
}

std::int64_t option_integer(const char* name, const std::string& text, const char* range) {
  std::int64_t n = 0;
  const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), n);
  if (ec == std::errc() && ptr == text.data() + text.size()) return n;
  if (const auto v = whole_number(text)) return static_cast<std::int64_t>(*v);
  throw UsageError("invalid " + std::string(name) + " = '" + text + "': not an integer; valid range is " + range);
}

}  // namespace

EnsembleOptions to_ensemble_options(const EnsembleText& text, Space space) {
  EnsembleOptions o;
  o.samples = to_samples(text.samples);
  o.dist = to_release_dist(text.release_dist);
  o.threads = to_threads(text.threads);
  {
    std::uint64_t seed = 0;
    const auto [ptr, ec] = std::from_chars(text.seed.data(), text.seed.data() + text.seed.size(), seed);
    if (ec != std::errc() || ptr != text.seed.data() + text.seed.size()) {
      // A whole number in another form (1e3) up to 2^53; larger seeds are written as integers.
      const auto v = whole_number(text.seed);
      if (!v || *v < 0.0) {
        throw UsageError("invalid seed = '" + text.seed + "': valid range is an integer 0 <= seed < 2^64");
      }
      seed = static_cast<std::uint64_t>(*v);
    }
    o.seed = seed;
  }
  o.release_mean = option_number("release", text.release, "-1 < release < 1 (x0/L)");
  o.release_sd = option_number("release-sd", text.release_sd, "0 < release-sd <= 10 (units of L)");
  o.velocity_sd = option_number("velocity-sd", text.velocity_sd, "0 <= velocity-sd <= 1000 (units of sqrt(gH))");
  // The mean and spread of the gaussian distribution mean nothing to another: silently ignored,
  // they would leave a run that looks as asked for and is not.
  if (!text.gaussian_given.empty() && o.dist != ReleaseDist::Gaussian) {
    const std::string& name = text.gaussian_given.front();
    const bool mean = name == "release";
    throw UsageError("invalid " + name + " = " + (mean ? text.release : text.release_sd) + ": valid range is " +
                     (mean ? "-1 < release < 1" : "0 < release-sd <= 10") +
                     ", with --release-dist gaussian only (a 2D distribution: the " +
                     (mean ? "mean" : "standard deviation") + " of its x0/L)");
  }
  // Likewise a seed where nothing is drawn at random: two seeds would look like two samples.
  if (text.seed_given && !is_random(o)) {
    const std::string random = space == Space::ThreeD ? "velocities only (--velocity-sd > 0: in 3d the releases are line or disk"
                               : text.velocity        ? "releases or velocities only (--release-dist uniform or gaussian, or --velocity-sd > 0"
                                                      : "releases only (--release-dist uniform or gaussian";
    throw UsageError("invalid seed = " + text.seed + ": valid range is an integer 0 <= seed < 2^64, with random " + random +
                     "; these releases draw no random number)");
  }
  const std::int64_t bins = option_integer("wear-bins", text.wear_bins, "an integer 0 <= wear-bins <= 10^4");
  o.wear_bins = static_cast<int>(std::clamp<std::int64_t>(bins, -1, 10'001));
  if (const auto err = validate(o)) {
    ParamError e = *err;
    if (e.name == "wear-bins") e.value = text.wear_bins;
    throw UsageError(e.message());
  }
  return o;
}

void add_output_options(CLI::App& app, std::string& format, std::string& out) {
  app.add_option("--format", format, "output format: json or csv (default json)")->type_name("FMT");
  app.add_option("--out", out, "output file (default '-': standard output); a regular file is replaced atomically (through a symbolic link, its target), a device or FIFO is written through")->type_name("FILE");
}

Format to_format(const std::string& text) {
  if (text == "json") return Format::Json;
  if (text == "csv") return Format::Csv;
  throw UsageError("invalid format = '" + text + "': valid values are json, csv");
}

std::vector<std::string> comma_items(const std::string& text) {
  std::vector<std::string> items;
  for (std::size_t pos = 0; pos <= text.size();) {
    const std::size_t comma = std::min(text.find(',', pos), text.size());
    items.push_back(text.substr(pos, comma - pos));
    pos = comma + 1;
  }
  return items;
}

void warn_stalled(const std::string& who, Space space, std::int64_t stalled, std::int64_t runs,
                  const std::string& where, std::int64_t guard) {
  if (stalled == 0) return;
  const bool one = runs == 1;
  std::string text = who + ": warning: ";
  text += one ? "the run stalled: an internal guard ended it before t-max"
              : std::to_string(stalled) + " of " + std::to_string(runs) +
                    " runs stalled: an internal guard ended them before t-max";
  if (space == Space::TwoD) {
    text += " (1000 events in a row that took no time, or hand-overs between faces and edges that never ended: "
            "docs/model.md §3). ";
    text += one ? "Its status is trapped" : "Their status is trapped";
  } else {
    text += ", most often a sustained contact that reached --max-ode-steps";
    if (guard > 0) text += " (here " + std::to_string(guard) + ")";
    text += " integrator steps: a ball that orbits the cone for a long time, rolling and sliding in turn (about "
            "10^3 steps per unit of time; common in shallow cones with a small mu), or one that hovers at the limit of "
            "rolling (docs/robustness.md, finding 22). ";
    text += one ? "Its status is trapped and its results stop at the guard ("
                : "Their status is trapped and their results stop at the guard (";
    text += where + "). A shorter --t-max or a lower --max-ode-steps bounds their cost; a higher --max-ode-steps "
                    "lets them go on";
  }
  std::cerr << text << ".\n";
}

void warn_capped(const std::string& who, std::int64_t capped, std::int64_t runs, std::int64_t cap) {
  if (capped == 0) return;
  const bool one = runs == 1;
  const std::string limit = "--max-collisions" + (cap > 0 ? " (" + count_text(static_cast<double>(cap)) + ")" : std::string());
  std::cerr << who << ": warning: "
            << (one ? "the run reached " + limit + " inside the funnel: its status is trapped and its"
                    : std::to_string(capped) + " of " + std::to_string(runs) + " runs reached " + limit +
                          " inside the funnel: their status is trapped and their")
            << " duration, impulse and energy loss stop at the cap, short of the time cap t-max. A higher "
               "--max-collisions lets "
            << (one ? "it" : "them") << " go on.\n";
}

}  // namespace funnel::cli
