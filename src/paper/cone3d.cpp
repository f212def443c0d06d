// The cone in 3D with random sideways release velocities (beyond the paper), as figure data.
#include "cone3d.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "funnel/ensemble3d.hpp"
#include "funnel/observables.hpp"
#include "funnel/stats.hpp"
#include "funnel/paper/records.hpp"
#include "util.hpp"

namespace funnel::paper {

namespace {

/// Mean and standard error of an observable of one point: over every sample ("duration"), over
/// the exited ones ("duration_exited"), or the fraction trapped ("trapped_fraction").
Summary point_summary(const Ensemble3Result& r, const std::string& name) {
  if (name == "trapped_fraction") {
    Accumulator acc;
    for (const Sample3& s : r.per_sample) acc.add(s.trajectory.status == Status::Trapped ? 1.0 : 0.0);
    return summarize(acc);
  }
  const std::string suffix = "_exited";
  const bool exited_only = name.size() > suffix.size() && name.ends_with(suffix);
  const ObservableInfo* info = find_observable(exited_only ? name.substr(0, name.size() - suffix.size()) : name);
  if (info == nullptr) return {std::nan(""), std::nan(""), std::nan(""), std::nan(""), std::nan("")};
  if (!exited_only) return r[info->id];
  Accumulator acc;
  for (const Sample3& s : r.per_sample) {
    if (s.trajectory.status == Status::Exited) acc.add(value(s.trajectory, info->id));
  }
  return summarize(acc);
}

}  // namespace

FigureData cone_3d_sweep(const FigureSpec& fig, int threads, const Progress& progress) {
  std::vector<double> sigmas;
  if (const toml::array* a = fig.settings["velocity_sds"].as_array()) {
    for (const auto& v : *a) sigmas.push_back(v.value<double>().value_or(std::nan("")));
  }
  if (sigmas.empty()) sigmas.push_back(0.0);
  const std::vector<Params> points = expand_grid(panel_params(fig, fig.panels.front()), fig.grid);
  std::vector<std::string> names = fig.observables;
  for (const char* extra : {"orbits_exited", "duration", "impulse", "energy_loss", "orbits", "trapped_fraction"}) {
    if (std::find(names.begin(), names.end(), extra) == names.end()) names.emplace_back(extra);
  }

  FigureData out;
  std::vector<std::string> cols{"panel", "velocity_sd", "theta"};
  for (const std::string& o : names) {
    cols.push_back(o + "_mean");
    cols.push_back(o + "_sem");
  }
  for (const char* c : {"exited", "trapped", "periodic", "total_collisions"}) cols.emplace_back(c);
  out.csv = csv_line(cols);
  out.extra["beyond_paper"] = true;
  out.extra["velocity_sds"] = sigmas;

  const std::string check_obs = fig.check["observable"].value_or(std::string("duration_exited"));
  std::map<std::pair<double, double>, double> check_of;  // (sigma, theta) -> mean of the check's observable
  std::int64_t collisions = 0;
  // Every (sigma, theta) ensemble in one parallel pool: no barrier between the sigmas.
  std::vector<Params> all_points;
  std::vector<double> all_sigmas;
  for (const double sigma : sigmas) {
    for (const Params& p : points) {
      all_points.push_back(p);
      all_sigmas.push_back(sigma);
    }
  }
  Ensemble3Options o;
  o.samples = fig.samples;
  o.dist = ReleaseDist::Disk;
  o.seed = static_cast<std::uint64_t>(setting(fig, "seed", 1.0));
  o.threads = threads;
  o.keep_samples = true;  // for the means over the exited samples
  const std::vector<Ensemble3Result> results = run_sweep_3d(all_points, all_sigmas, o, progress);
  for (std::size_t j = 0; j < all_points.size(); ++j) {
    const Ensemble3Result& r = results[j];
    std::vector<std::string> row{fig.panels.front().id, number(all_sigmas[j]), number(all_points[j].theta)};
    for (const std::string& name : names) {
      const Summary s = point_summary(r, name);
      row.push_back(number(s.mean));
      row.push_back(number(s.sem));
    }
    for (const std::int64_t c : {r.exited, r.trapped, r.periodic, r.total_collisions}) row.push_back(std::to_string(c));
    out.csv += csv_line(row);
    check_of[{all_sigmas[j], all_points[j].theta}] = point_summary(r, check_obs).mean;
    collisions += r.total_collisions;
  }
  out.extra["total_collisions"] = collisions;

  // The check: the ratio above/below 45 degrees of the check's observable for every sigma. The
  // claim holds when it exceeds min_ratio for sigma = 0 (the paper's cone), stays above
  // min_ratio_off_plane for every sigma > 0 (the anomaly survives) and does not grow with sigma
  // (it weakens).
  const double below = check_number(fig, "below", 44.0), above = check_number(fig, "above", 46.0);
  const double min_ratio = check_number(fig, "min_ratio", 2.0);
  const double min_off = check_number(fig, "min_ratio_off_plane", 1.5);
  std::string measured = "mean " + check_obs + " " + fmt(above) + "°/" + fmt(below) + "°:";
  bool holds = true;
  double previous = std::numeric_limits<double>::infinity();
  nlohmann::ordered_json ratios = nlohmann::ordered_json::array();
  for (const double s : sigmas) {
    const auto hi = check_of.find({s, above}), lo = check_of.find({s, below});
    const double ratio = hi != check_of.end() && lo != check_of.end() ? hi->second / lo->second : std::nan("");
    measured += " " + fmt(ratio, 3) + " at σ = " + fmt(s) + ",";
    ratios.push_back({{"velocity_sd", s}, {"ratio", ratio}});
    holds = holds && ratio > (s == 0.0 ? min_ratio : min_off) && ratio <= previous;
    previous = ratio;
  }
  measured.back() = '.';
  out.extra["ratios"] = ratios;
  out.check = verdict(claim_of(fig), measured, holds);
  return out;
}

}  // namespace funnel::paper
