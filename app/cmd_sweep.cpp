// `funnel sweep`: one ensemble per point of a parameter grid, written as CSV.
#include <toml++/toml.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>

#include "cli_common.hpp"
#include "commands.hpp"
#include "funnel/ensemble.hpp"
#include "funnel/version.hpp"
#include "output.hpp"
#include "progress.hpp"

namespace funnel::cli {

namespace {

/// A TOML number as text. Integers are written exactly: toml++ gives no value<double>() for
/// |i| > 2^53, and dereferencing that empty optional ran the sweep with a garbage value
/// (theta = 9007199254740993 ran at theta = 6.9e-310; found writing fuzz/fuzz_parse).
std::string toml_number_text(const toml::node& node) {
  if (const auto* i = node.as_integer()) return std::to_string(i->get());
  return number(node.as_floating_point()->get());
}

/// Text of a TOML value as the command line would give it: a number, a list or a range.
std::string toml_value_text(const std::string& key, const toml::node& node, const std::string& file) {
  if (node.is_string()) return *node.value<std::string>();
  if (node.is_integer() || node.is_floating_point()) return toml_number_text(node);
  if (const toml::array* arr = node.as_array()) {
    std::string text;
    for (const toml::node& item : *arr) {
      if (!(item.is_integer() || item.is_floating_point())) {
        throw UsageError("invalid " + key + " in config '" + file + "': arrays must hold numbers only");
      }
      text += (text.empty() ? "" : ",") + toml_number_text(item);
    }
    if (text.empty()) throw UsageError("invalid " + key + " in config '" + file + "': empty array");
    return text;
  }
  throw UsageError("invalid " + key + " in config '" + file + "': expected a number, an array or a string");
}

std::string canonical_key(std::string key) {
  for (char& c : key) {
    if (c == '_') c = '-';
  }
  return key;
}

struct SweepCommand {
  ModelOptions model;
  EnsembleText ens;
  std::string config;
  std::string out;
  bool resume = false;
  std::string command_line;

  /// Fills the options the command line did not give from the TOML file.
  void read_config(ModelOptions& merged, EnsembleText& merged_ens, bool samples_given, bool dist_given) const {
    toml::table tbl;
    try {
      tbl = toml::parse_file(config);
    } catch (const toml::parse_error& err) {
      throw UsageError("invalid config = '" + config + "': " + std::string(err.description()));
    }
    const auto& names = sweep_parameter_names();
    for (auto&& [k, node] : tbl) {
      const std::string key = canonical_key(std::string(k.str()));
      const std::string text = toml_value_text(key, node, config);
      if (key == "samples") {
        if (!samples_given) merged_ens.samples = text;
      } else if (key == "release-dist") {
        if (!dist_given) merged_ens.release_dist = text;
      } else if (std::find(names.begin(), names.end(), key) != names.end()) {
        merged.given.emplace(key, text);  // the command line wins
      } else {
        throw UsageError("invalid key '" + std::string(k.str()) + "' in config '" + config +
                         "': valid keys are samples, release-dist and the model parameters");
      }
    }
  }

  void run(bool samples_given, bool dist_given) const {
    const auto start = std::chrono::steady_clock::now();
    ModelOptions merged = model;
    EnsembleText merged_ens = ens;
    if (!config.empty()) read_config(merged, merged_ens, samples_given, dist_given);
    const std::vector<Axis> axes = to_axes(merged);
    const std::vector<Params> points = expand_grid(default_params(), axes);
    validate_all(points);
    const EnsembleOptions options = to_ensemble_options(merged_ens);
    check_writable(out);

    std::vector<std::string> cols = param_columns();
    cols.push_back("release_dist");
    for (const auto& c : ensemble_columns()) cols.push_back(c);
    const std::string header = csv_line(cols);
    // What the rows depend on: a partial file is continued only if this is the same.
    nlohmann::ordered_json spec;
    spec["version"] = version();
    spec["samples"] = options.samples;
    spec["release_dist"] = to_string(options.dist);
    spec["grid"] = nlohmann::ordered_json::array();
    for (const Axis& a : axes) spec["grid"].push_back({{"name", a.name}, {"values", a.values}});
    const std::string spec_line = "# funnel sweep spec: " + spec.dump() + "\n";

    // Rows already computed by an interrupted run ("point,<row>"), by grid index.
    const std::string partial = out + ".partial";
    std::map<std::size_t, std::string> done;
    if (resume) done = read_partial(partial, spec_line, header, points.size());
    write_partial_start(partial, spec_line, header, done);
    if (!done.empty()) std::cerr << "funnel sweep: resuming: " << done.size() << " of " << points.size() << " points already done\n";

    std::vector<Params> todo;
    std::vector<std::size_t> todo_index;
    for (std::size_t i = 0; i < points.size(); ++i) {
      if (done.count(i) == 0) {
        todo.push_back(points[i]);
        todo_index.push_back(i);
      }
    }
    {
      // Each finished point is appended (one write, flushed) so that an interruption keeps it.
      std::FILE* f = std::fopen(partial.c_str(), "ab");
      if (f == nullptr) throw UsageError("cannot append to '" + partial + "': " + std::strerror(errno));
      ProgressBar bar("sweep");
      run_sweep(
          todo, options, [&bar](std::int64_t d, std::int64_t t) { bar.update(d, t); },
          [&](std::size_t k, const EnsembleResult& r) {
            const std::size_t i = todo_index[k];
            std::vector<std::string> row = param_row(points[i]);
            row.emplace_back(to_string(options.dist));
            for (const auto& v : ensemble_row(r)) row.push_back(v);
            done[i] = csv_line(row);
            const std::string line = std::to_string(i) + "," + done[i];
            std::fwrite(line.data(), 1, line.size(), f);
            std::fflush(f);
          });
      std::fclose(f);
    }

    std::string text = header;
    for (std::size_t i = 0; i < points.size(); ++i) text += done.at(i);
    write_output(out, text);
    nlohmann::ordered_json meta;
    meta["provenance"] = provenance_json(command_line);
    meta["spec"] = spec;
    meta["points"] = points.size();
    meta["resumed_points"] = points.size() - todo.size();
    meta["wall_time_s"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    write_output(out + ".json", meta.dump(2) + "\n");
    std::remove(partial.c_str());
  }

  /// Valid rows of a partial file made by the same sweep; an empty map if there is none.
  static std::map<std::size_t, std::string> read_partial(const std::string& path, const std::string& spec_line,
                                                         const std::string& header, std::size_t n_points) {
    std::map<std::size_t, std::string> rows;
    std::ifstream in(path, std::ios::binary);
    if (!in) return rows;
    std::stringstream buffer;
    buffer << in.rdbuf();
    const std::string text = buffer.str();
    if (text.rfind(spec_line + "point," + header, 0) != 0) {
      throw UsageError("invalid resume: '" + path + "' was made by a different sweep (grid, samples, release-dist "
                       "or funnel version); remove it or run without --resume");
    }
    std::size_t pos = spec_line.size() + 6 + header.size();
    for (std::size_t eol; (eol = text.find('\n', pos)) != std::string::npos; pos = eol + 1) {
      const std::string line = text.substr(pos, eol + 1 - pos);  // a line cut by a kill has no newline
      const std::size_t comma = line.find(',');
      const auto index = parse_number(line.substr(0, comma));
      if (comma == std::string::npos || !index || *index < 0 || *index >= static_cast<double>(n_points)) continue;
      rows[static_cast<std::size_t>(*index)] = line.substr(comma + 1);
    }
    return rows;
  }

  /// (Re)writes the partial file with its spec, header and the rows kept, atomically.
  static void write_partial_start(const std::string& path, const std::string& spec_line, const std::string& header,
                                  const std::map<std::size_t, std::string>& rows) {
    std::string text = spec_line + "point," + header;
    for (const auto& [i, row] : rows) text += std::to_string(i) + "," + row;
    write_output(path, text);
  }
};

}  // namespace

void add_sweep_command(CLI::App& app, const std::string& command_line) {
  auto cmd = std::make_shared<SweepCommand>();
  cmd->command_line = command_line;
  CLI::App* sub = app.add_subcommand(
      "sweep", "Run one ensemble per point of a parameter grid (Cartesian product of lists/ranges) to CSV.");
  add_model_options(*sub, cmd->model, true);
  add_ensemble_options(*sub, cmd->ens);
  sub->add_option("--config", cmd->config,
                  "TOML file with the grid: keys theta, e, mu, ... (number, array or \"start:stop:step\"), "
                  "samples, release-dist; command-line options override it")
      ->type_name("FILE.toml");
  sub->add_flag("--resume", cmd->resume,
                "continue an interrupted sweep from FILE.csv.partial: finished points are not recomputed");
  sub->add_option("--out", cmd->out,
                  "output CSV file, one row per grid point, written atomically at the end (with FILE.csv.json: "
                  "provenance); while running, finished points are appended to FILE.csv.partial")
      ->required()
      ->type_name("FILE.csv");
  sub->callback([cmd, sub] { cmd->run(sub->count("--samples") > 0, sub->count("--release-dist") > 0); });
}

}  // namespace funnel::cli
