// Model options, validation messages and atomic file output for the CLI.
#include "cli_common.hpp"

#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>

namespace funnel::cli {

namespace {

struct OptionDoc {
  const char* name;
  const char* meaning;
  const char* fallback;
};

// Meaning and default of each model option (MODEL.md §1); ranges come from the library.
const OptionDoc option_docs[] = {
    {"theta", "wall angle to the horizontal, degrees", "60"},
    {"e", "normal restitution", "0.99"},
    {"mu", "Coulomb friction coefficient", "1"},
    {"beta0", "maximum tangential restitution (Walton)", "0"},
    {"radius", "particle radius a / H", "0.01"},
    {"gap", "gap between the walls' lower edges / H (0 = closed funnel)", "0.04"},
    {"inertia", "kappa = I/(m a^2): 0.4 solid sphere, 2/3 hollow sphere, 0.5 disk", "0.4"},
    {"t-max", "time cap, units of sqrt(H/g)", "1e5"},
    {"max-collisions", "collision cap per trajectory", "1e8"},
};

double parse_single(const std::string& name, const std::string& text) {
  const auto v = parse_number(text);
  if (!v) {
    throw UsageError("invalid " + name + " = '" + text + "': not a finite number; valid range is " +
                     std::string(valid_range(name)));
  }
  return *v;
}

void set_or_throw(Params& p, const std::string& name, double value, const std::string& text) {
  if (!set_parameter(p, name, value)) {
    throw UsageError("invalid " + name + " = '" + text + "': not an integer; valid range is " +
                     std::string(valid_range(name)));
  }
}

}  // namespace

void add_model_options(CLI::App& app, ModelOptions& options, bool lists) {
  for (const OptionDoc& doc : option_docs) {
    std::string help = std::string(doc.meaning) + "; " + std::string(valid_range(doc.name)) +
                       " (default " + doc.fallback + ")";
    if (lists) help += "; a list a,b,c or a range start:stop:step sweeps it";
    const std::string name = doc.name;
    app.add_option_function<std::string>(
           "--" + name, [&options, name](const std::string& value) { options.given[name] = value; }, help)
        ->type_name(lists ? "LIST" : "NUM");
  }
}

Params to_params(const ModelOptions& options) {
  Params p = default_params();
  for (const auto& [name, text] : options.given) set_or_throw(p, name, parse_single(name, text), text);
  if (const auto err = validate(p)) throw UsageError(err->message());
  return p;
}

std::vector<Axis> to_axes(const ModelOptions& options) {
  std::vector<Axis> axes;
  for (const std::string& name : sweep_parameter_names()) {
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
      if (!set_parameter(probe, name, v)) {
        throw UsageError("invalid " + name + " = '" + it->second + "': " + number(v) +
                         " is not an integer; valid range is " + std::string(valid_range(name)));
      }
    }
    axes.push_back({name, std::move(*values)});
  }
  return axes;
}

void validate_all(const std::vector<Params>& points) {
  for (const Params& p : points) {
    if (const auto err = validate(p)) throw UsageError(err->message());
  }
}

std::int64_t to_samples(const std::string& text) {
  std::int64_t n = 0;
  const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), n);
  if (ec != std::errc() || ptr != text.data() + text.size() || n < 1 || n > 1'000'000'000) {
    throw UsageError("invalid samples = '" + text + "': valid range is an integer 1 <= samples <= 10^9");
  }
  return n;
}

ReleaseDist to_release_dist(const std::string& text) {
  const auto d = parse_release_dist(text);
  if (!d) throw UsageError("invalid release-dist = '" + text + "': valid values are line, disk");
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

void add_ensemble_options(CLI::App& app, EnsembleText& text) {
  app.add_option("--samples", text.samples, "release positions N; integer >= 1 (default 4000)")->type_name("N");
  app.add_option("--release-dist", text.release_dist,
                 "release distribution: line (2D funnel, uniform x0) or disk (cone, uniform over the disk); default line")
      ->type_name("DIST");
  app.add_option("--threads", text.threads, "worker threads; integer >= 1, or 0 = all cores (default 0)")
      ->type_name("T");
}

EnsembleOptions to_ensemble_options(const EnsembleText& text) {
  EnsembleOptions o;
  o.samples = to_samples(text.samples);
  o.dist = to_release_dist(text.release_dist);
  o.threads = to_threads(text.threads);
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

std::string number(double x) {
  char buf[32];
  const auto [ptr, ec] = std::to_chars(buf, buf + sizeof buf, x);
  (void)ec;
  return std::string(buf, ptr);
}

}  // namespace funnel::cli
