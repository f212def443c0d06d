// `funnel trajectory --space 3d` and `funnel ensemble --space 3d`.
#include "run3d.hpp"

#include "funnel/cone.hpp"
#include "funnel/paper/records.hpp"
#include "output3d.hpp"
#include "progress.hpp"

namespace funnel::cli {

Ensemble3Options to_ensemble3_options(const EnsembleOptions& options, bool dist_given) {
  if (options.wear_bins != 0) {
    throw UsageError("invalid wear-bins = " + std::to_string(options.wear_bins) +
                     ": valid range is 0 in 3d (the wear record is 2D only; use --space 2d)");
  }
  Ensemble3Options o;
  o.samples = options.samples;
  o.dist = dist_given ? options.dist : ReleaseDist::Disk;
  if (o.dist != ReleaseDist::Line && o.dist != ReleaseDist::Disk) {
    throw UsageError("invalid release-dist = '" + std::string(to_string(o.dist)) +
                     "': valid values in 3d are disk (uniform over the opening, the default) and line (along a "
                     "diameter); uniform and gaussian are 2D only");
  }
  o.velocity_sd = options.velocity_sd;
  o.seed = options.seed;
  o.threads = options.threads;
  o.keep_samples = options.keep_samples;
  return o;
}

void write_trajectory_3d(const Params& params, double release, bool events, Format format, const std::string& out,
                         const std::string& command_line) {
  check_writable(out);
  const Cone cone = make_cone(params);
  const State3 start = release_state_3d(params, cone, release);
  EventLog3 log;
  const Trajectory3 t = simulate_3d(params, cone, start, events ? &log : nullptr);
  std::string text;
  if (format == Format::Json) {
    nlohmann::ordered_json j;
    j["space"] = "3d";
    j["params"] = params_json(params, Space::ThreeD);
    j["release"] = release;
    j["x0"] = start.r.x;
    j["y0"] = start.r.y;
    j["z0"] = start.r.z;
    j["u0"] = start.v.x;
    j["v0"] = start.v.y;
    j["w0"] = start.v.z;
    j["omega0"] = {start.omega.x, start.omega.y, start.omega.z};
    j.update(trajectory_json(t));
    if (events) {
      j["events"] = nlohmann::ordered_json::array();
      for (const Event3& e : log.events) j["events"].push_back(event_json(e));
    }
    j["provenance"] = provenance_json(command_line);
    text = j.dump(2) + "\n";
  } else if (events) {
    text = csv_line(event_columns_3d());
    for (const Event3& e : log.events) text += csv_line(event_row(e));
  } else {
    std::vector<std::string> cols = param_columns(Space::ThreeD);
    std::vector<std::string> row = param_row(params, Space::ThreeD);
    cols.push_back("release");
    row.push_back(number(release));
    for (const auto& c : trajectory_columns_3d()) cols.push_back(c);
    for (const auto& v : trajectory_row(t)) row.push_back(v);
    text = csv_line(cols) + csv_line(row);
  }
  write_output(out, text);
  warn_stalled("funnel trajectory", Space::ThreeD, t.stalled ? 1 : 0, 1, "\"stalled\" in the output",
               params.max_ode_steps);
  warn_capped("funnel trajectory", t.capped ? 1 : 0, 1, params.max_collisions);
}

void write_ensemble_3d(const Params& params, const Ensemble3Options& options, bool per_sample, Format format,
                       const std::string& out, const std::string& command_line) {
  check_writable(out);
  Ensemble3Options o = options;
  o.keep_samples = per_sample;
  ProgressBar bar("ensemble");
  const Ensemble3Result r =
      run_ensemble_3d(params, o, [&bar](std::int64_t done, std::int64_t total) { bar.update(done, total); });

  std::vector<std::string> sample_columns{"release", "u0", "v0", "w0"};
  for (const auto& c : trajectory_columns_3d()) sample_columns.push_back(c);
  std::string text;
  if (format == Format::Json) {
    nlohmann::ordered_json j;
    j["space"] = "3d";
    j["params"] = params_json(params, Space::ThreeD);
    j["release_dist"] = to_string(o.dist);
    if (o.velocity_sd > 0.0) j["seed"] = o.seed;
    j["velocity_sd"] = o.velocity_sd;
    j.update(ensemble_json(r));
    if (per_sample) {
      nlohmann::ordered_json s;
      for (const auto& c : sample_columns) s[c] = nlohmann::ordered_json::array();
      for (const Sample3& smp : r.per_sample) {
        s["release"].push_back(smp.fraction);
        s["u0"].push_back(smp.velocity.x);
        s["v0"].push_back(smp.velocity.y);
        s["w0"].push_back(smp.velocity.z);
        const nlohmann::ordered_json tj = trajectory_json(smp.trajectory);
        for (const auto& c : trajectory_columns_3d()) s[c].push_back(tj[c]);
      }
      j["per_sample"] = s;
    }
    j["provenance"] = provenance_json(command_line);
    text = j.dump(2) + "\n";
  } else if (per_sample) {
    text = csv_line(sample_columns);
    for (const Sample3& smp : r.per_sample) {
      std::vector<std::string> row{number(smp.fraction), number(smp.velocity.x), number(smp.velocity.y),
                                   number(smp.velocity.z)};
      for (const auto& v : trajectory_row(smp.trajectory)) row.push_back(v);
      text += csv_line(row);
    }
  } else {
    std::vector<std::string> cols = param_columns(Space::ThreeD);
    std::vector<std::string> row = param_row(params, Space::ThreeD);
    cols.push_back("release_dist");
    row.emplace_back(to_string(o.dist));
    for (const auto& c : ensemble_columns_3d()) cols.push_back(c);
    for (const auto& v : ensemble_row(r)) row.push_back(v);
    text = csv_line(cols) + csv_line(row);
  }
  write_output(out, text);
  warn_stalled("funnel ensemble", Space::ThreeD, r.stalled, r.samples,
               per_sample ? "\"stalled\" for each sample" : "the count \"stalled\"; each sample's with --per-sample",
               params.max_ode_steps);
  warn_capped("funnel ensemble", r.capped, r.samples, params.max_collisions);
}

}  // namespace funnel::cli
