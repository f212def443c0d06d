// `funnel closed`: long-time states of a closed funnel (the paper's Figs. 11 and 12).
#include <cmath>
#include <memory>

#include "cli_common.hpp"
#include "commands.hpp"
#include "funnel/closed.hpp"
#include "funnel/funnel.hpp"
#include "funnel/geometry.hpp"
#include "funnel/paper/records.hpp"
#include "progress.hpp"

namespace funnel::cli {

namespace {

/// Caps whose default differs here, suited to deciding periodic or rest (and e = 1, as in the
/// paper's Figs. 11-12, set in run(): with e < 1 there is no periodic orbit).
const std::pair<const char*, const char*> closed_caps[] = {{"t-max", "1e4"}, {"max-collisions", "1e7"}};

struct ClosedCommand {
  ModelOptions model;
  EnsembleText ens;
  std::string window = "20";
  std::string slip_tol = "1e-6";
  std::string height_tol = "1e-6";
  std::string format = "json";
  std::string out = "-";
  std::string command_line;

  static double positive(const std::string& name, const std::string& text, const std::string& range) {
    const auto v = parse_number(text);
    if (!v || !(*v > 0.0)) throw UsageError("invalid " + name + " = '" + text + "': valid range is " + range);
    return *v;
  }

  void run() const {
    ModelOptions m = model;
    if (const auto it = m.given.find("gap"); it != m.given.end() && parse_number(it->second) != 0.0) {
      throw UsageError("invalid gap = '" + it->second + "': funnel closed needs gap = 0 (the default here)");
    }
    if (m.geometry.empty()) m.given["gap"] = "0";  // a geometry file's own walls must close (below)
    // The defaults of this command (the paper's Figs. 11 and 12), where the user gave none; e as
    // a value, not as given (a geometry whose walls all set their own e refuses a given e).
    for (const auto& [name, value] : closed_caps) m.given.emplace(name, value);
    Params params = to_params(m);
    if (!m.given.contains("e")) params.e = 1.0;
    if (params.profile && !make_funnel(params).closed) {
      throw UsageError("invalid geometry = '" + model.geometry +
                       "': funnel closed needs a closed funnel (the two walls' lower ends at one point)");
    }
    const EnsembleOptions ensemble = to_ensemble_options(ens);
    validate_all({params}, Space::TwoD, ensemble);
    ClosedOptions opt;
    opt.max_time = params.t_max;
    opt.max_collisions = params.max_collisions;
    const double w = positive("window", window, "an integer 1 <= window <= 10^6");
    if (w != std::floor(w) || w > 1e6) throw UsageError("invalid window = '" + window + "': valid range is an integer 1 <= window <= 10^6");
    opt.window = static_cast<int>(w);
    opt.slip_tol = positive("slip-tol", slip_tol, "slip-tol > 0");
    opt.height_tol = positive("height-tol", height_tol, "height-tol > 0");
    const Format fmt = to_format(format);
    check_writable(out, {{"geometry", model.geometry}});

    ClosedResult r;
    {
      ProgressBar bar("funnel closed");  // a bar on a terminal
      r = run_closed(params, ensemble, opt, [&bar](std::int64_t done, std::int64_t total) { bar.update(done, total); });
    }
    const double half_width = make_funnel(params).half_width;
    std::string text;
    if (fmt == Format::Json) {
      nlohmann::ordered_json j;
      j["params"] = params_json(params);
      j["geometry"] = geometry_json(params);
      j["release_dist"] = to_string(ensemble.dist);
      // What the random releases were drawn with, as Python's closed() records it ("release" is
      // each release's column, so the gaussian's mean is release_mean).
      if (is_random(ensemble)) j["seed"] = ensemble.seed;
      if (ensemble.dist == ReleaseDist::Gaussian) {
        j["release_mean"] = ensemble.release_mean;
        j["release_sd"] = ensemble.release_sd;
      }
      j["samples"] = ensemble.samples;
      j["options"] = {{"max_time", opt.max_time}, {"max_collisions", opt.max_collisions}, {"window", opt.window},
                      {"slip_tol", opt.slip_tol}, {"height_tol", opt.height_tol}};
      j["periodic_fraction"] = r.periodic_fraction;
      j["state_counts"] = {{"periodic", r.periodic}, {"rest", r.rest}, {"undecided", r.undecided}};
      nlohmann::ordered_json per;
      for (const char* key : {"release", "state", "x_last_over_L", "x_prev_over_L", "y_last", "y_prev", "collisions", "time"}) {
        per[key] = nlohmann::ordered_json::array();
      }
      for (const ClosedSample& s : r.samples) {
        per["release"].push_back(s.fraction);
        per["state"].push_back(to_string(s.state));
        per["x_last_over_L"].push_back(s.x_last / half_width);
        per["x_prev_over_L"].push_back(s.x_prev / half_width);
        per["y_last"].push_back(s.y_last);
        per["y_prev"].push_back(s.y_prev);
        per["collisions"].push_back(s.collisions);
        per["time"].push_back(s.time);
      }
      j["per_sample"] = per;
      j["provenance"] = provenance_json(command_line);
      text = j.dump(2) + "\n";
    } else {
      text = csv_line({"release", "state", "x_last_over_L", "x_prev_over_L", "y_last", "y_prev", "collisions", "time"});
      for (const ClosedSample& s : r.samples) {
        text += csv_line({number(s.fraction), std::string(to_string(s.state)), csv_number(s.x_last / half_width),
                          csv_number(s.x_prev / half_width), csv_number(s.y_last), csv_number(s.y_prev),
                          std::to_string(s.collisions), number(s.time)});
      }
    }
    write_output(out, text);
  }
};

}  // namespace

void add_closed_command(CLI::App& app, const std::string& command_line) {
  auto cmd = std::make_shared<ClosedCommand>();
  cmd->command_line = command_line;
  CLI::App* sub = app.add_subcommand(
      "closed", "Closed funnel (gap 0): does each release reach the period-2 orbit or rest? (Figs. 11, 12)");
  add_model_options(*sub, cmd->model, false);
  add_geometry_option(*sub, cmd->model);
  sub->get_option("--e")->description("normal restitution; " + std::string(valid_range("e")) +
                                      " (default 1 here, as in the paper's Figs. 11-12; with e < 1 there is no periodic orbit: each release ends at rest or is undecided)");
  sub->get_option("--gap")->description("gap between the walls' lower edges / H: 0 here, a closed funnel (default 0)");
  sub->get_option("--t-max")->description(
      "time cap per release, units of sqrt(H/g); " + std::string(valid_range("t-max")) + " (default 1e4 here); beyond it: undecided");
  sub->get_option("--max-collisions")->description(
      "collision cap per release; " + std::string(valid_range("max-collisions")) + " (default 1e7 here); beyond it: undecided");
  add_ensemble_options(*sub, cmd->ens, false, false);
  // funnel closed is 2D only: its releases without the 3D note of the shared text.
  sub->get_option("--release-dist")
      ->description("release distribution: line (x0 uniformly spaced, the paper's), disk (x0/L = sqrt((k + 1/2)/N), the cone's "
                    "radii uniform over the disk, Sec. V), "
                    "uniform (x0/L uniform random), gaussian (x0/L normal, mean --release, sd --release-sd, truncated "
                    "to (-1, 1)); default line");
  sub->add_option("--window", cmd->window,
                  "consecutive collisions that must pass the periodic test; integer 1 to 10^6 (default 20)")->type_name("K");
  sub->add_option("--slip-tol", cmd->slip_tol, "periodic test: |slip before| <= tol * speed; > 0 (default 1e-6)")->type_name("TOL");
  sub->add_option("--height-tol", cmd->height_tol,
                  "periodic test: |y_k - y_(k-1)| <= tol * |y_k| (y_(k-2) in a funnel that is not mirror symmetric); > 0 "
                  "(default 1e-6)")->type_name("TOL");
  add_output_options(*sub, cmd->format, cmd->out);
  sub->callback([cmd] { cmd->run(); });
}

}  // namespace funnel::cli
