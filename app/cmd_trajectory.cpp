// `funnel trajectory`: one trajectory from a release position, optionally with its event log.
#include <memory>

#include "cli_common.hpp"
#include "commands.hpp"
#include "funnel/engine.hpp"
#include "funnel/geometry.hpp"
#include "output.hpp"

namespace funnel::cli {

namespace {

struct TrajectoryCommand {
  ModelOptions model;
  std::string release;
  bool events = false;
  std::string format = "json";
  std::string out = "-";
  std::string command_line;

  void run() const {
    const Params params = to_params(model);
    const auto x = parse_number(release);
    if (!x || !(*x > -1.0 && *x < 1.0)) {
      throw UsageError("invalid release = '" + release + "': valid range is -1 < release < 1 (x0/L)");
    }
    const Format fmt = to_format(format);
    check_writable(out);
    const Geometry g = make_geometry(params);
    EventLog log;
    const Trajectory t = simulate_release(params, g, *x, events ? &log : nullptr);

    std::string text;
    if (fmt == Format::Json) {
      nlohmann::ordered_json j;
      j["params"] = params_json(params);
      j["release"] = *x;
      j["x0"] = *x * g.half_width;
      j["y0"] = g.y_release;
      j.update(trajectory_json(t));
      if (events) {
        j["events"] = nlohmann::ordered_json::array();
        for (const Event& e : log.events) j["events"].push_back(event_json(e));
      }
      j["provenance"] = provenance_json(command_line);
      text = j.dump(2) + "\n";
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
  }
};

}  // namespace

void add_trajectory_command(CLI::App& app, const std::string& command_line) {
  auto cmd = std::make_shared<TrajectoryCommand>();
  cmd->command_line = command_line;
  CLI::App* sub = app.add_subcommand("trajectory", "Simulate one trajectory released at rest at x0 = X*L.");
  add_model_options(*sub, cmd->model, false);
  sub->add_option("--release", cmd->release, "release position X = x0/L; -1 < X < 1")->required()->type_name("X");
  sub->add_flag("--events", cmd->events, "include the event log (JSON key 'events'; with csv, one row per event)");
  add_output_options(*sub, cmd->format, cmd->out);
  sub->callback([cmd] { cmd->run(); });
}

}  // namespace funnel::cli
