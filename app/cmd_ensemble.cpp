// `funnel ensemble`: statistics of the observables over the release positions.
#include <memory>

#include "cli_common.hpp"
#include "commands.hpp"
#include "funnel/ensemble.hpp"
#include "output.hpp"
#include "progress.hpp"

namespace funnel::cli {

namespace {

struct EnsembleCommand {
  ModelOptions model;
  EnsembleText ens;
  bool per_sample = false;
  std::string format = "json";
  std::string out = "-";
  std::string command_line;

  void run() const {
    const Params params = to_params(model);
    EnsembleOptions options = to_ensemble_options(ens);
    options.keep_samples = per_sample;
    const Format fmt = to_format(format);
    check_writable(out);
    ProgressBar bar("ensemble");
    const EnsembleResult r =
        run_ensemble(params, options, [&bar](std::int64_t done, std::int64_t total) { bar.update(done, total); });

    std::string text;
    if (fmt == Format::Json) {
      nlohmann::ordered_json j;
      j["params"] = params_json(params);
      j["release_dist"] = to_string(options.dist);
      j.update(ensemble_json(r));
      if (per_sample) {
        nlohmann::ordered_json s;
        s["release"] = nlohmann::ordered_json::array();
        for (const auto& c : trajectory_columns()) s[c] = nlohmann::ordered_json::array();
        for (const Sample& smp : r.per_sample) {
          s["release"].push_back(smp.fraction);
          const nlohmann::ordered_json tj = trajectory_json(smp.trajectory);
          for (const auto& c : trajectory_columns()) s[c].push_back(tj[c]);
        }
        j["per_sample"] = s;
      }
      j["provenance"] = provenance_json(command_line);
      text = j.dump(2) + "\n";
    } else if (per_sample) {
      std::vector<std::string> cols{"release"};
      for (const auto& c : trajectory_columns()) cols.push_back(c);
      text = csv_line(cols);
      for (const Sample& smp : r.per_sample) {
        std::vector<std::string> row{number(smp.fraction)};
        for (const auto& v : trajectory_row(smp.trajectory)) row.push_back(v);
        text += csv_line(row);
      }
    } else {
      std::vector<std::string> cols = param_columns();
      std::vector<std::string> row = param_row(params);
      cols.push_back("release_dist");
      row.emplace_back(to_string(options.dist));
      for (const auto& c : ensemble_columns()) cols.push_back(c);
      for (const auto& v : ensemble_row(r)) row.push_back(v);
      text = csv_line(cols) + csv_line(row);
    }
    write_output(out, text);
  }
};

}  // namespace

void add_ensemble_command(CLI::App& app, const std::string& command_line) {
  auto cmd = std::make_shared<EnsembleCommand>();
  cmd->command_line = command_line;
  CLI::App* sub = app.add_subcommand("ensemble", "Statistics of the observables over N release positions.");
  add_model_options(*sub, cmd->model, false);
  add_ensemble_options(*sub, cmd->ens);
  sub->add_flag("--per-sample", cmd->per_sample,
                "also output every trajectory (JSON key 'per_sample'; with csv, one row per sample instead of the summary)");
  add_output_options(*sub, cmd->format, cmd->out);
  sub->callback([cmd] { cmd->run(); });
}

}  // namespace funnel::cli
