// Where the walls wear (beyond the paper): ensembles with a wear record, as figure data.
#include "designer.hpp"

#include <cmath>

#include "funnel/geometry.hpp"
#include "funnel/observables.hpp"
#include "funnel/paper/records.hpp"
#include "util.hpp"

namespace funnel::paper {

FigureData wear_profiles(const FigureSpec& fig, int threads, const Progress& progress) {
  FigureData out;
  const int bins = static_cast<int>(setting(fig, "bins", 40.0));
  out.csv = csv_line({"panel", "theta", "wall", "bin", "height", "s", "collisions", "normal_impulse", "impulse",
                      "collisions_per_length", "normal_impulse_per_length", "impulse_per_length"});
  out.extra["panels"] = value_panels(fig.thetas, "θ", "°");
  out.extra["beyond_paper"] = true;
  out.extra["bins"] = bins;
  nlohmann::ordered_json totals = nlohmann::ordered_json::array();
  std::map<double, double> impulse_of;
  for (std::size_t i = 0; i < fig.thetas.size(); ++i) {
    Params p = panel_params(fig, fig.panels.front());
    p.theta = fig.thetas[i];
    const Geometry g = make_geometry(p);
    EnsembleOptions opt{fig.samples, ReleaseDist::Line, threads, false};
    opt.wear_bins = bins;
    const auto n = static_cast<std::int64_t>(fig.thetas.size());
    const auto k = static_cast<std::int64_t>(i);
    const EnsembleResult r = run_ensemble(p, opt, [&](std::int64_t d, std::int64_t t) {
      if (progress) progress(k * t + d, n * t);
    });
    const std::string panel(1, static_cast<char>('a' + i));
    const Wear& w = r.wear;
    double edge_impulse = 0.0, face_impulse = 0.0;
    for (const Wall wall : {Wall::Left, Wall::Right}) {
      const WallWear& ww = w[wall];
      const std::string side(to_string(wall));
      const double width = w.width(wall);
      for (int b = 0; b < w.bins; ++b) {
        const auto j = static_cast<std::size_t>(b);
        const double s = (b + 0.5) * width;
        out.csv += csv_line({panel, number(p.theta), side, std::to_string(b), number(s * g.sin_t), number(s),
                             number(ww.collisions[j]), number(ww.normal_impulse[j]), number(ww.impulse[j]),
                             number(ww.collisions[j] / width), number(ww.normal_impulse[j] / width),
                             number(ww.impulse[j] / width)});
        face_impulse += ww.impulse[j];
      }
      out.csv += csv_line({panel, number(p.theta), side, "edge", "0", "0", number(ww.edge_collisions),
                           number(ww.edge_normal_impulse), number(ww.edge_impulse), "nan", "nan", "nan"});
      edge_impulse += ww.edge_impulse;
    }
    impulse_of[p.theta] = r[Observable::Impulse].mean;
    totals.push_back({{"theta", p.theta},
                      {"bin_width", w.width(Wall::Left)},
                      {"impulse_per_particle", r[Observable::Impulse].mean},
                      {"face_impulse", face_impulse},
                      {"edge_impulse", edge_impulse},
                      {"exit_speed_mean", r[Observable::ExitSpeed].mean}});
  }
  out.extra["totals"] = totals;
  const double below = check_number(fig, "below", 44.0), above = check_number(fig, "above", 46.0);
  const double lo = impulse_of.count(below) ? impulse_of[below] : std::nan("");
  const double hi = impulse_of.count(above) ? impulse_of[above] : std::nan("");
  std::string measured = "impulse on the walls per particle:";
  for (const auto& [theta, impulse] : impulse_of) measured += " " + fmt(impulse) + " at " + fmt(theta) + "°,";
  measured.back() = ';';
  measured += " ratio " + fmt(above) + "°/" + fmt(below) + "° = " + fmt(hi / lo, 3);
  out.check = verdict(claim_of(fig), measured, hi > check_number(fig, "min_ratio", 2.0) * lo);
  return out;
}

}  // namespace funnel::paper
