// The cone in 3D with random sideways release velocities (beyond the paper), as figure data.
#include "paper_cone3d.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include "cli_common.hpp"
#include "funnel/ensemble3d.hpp"
#include "funnel/observables.hpp"
#include "output.hpp"
#include "paper_util.hpp"

namespace funnel::cli {

FigureData cone_3d_sweep(const FigureSpec& fig, int threads, const Progress& progress) {
  std::vector<double> sigmas;
  if (const toml::array* a = fig.settings["velocity_sds"].as_array()) {
    for (const auto& v : *a) sigmas.push_back(v.value<double>().value_or(std::nan("")));
  }
  if (sigmas.empty()) sigmas.push_back(0.0);
  std::vector<Params> points;
  for (const Params& p : expand_grid(panel_params(fig, fig.panels.front()), fig.grid)) points.push_back(p);

  FigureData out;
  std::vector<std::string> cols{"panel", "velocity_sd", "theta"};
  for (const std::string& o : fig.observables) {
    cols.push_back(o + "_mean");
    cols.push_back(o + "_sem");
  }
  for (const char* c : {"orbits_mean", "exited", "trapped", "total_collisions"}) cols.emplace_back(c);
  out.csv = csv_line(cols);
  out.extra["beyond_paper"] = true;
  out.extra["samples"] = fig.samples;

  std::map<std::pair<double, double>, double> duration_of;  // (sigma, theta) -> mean duration
  std::int64_t collisions = 0;
  const auto n_sigma = static_cast<std::int64_t>(sigmas.size());
  for (std::size_t i = 0; i < sigmas.size(); ++i) {
    Ensemble3Options o;
    o.samples = fig.samples;
    o.dist = ReleaseDist::Disk;
    o.velocity_sd = sigmas[i];
    o.seed = static_cast<std::uint64_t>(setting(fig, "seed", 1.0));
    o.threads = threads;
    const auto k = static_cast<std::int64_t>(i);
    const std::vector<Ensemble3Result> results = run_sweep_3d(points, o, [&](std::int64_t d, std::int64_t t) {
      if (progress) progress(k * t + d, n_sigma * t);
    });
    const std::string& panel = fig.panels.front().id;  // one panel; velocity_sd is the series
    for (std::size_t j = 0; j < points.size(); ++j) {
      const Ensemble3Result& r = results[j];
      std::vector<std::string> row{panel, number(sigmas[i]), number(points[j].theta)};
      for (const std::string& name : fig.observables) {
        const ObservableInfo* info = find_observable(name);
        const Summary s = info != nullptr ? r[info->id] : Summary{};
        row.push_back(number(s.mean));
        row.push_back(number(s.sem));
      }
      row.push_back(number(r[Observable::Orbits].mean));
      row.push_back(std::to_string(r.exited));
      row.push_back(std::to_string(r.trapped));
      row.push_back(std::to_string(r.total_collisions));
      out.csv += csv_line(row);
      duration_of[{sigmas[i], points[j].theta}] = r[Observable::Duration].mean;
      collisions += r.total_collisions;
    }
  }
  out.extra["total_collisions"] = collisions;

  const double below = check_number(fig, "below", 44.0), above = check_number(fig, "above", 46.0);
  const double min_ratio = check_number(fig, "min_ratio", 2.0);
  std::string measured = "mean duration " + fmt(above) + "°/" + fmt(below) + "°:";
  bool holds = true;
  nlohmann::ordered_json ratios = nlohmann::ordered_json::array();
  for (const double s : sigmas) {
    const auto hi = duration_of.find({s, above}), lo = duration_of.find({s, below});
    const double ratio = hi != duration_of.end() && lo != duration_of.end() ? hi->second / lo->second : std::nan("");
    measured += " " + fmt(ratio, 3) + " at σ = " + fmt(s) + ",";
    ratios.push_back({{"velocity_sd", s}, {"ratio", ratio}});
    holds = holds && ratio > min_ratio;
  }
  measured.back() = '.';
  out.extra["duration_ratios"] = ratios;
  out.check = verdict(claim_of(fig), measured, holds);
  return out;
}

}  // namespace funnel::cli
