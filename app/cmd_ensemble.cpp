// `funnel ensemble`: statistics of the observables over the release positions.
#include <memory>
#include <utility>

#include "cli_common.hpp"
#include "commands.hpp"
#include "funnel/ensemble.hpp"
#include "mpi_run.hpp"
#include "funnel/paper/records.hpp"
#include "progress.hpp"
#include "run3d.hpp"

namespace funnel::cli {

namespace {

/// The options of an ensemble as JSON (those that matter for its distribution).
nlohmann::ordered_json options_json(const EnsembleOptions& o) {
  nlohmann::ordered_json j;
  j["release_dist"] = to_string(o.dist);
  if (is_random(o)) j["seed"] = o.seed;
  if (o.dist == ReleaseDist::Gaussian) {
    j["release"] = o.release_mean;
    j["release_sd"] = o.release_sd;
  }
  j["velocity_sd"] = o.velocity_sd;
  return j;
}

struct EnsembleCommand {
  ModelOptions model;
  EnsembleText ens;
  bool per_sample = false;
  std::string space = "2d";
  bool dist_given = false;
  std::string format = "json";
  std::string out = "-";
  std::string command_line;

  void run() const {
    const Space sp = to_space(space);
    const Params params = to_params(model, sp);
    EnsembleOptions options = to_ensemble_options(ens, sp);
    options.keep_samples = per_sample;
    const Format fmt = to_format(format);
    if (sp == Space::ThreeD) {
      return write_ensemble_3d(params, to_ensemble3_options(options, dist_given), per_sample, fmt, out, command_line);
    }
    if (fmt == Format::Csv && per_sample && options.wear_bins > 0) {
      throw UsageError("invalid --per-sample with --wear-bins and --format csv: the CSV holds either the samples or "
                       "the wear table; use --format json for both");
    }
    validate_all({params}, sp, options);
    check_writable(out, {{"geometry", model.geometry}});
    ProgressBar bar("ensemble");
    const EnsembleResult r = std::move(distributed_sweep({params}, options, [&bar](std::int64_t done, std::int64_t total) {
                                         bar.update(done, total);
                                       }).front());

    const std::vector<std::string> sample_columns = [] {
      std::vector<std::string> cols{"release", "u0", "v0"};
      for (const auto& c : trajectory_columns()) cols.push_back(c);
      return cols;
    }();
    auto sample_row = [](const Sample& smp) {
      std::vector<std::string> row{number(smp.fraction), number(smp.release.v.x), number(smp.release.v.y)};
      for (const auto& v : trajectory_row(smp.trajectory)) row.push_back(v);
      return row;
    };

    std::string text;
    if (fmt == Format::Json) {
      nlohmann::ordered_json j;
      j["params"] = params_json(params);
      j["geometry"] = geometry_json(params);
      j.update(options_json(options));
      j.update(ensemble_json(r));
      if (per_sample) {
        nlohmann::ordered_json s;
        for (const auto& c : sample_columns) s[c] = nlohmann::ordered_json::array();
        for (const Sample& smp : r.per_sample) {
          s["release"].push_back(smp.fraction);
          s["u0"].push_back(smp.release.v.x);
          s["v0"].push_back(smp.release.v.y);
          const nlohmann::ordered_json tj = trajectory_json(smp.trajectory);
          for (const auto& c : trajectory_columns()) s[c].push_back(tj[c]);
        }
        j["per_sample"] = s;
      }
      j["provenance"] = provenance_json(command_line);
      text = j.dump(2) + "\n";
    } else if (options.wear_bins > 0) {
      text = wear_csv(r.wear);
    } else if (per_sample) {
      text = csv_line(sample_columns);
      for (const Sample& smp : r.per_sample) text += csv_line(sample_row(smp));
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
    warn_stalled("funnel ensemble", Space::TwoD, r.stalled, r.samples);
    warn_capped("funnel ensemble", r.capped, r.samples, params.max_collisions);
  }
};

}  // namespace

void add_ensemble_command(CLI::App& app, const std::string& command_line) {
  auto cmd = std::make_shared<EnsembleCommand>();
  cmd->command_line = command_line;
  CLI::App* sub = app.add_subcommand("ensemble", "Statistics of the observables over N release positions.");
  add_model_options(*sub, cmd->model, false, Space::ThreeD);
  add_space_option(*sub, cmd->space);
  add_geometry_option(*sub, cmd->model);
  add_ensemble_options(*sub, cmd->ens);
  sub->add_flag("--per-sample", cmd->per_sample,
                "also output every trajectory (JSON key 'per_sample'; with csv, one row per sample instead of the summary)");
  add_output_options(*sub, cmd->format, cmd->out);
  sub->callback([cmd, sub] {
    cmd->dist_given = sub->count("--release-dist") > 0;
    cmd->run();
  });
}

}  // namespace funnel::cli
