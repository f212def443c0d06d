// `funnel trajectory`: one trajectory from a release position, optionally with its event log.
#include <memory>

#include "cli_common.hpp"
#include "commands.hpp"
#include "funnel/engine.hpp"
#include "funnel/geometry.hpp"
#include "funnel/paper/records.hpp"
#include "run3d.hpp"

namespace funnel::cli {

namespace {

struct TrajectoryCommand {
  ModelOptions model;
  std::string release;
  bool events = false;
  std::string wear_bins = "0";
  std::string space = "2d";
  std::string format = "json";
  std::string out = "-";
  std::string command_line;

  void run() const {
    const Space sp = to_space(space);
    const Params params = to_params(model, sp);
    const auto x = parse_number(release);
    if (!x || !(*x > -1.0 && *x < 1.0)) {
      throw UsageError("invalid release = '" + release + "': valid range is -1 < release < 1 (x0/L)");
    }
    if (sp == Space::ThreeD) {
      if (wear_bins != "0") {
        throw UsageError("invalid wear-bins = " + wear_bins + ": valid range is 0 in 3d (the wear record is 2D only)");
      }
      return write_trajectory_3d(params, *x, events, to_format(format), out, command_line);
    }
    EnsembleText wear_text;
    wear_text.wear_bins = wear_bins;
    const int bins = to_ensemble_options(wear_text).wear_bins;
    const Format fmt = to_format(format);
    if (fmt == Format::Csv && events && bins > 0) {
      throw UsageError("invalid --events with --wear-bins and --format csv: the CSV holds either the event log or "
                       "the wear table; use --format json for both");
    }
    check_writable(out, {{"geometry", model.geometry}});
    const Funnel g = make_funnel(params);
    EventLog log;
    Wear wear = Wear::make(g, bins);
    const Trajectory t = simulate_release(params, g, *x, events ? &log : nullptr, bins > 0 ? &wear : nullptr);

    std::string text;
    if (fmt == Format::Json) {
      nlohmann::ordered_json j;
      j["params"] = params_json(params);
      j["geometry"] = geometry_json(params);
      j["release"] = *x;
      j["x0"] = release_point(g, *x).x;
      j["y0"] = g.y_release;
      j["u0"] = params.release_u;
      j["v0"] = params.release_v;
      j["omega0"] = params.release_spin;
      j.update(trajectory_json(t));
      if (bins > 0) j["wear"] = wear_json(wear);
      if (events) {
        j["events"] = nlohmann::ordered_json::array();
        for (const Event& e : log.events) j["events"].push_back(event_json(e));
      }
      j["provenance"] = provenance_json(command_line);
      text = j.dump(2) + "\n";
    } else if (bins > 0) {
      text = wear_csv(wear);
    } else if (events) {
      text = csv_line(event_columns());
      for (const Event& e : log.events) text += csv_line(event_row(e));
    } else {
      std::vector<std::string> cols = param_columns();
      std::vector<std::string> row = param_row(params);
      cols.push_back("release");
      row.push_back(number(*x));
      for (const auto& c : trajectory_columns()) cols.push_back(c);
      for (const auto& v : trajectory_row(t)) row.push_back(v);
      text = csv_line(cols) + csv_line(row);
    }
    write_output(out, text);
    warn_stalled("funnel trajectory", Space::TwoD, t.stalled ? 1 : 0, 1);
    warn_capped("funnel trajectory", t.capped ? 1 : 0, 1, params.max_collisions);
  }
};

}  // namespace

void add_trajectory_command(CLI::App& app, const std::string& command_line) {
  auto cmd = std::make_shared<TrajectoryCommand>();
  cmd->command_line = command_line;
  CLI::App* sub = app.add_subcommand("trajectory", "Simulate one trajectory released at x0 = X*L (at rest unless --release-u/-v/-spin say otherwise).");
  add_model_options(*sub, cmd->model, false, Space::ThreeD);
  add_space_option(*sub, cmd->space);
  add_geometry_option(*sub, cmd->model);
  sub->add_option("--release", cmd->release, "release position X = x0/L; -1 < X < 1 (3d: at z = 0)")->required()->type_name("X");
  sub->add_flag("--events", cmd->events, "include the event log (JSON key 'events'; with csv, one row per event)");
  sub->add_option("--wear-bins", cmd->wear_bins,
                  "record where the walls wear in N equal bins of distance along each wall from its lower edge up to "
                  "the release height (JSON key 'wear'; with csv, one row per wall and bin); integer 0 <= N <= 10^4 "
                  "(default 0: none)")
      ->type_name("N");
  add_output_options(*sub, cmd->format, cmd->out);
  sub->callback([cmd] { cmd->run(); });
}

}  // namespace funnel::cli
