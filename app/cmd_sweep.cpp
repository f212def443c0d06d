// `funnel sweep`: one ensemble per point of a parameter grid, written as CSV.
#include <toml++/toml.h>

#include <memory>

#include "cli_common.hpp"
#include "commands.hpp"
#include "funnel/ensemble.hpp"
#include "output.hpp"
#include "progress.hpp"

namespace funnel::cli {

namespace {

/// Text of a TOML value as the command line would give it: a number, a list or a range.
std::string toml_value_text(const std::string& key, const toml::node& node, const std::string& file) {
  if (node.is_string()) return *node.value<std::string>();
  if (node.is_integer() || node.is_floating_point()) return number(*node.value<double>());
  if (const toml::array* arr = node.as_array()) {
    std::string text;
    for (const toml::node& item : *arr) {
      if (!(item.is_integer() || item.is_floating_point())) {
        throw UsageError("invalid " + key + " in config '" + file + "': arrays must hold numbers only");
      }
      text += (text.empty() ? "" : ",") + number(*item.value<double>());
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
    ModelOptions merged = model;
    EnsembleText merged_ens = ens;
    if (!config.empty()) read_config(merged, merged_ens, samples_given, dist_given);
    const std::vector<Axis> axes = to_axes(merged);
    const std::vector<Params> points = expand_grid(default_params(), axes);
    validate_all(points);
    const EnsembleOptions options = to_ensemble_options(merged_ens);
    check_writable(out);

    ProgressBar bar("sweep");
    const std::vector<EnsembleResult> results =
        run_sweep(points, options, [&bar](std::int64_t done, std::int64_t total) { bar.update(done, total); });

    std::vector<std::string> cols = param_columns();
    cols.push_back("release_dist");
    for (const auto& c : ensemble_columns()) cols.push_back(c);
    std::string text = csv_line(cols);
    for (std::size_t i = 0; i < points.size(); ++i) {
      std::vector<std::string> row = param_row(points[i]);
      row.emplace_back(to_string(options.dist));
      for (const auto& v : ensemble_row(results[i])) row.push_back(v);
      text += csv_line(row);
    }
    write_output(out, text);
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
  sub->add_option("--out", cmd->out, "output CSV file, one row per grid point, written atomically")
      ->required()
      ->type_name("FILE.csv");
  sub->callback([cmd, sub] { cmd->run(sub->count("--samples") > 0, sub->count("--release-dist") > 0); });
}

}  // namespace funnel::cli
