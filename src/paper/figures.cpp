// Data and claim checks of each kind of figure (see paper/*.toml and docs/paper.md).
#include "funnel/paper/figures.hpp"

#include "funnel/observables.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>

#include "funnel/closed.hpp"
#include "funnel/engine.hpp"
#include "funnel/orbit.hpp"
#include "funnel/paper/records.hpp"
#include "cone3d.hpp"
#include "designer.hpp"
#include "orbits.hpp"
#include "util.hpp"

namespace funnel::paper {

namespace {

ReleaseDist dist_of(const std::string& text) { return *parse_release_dist(text); }

/// Mean of an observable ("duration", "impulse", "energy_loss", ...) in an ensemble result.
double mean_of(const EnsembleResult& r, const std::string& observable) {
  const ObservableInfo* o = find_observable(observable);
  return o != nullptr ? r[o->id].mean : std::nan("");
}

// ---- theta sweeps (Figs. 2-6, 13) ----

/// The grid points of one panel and release distribution of a theta-sweep figure.
std::vector<Params> sweep_points(const FigureSpec& fig, const PanelSpec& panel) {
  std::vector<Params> points = expand_grid(panel_params(fig, panel), fig.grid);
  if (!panel.theta_right_offset) return points;
  std::vector<Params> kept;
  for (Params p : points) {
    p.theta_right = p.theta + *panel.theta_right_offset;
    if (p.theta_right > 0.0 && p.theta_right < 90.0) kept.push_back(p);
  }
  return kept;
}

/// The series value of a point, as text ("1", "0.99", "disk").
std::string series_text(const FigureSpec& fig, const Params& p, const std::string& dist) {
  if (fig.series == "release_dist") return dist;
  return number(get_parameter(p, fig.series));
}

/// Mean of `observable` at angle `theta` in the check's panel and series.
double sweep_value(const FigureSpec& fig, const SweepCache& cache, const std::string& series, double theta,
                   const std::string& observable) {
  const std::string panel_id = fig.check["panel"].value_or(std::string("a"));
  for (const PanelSpec& panel : fig.panels) {
    if (panel.id != panel_id) continue;
    for (const std::string& dist : fig.dists) {
      for (const Params& p : sweep_points(fig, panel)) {
        if (p.theta == theta && series_text(fig, p, dist) == series) {
          return mean_of(cache.get(p, dist_of(dist), fig.samples), observable);
        }
      }
    }
  }
  return std::nan("");
}

std::string series_value_text(const FigureSpec& fig, const char* key) {
  if (const auto s = fig.check[key].value<std::string>()) return *s;
  return number(fig.check[key].value<double>().value_or(std::nan("")));
}

nlohmann::ordered_json check_sweep(const FigureSpec& fig, const SweepCache& cache) {
  const std::string type = fig.check["type"].value_or(std::string());
  const std::string obs = fig.check["observable"].value_or(std::string("duration"));
  const std::string series = series_value_text(fig, "series_value");
  const double above = check_number(fig, "above", 46.0), below = check_number(fig, "below", 44.0);
  if (type == "ratio_above_below") {
    const double hi = sweep_value(fig, cache, series, above, obs), lo = sweep_value(fig, cache, series, below, obs);
    const double ratio = hi / lo;
    return verdict(claim_of(fig),
                   "mean " + obs + " " + fmt(hi) + " at " + fmt(above) + "° vs " + fmt(lo) + " at " + fmt(below) +
                       "° (" + fig.series + " = " + series + "): ratio " + fmt(ratio, 3),
                   ratio > check_number(fig, "min_ratio", 2.0));
  }
  if (type == "ratio_fades_with_e") {
    const std::string low = series_value_text(fig, "series_low");
    const double r_hi = sweep_value(fig, cache, series, above, obs) / sweep_value(fig, cache, series, below, obs);
    const double r_lo = sweep_value(fig, cache, low, above, obs) / sweep_value(fig, cache, low, below, obs);
    return verdict(claim_of(fig),
                   "ratio of mean " + obs + " at " + fmt(above) + "° to " + fmt(below) + "°: " + fmt(r_hi, 3) +
                       " for " + fig.series + " = " + series + ", " + fmt(r_lo, 3) + " for " + fig.series + " = " + low,
                   r_hi > 1.5 * r_lo);
  }
  if (type == "fraction_above_reference") {
    const double ref_theta = check_number(fig, "reference", 44.0);
    const double ref = sweep_value(fig, cache, series, ref_theta, obs);
    int count = 0, larger = 0;
    const auto axis = std::find_if(fig.grid.begin(), fig.grid.end(), [](const Axis& a) { return a.name == "theta"; });
    for (const double theta : axis == fig.grid.end() ? std::vector<double>{} : axis->values) {
      if (theta <= 45.0) continue;
      ++count;
      larger += sweep_value(fig, cache, series, theta, obs) > ref;
    }
    const double frac = count > 0 ? static_cast<double>(larger) / count : 0.0;
    return verdict(claim_of(fig),
                   fmt(100.0 * frac, 3) + "% of the angles above 45° have a larger mean " + obs + " than " +
                       fmt(ref_theta) + "° (" + fig.series + " = " + series + ")",
                   count > 0 && frac <= check_number(fig, "max_fraction", 0.5));
  }
  return verdict(claim_of(fig), "no check defined", false);
}

FigureData theta_sweep(const FigureSpec& fig, const SweepCache& cache) {
  FigureData out;
  std::vector<std::string> cols{"panel"};
  for (const auto& c : param_columns()) cols.push_back(c);
  cols.emplace_back("release_dist");
  for (const auto& c : ensemble_columns()) cols.push_back(c);
  out.csv = csv_line(cols);
  for (const PanelSpec& panel : fig.panels) {
    for (const std::string& dist : fig.dists) {
      for (const Params& p : sweep_points(fig, panel)) {
        std::vector<std::string> row{panel.id};
        for (const auto& v : param_row(p)) row.push_back(v);
        row.push_back(dist);
        for (const auto& v : ensemble_row(cache.get(p, dist_of(dist), fig.samples))) row.push_back(v);
        out.csv += csv_line(row);
      }
    }
  }
  out.check = check_sweep(fig, cache);
  return out;
}

// ---- Fig. 7: duration vs release position ----

/// Fraction of neighbouring releases whose durations agree within `tol` (relative).
double smoothness(const std::vector<Sample>& samples, double tol) {
  int close = 0;
  for (std::size_t i = 1; i < samples.size(); ++i) {
    const double a = samples[i - 1].trajectory.duration, b = samples[i].trajectory.duration;
    close += std::fabs(a - b) <= tol * std::max(a, b);
  }
  return samples.size() > 1 ? static_cast<double>(close) / static_cast<double>(samples.size() - 1) : 0.0;
}

FigureData release_scan(const FigureSpec& fig, const SweepRunner& runner, int threads, const Progress& progress) {
  FigureData out;
  out.csv = csv_line({"panel", "theta", "release", "duration", "status", "collisions"});
  out.extra["panels"] = value_panels(fig.thetas, "θ", "°");
  std::map<double, double> smooth;
  const double tol = check_number(fig, "tolerance", 0.05);
  for (std::size_t i = 0; i < fig.thetas.size(); ++i) {
    Params p = panel_params(fig, fig.panels.front());
    p.theta = fig.thetas[i];
    const auto n = static_cast<std::int64_t>(fig.thetas.size());
    const auto k = static_cast<std::int64_t>(i);
    const EnsembleResult r = std::move(
        runner({p}, {fig.samples, dist_of(fig.dists.front()), threads, true}, [&](std::int64_t d, std::int64_t t) {
          if (progress) progress(k * t + d, n * t);
        }).front());
    const std::string panel(1, static_cast<char>('a' + i));
    for (const Sample& s : r.per_sample) {
      out.csv += csv_line({panel, number(p.theta), number(s.fraction), number(s.trajectory.duration),
                           std::string(to_string(s.trajectory.status)), std::to_string(s.trajectory.collisions)});
    }
    smooth[p.theta] = smoothness(r.per_sample, tol);
  }
  const double below = check_number(fig, "below", 44.0), above = check_number(fig, "above", 46.0);
  const double fb = smooth.count(below) ? smooth[below] : std::nan("");
  const double fa = smooth.count(above) ? smooth[above] : std::nan("");
  out.check = verdict(claim_of(fig),
                      "neighbouring releases with durations within " + fmt(100 * tol, 2) + "%: " + fmt(100 * fb, 3) +
                          "% at " + fmt(below) + "°, " + fmt(100 * fa, 3) + "% at " + fmt(above) + "°",
                      fa > 1.5 * fb);
  return out;
}

// ---- Fig. 8: two trajectories ----

/// Longest run of face collisions that alternate between the walls.
int longest_alternation(const std::vector<Event>& events) {
  int best = 0, run = 0;
  std::optional<Wall> last;
  for (const Event& e : events) {
    if (e.kind != EventKind::Face) continue;
    run = last && *e.wall != *last ? run + 1 : 1;
    best = std::max(best, run);
    last = e.wall;
  }
  return best;
}

FigureData trajectories(const FigureSpec& fig) {
  FigureData out;
  std::vector<std::string> cols{"panel", "theta"};
  for (const auto& c : event_columns()) cols.push_back(c);
  out.csv = csv_line(cols);
  out.extra["geometry"] = nlohmann::ordered_json::object();
  out.extra["panels"] = value_panels(fig.thetas, "θ", "°");
  std::vector<int> runs;
  std::string measured;
  for (std::size_t i = 0; i < fig.thetas.size(); ++i) {
    Params p = panel_params(fig, fig.panels.front());
    p.theta = fig.thetas[i];
    const Geometry g = make_geometry(p);
    const double release = i < fig.releases.size() ? fig.releases[i] : 0.3;
    EventLog log;
    simulate_release(p, g, release, &log);
    const std::string panel(1, static_cast<char>('a' + i));
    // The release itself, so that the plotted path starts at the release point.
    Event start;
    start.kind = EventKind::ContactEnd;
    start.position = release_point(g, release);
    std::vector<std::string> first{panel, number(p.theta)};
    for (auto v : event_row(start)) first.push_back(v);
    first[3] = "release";
    out.csv += csv_line(first);
    for (const Event& e : log.events) {
      std::vector<std::string> row{panel, number(p.theta)};
      for (const auto& v : event_row(e)) row.push_back(v);
      out.csv += csv_line(row);
    }
    out.extra["geometry"][panel] = {{"theta", p.theta},         {"radius", g.radius},         {"half_gap", g.half_gap},
                                    {"y_bottom", g.y_bottom},   {"y_release", g.y_release},   {"half_width", g.half_width},
                                    {"y_face_end", g.y_face_end}, {"x_face_end", g.x_face_end}, {"release", release}};
    runs.push_back(longest_alternation(log.events));
    measured += (measured.empty() ? "" : "; ") + std::string("longest run of alternating collisions at ") +
                fmt(p.theta) + "°: " + std::to_string(runs.back());
  }
  const int min_run = static_cast<int>(check_number(fig, "min_run", 20.0));
  const bool holds = runs.size() == 2 && runs[0] >= min_run && runs[1] < min_run;
  out.check = verdict(claim_of(fig), measured, holds);
  return out;
}

// ---- Fig. 10: eigenvalues ----

FigureData eigenvalue_figure(const FigureSpec& fig) {
  FigureData out;
  out.csv = csv_line({"theta", "mod1", "mod2", "mod3", "mod4", "stable"});
  const Params base = panel_params(fig, fig.panels.front());
  int wrong = 0, total = 0;
  for (const Params& p : expand_grid(base, fig.grid)) {
    const orbit::OrbitParams op{p.theta, p.beta0, p.inertia, p.radius};
    const Eigen::Vector4cd ev = orbit::orbit_eigenvalues(op);
    const bool stable = orbit::is_stable(op);
    out.csv += csv_line({number(p.theta), number(std::abs(ev[0])), number(std::abs(ev[1])), number(std::abs(ev[2])),
                         number(std::abs(ev[3])), stable ? "1" : "0"});
    if (p.theta != 45.0) {
      ++total;
      wrong += stable != (p.theta > 45.0);
    }
  }
  out.check = verdict(claim_of(fig),
                      std::to_string(total - wrong) + " of " + std::to_string(total) +
                          " angles (45° excluded) are stable exactly when θ > 45° (β0 = " + fmt(base.beta0) + ")",
                      wrong == 0 && total > 0);
  return out;
}

// ---- Figs. 11 and 12: closed funnel ----

FigureData closed_final(const FigureSpec& fig, int threads, const Progress& progress) {
  FigureData out;
  out.csv = csv_line({"panel", "mu", "release", "state", "x_last_over_L", "x_prev_over_L"});
  out.extra["panels"] = value_panels(fig.mus, "μ", "");
  std::int64_t undecided = 0, asymmetric = 0, periodic = 0, rest = 0;
  std::string fractions;
  for (std::size_t i = 0; i < fig.mus.size(); ++i) {
    Params p = panel_params(fig, fig.panels.front());
    p.mu = fig.mus[i];
    const double half_width = make_geometry(p).half_width;
    const ClosedResult r = run_closed(p, {fig.samples, dist_of(fig.dists.front()), threads, false}, {});
    if (progress) progress(static_cast<std::int64_t>(i + 1), static_cast<std::int64_t>(fig.mus.size()));
    const std::string panel(1, static_cast<char>('a' + i));
    for (const ClosedSample& s : r.samples) {
      out.csv += csv_line({panel, number(p.mu), number(s.fraction), std::string(to_string(s.state)),
                           csv_number(s.x_last / half_width), csv_number(s.x_prev / half_width)});
      if (s.state == FinalState::Periodic && std::fabs(s.x_last + s.x_prev) > 1e-4 * std::fabs(s.x_last)) ++asymmetric;
    }
    undecided += r.undecided;
    periodic += r.periodic;
    rest += r.rest;
    fractions += (fractions.empty() ? "" : ", ") + std::string("μ = ") + fmt(p.mu) + ": " + fmt(100 * r.periodic_fraction, 3) + "%";
  }
  out.check = verdict(claim_of(fig),
                      std::to_string(periodic) + " periodic (" + std::to_string(asymmetric) + " not symmetric), " +
                          std::to_string(rest) + " at rest, " + std::to_string(undecided) +
                          " undecided; periodic fraction " + fractions,
                      undecided == 0 && asymmetric == 0);
  return out;
}

FigureData periodic_fraction(const FigureSpec& fig, int threads, const Progress& progress) {
  FigureData out;
  out.csv = csv_line({"theta", "mu", "periodic_fraction"});
  std::map<std::pair<double, double>, double> frac;
  for (const double theta : fig.thetas) {
    for (const double mu : fig.mus) {
      Params p = panel_params(fig, fig.panels.front());
      p.theta = theta;
      p.mu = mu;
      const ClosedResult r = run_closed(p, {fig.samples, dist_of(fig.dists.front()), threads, false}, {});
      frac[{theta, mu}] = r.periodic_fraction;
      if (progress) progress(static_cast<std::int64_t>(frac.size()), static_cast<std::int64_t>(fig.thetas.size() * fig.mus.size()));
      out.csv += csv_line({number(theta), number(mu), number(r.periodic_fraction)});
    }
  }
  // Grows with mu (up to sampling noise), near 1 at mu = 0.1 for theta >= 60, steeper is higher.
  bool grows = true, steep_high = true, ordered = true;
  for (const double theta : fig.thetas) {
    for (std::size_t i = 1; i < fig.mus.size(); ++i) {
      grows &= frac[{theta, fig.mus[i]}] >= frac[{theta, fig.mus[i - 1]}] - 0.02;
    }
    if (theta >= 60.0) steep_high &= frac[{theta, 0.1}] >= 0.95;
  }
  for (const double mu : fig.mus) ordered &= frac[{fig.thetas.back(), mu}] >= frac[{fig.thetas.front(), mu}] - 0.02;
  std::string measured;
  for (const double theta : fig.thetas) {
    measured += (measured.empty() ? "" : "; ") + std::string("θ = ") + fmt(theta) + "°: " +
                fmt(100 * frac[{theta, fig.mus.front()}], 3) + "% at μ = " + fmt(fig.mus.front()) + " → " +
                fmt(100 * frac[{theta, 0.1}], 3) + "% at μ = 0.1 → " + fmt(100 * frac[{theta, fig.mus.back()}], 3) +
                "% at μ = " + fmt(fig.mus.back());
  }
  out.check = verdict(claim_of(fig), measured, grows && steep_high && ordered);
  return out;
}

}  // namespace

Params SweepCache::canonical(const Params& p) {
  // Without friction beta0 enters no result: Walton's law slides whenever the slip is not 0
  // (mu (1 + e)(1 + 1/kappa)|p| = 0 < (1 + beta0)|s| for beta0 > -1) with a tangential impulse
  // of -0 * J_N = +-0, and sticks only at s = +-0, where -(1 + beta0) s / (1 + 1/kappa) is the same
  // signed zero; the sustained contacts' friction is mu N = 0. Every trajectory, and so every
  // ensemble, is the same bit for bit (test: FrictionlessEnsemblesDoNotDependOnBeta0).
  Params c = p;
  if (c.mu == 0.0 && c.beta0 > -1.0 && !c.profile) c.beta0 = 0.0;
  return c;
}

SweepCache::Key SweepCache::key(const Params& params, ReleaseDist dist, std::int64_t samples) {
  const Params p = canonical(params);
  std::string k;
  for (const std::string& name : sweep_parameter_names()) k += number(get_parameter(p, name)) + ",";
  return {k, static_cast<int>(dist), samples};
}

SweepCache::SweepCache(SweepRunner runner) : runner_(std::move(runner)) {
  if (!runner_) {
    runner_ = [](const std::vector<Params>& points, const EnsembleOptions& options, const Progress& progress) {
      return run_sweep(points, options, progress);
    };
  }
}

void SweepCache::request(const Params& params, ReleaseDist dist, std::int64_t samples) {
  entries_.try_emplace(key(params, dist, samples), Entry{canonical(params), dist, samples, {}, false});
}

void SweepCache::run(int threads, const Progress& progress) {
  // One batch per (distribution, samples): run_sweep keeps every core busy across points.
  std::map<std::pair<int, std::int64_t>, std::vector<Entry*>> batches;
  for (auto& [k, e] : entries_) {
    if (!e.done) batches[{static_cast<int>(e.dist), e.samples}].push_back(&e);
  }
  std::int64_t total_points = 0, done_points = 0;
  for (const auto& [k, list] : batches) total_points += static_cast<std::int64_t>(list.size());
  for (auto& [k, list] : batches) {
    std::vector<Params> points;
    for (const Entry* e : list) points.push_back(e->params);
    const EnsembleOptions opt{k.second, static_cast<ReleaseDist>(k.first), threads, false};
    const auto n = static_cast<std::int64_t>(list.size());
    auto results = runner_(points, opt, [&](std::int64_t d, std::int64_t t) {
      if (progress) progress(done_points * t + d * n, total_points * t);
    });
    for (std::size_t i = 0; i < list.size(); ++i) {
      list[i]->result = std::move(results[i]);
      list[i]->done = true;
    }
    done_points += n;
  }
}

const EnsembleResult& SweepCache::get(const Params& params, ReleaseDist dist, std::int64_t samples) const {
  return entries_.at(key(params, dist, samples)).result;
}

std::int64_t SweepCache::simulated_collisions() const {
  std::int64_t n = 0;
  for (const auto& [k, e] : entries_) n += e.done ? e.result.simulated_collisions : 0;
  return n;
}

std::map<std::string, double> attributed_collisions(const std::vector<FigureSpec>& figs, const SweepCache& cache) {
  std::map<std::string, std::set<const EnsembleResult*>> used;
  std::map<const EnsembleResult*, int> users;
  for (const FigureSpec& fig : figs) {
    auto& mine = used[fig.id];
    if (fig.kind != "theta_sweep") continue;
    for (const PanelSpec& panel : fig.panels) {
      for (const std::string& dist : fig.dists) {
        for (const Params& p : sweep_points(fig, panel)) mine.insert(&cache.get(p, dist_of(dist), fig.samples));
      }
    }
    for (const EnsembleResult* r : mine) ++users[r];
  }
  std::map<std::string, double> share;
  for (const auto& [id, mine] : used) {
    double n = 0.0;
    for (const EnsembleResult* r : mine) n += static_cast<double>(r->simulated_collisions) / users[r];
    share[id] = n;
  }
  return share;
}

void request_sweeps(const FigureSpec& fig, SweepCache& cache) {
  if (fig.kind != "theta_sweep" && fig.kind != "retrace_windows") return;
  for (const PanelSpec& panel : fig.panels) {
    for (const std::string& dist : fig.dists) {
      for (const Params& p : sweep_points(fig, panel)) cache.request(p, dist_of(dist), fig.samples);
    }
  }
}

FigureData compute_figure(const FigureSpec& fig, const SweepCache& cache, int threads, const Progress& progress) {
  if (fig.kind == "theta_sweep") return theta_sweep(fig, cache);
  if (fig.kind == "release_scan") return release_scan(fig, cache.runner(), threads, progress);
  if (fig.kind == "trajectories") return trajectories(fig);
  if (fig.kind == "eigenvalues") return eigenvalue_figure(fig);
  if (fig.kind == "closed_final") return closed_final(fig, threads, progress);
  if (fig.kind == "periodic_fraction") return periodic_fraction(fig, threads, progress);
  if (fig.kind == "funnel_sketch") return funnel_sketch(fig);
  if (fig.kind == "period2_orbits") return period2_orbits(fig);
  if (fig.kind == "retrace_orbits") return retrace_orbits(fig, threads);
  if (fig.kind == "retrace_windows") return retrace_windows(fig, cache, threads);
  if (fig.kind == "wear_profiles") return wear_profiles(fig, threads, progress);
  if (fig.kind == "cone_3d_sweep") return cone_3d_sweep(fig, threads, progress);
  throw InputError("invalid figure definition '" + fig.source + "': unknown kind '" + fig.kind + "'");
}

FigureData compute_figure(const FigureSpec& fig, int threads, const Progress& progress) {
  SweepCache cache;
  request_sweeps(fig, cache);
  cache.run(threads, progress);
  return compute_figure(fig, cache, threads, progress);
}

}  // namespace funnel::paper
