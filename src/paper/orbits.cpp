// Figs. 1, 9, 14 and Fig. 2 explained: geometry, period-2 orbits and self-retracing orbits as figure data.
#include "orbits.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>

#include "funnel/geometry.hpp"
#include "funnel/orbit.hpp"
#include "funnel/retrace.hpp"
#include "funnel/paper/records.hpp"
#include "util.hpp"
#include "funnel/paper/retrace_records.hpp"

namespace funnel::paper {

namespace {

std::string setting_text(const FigureSpec& fig, const char* key, const std::string& fallback) {
  return fig.settings[key].value<std::string>().value_or(fallback);
}

/// A setting holding numbers: an array, a number, or a text list/range "a,b" / "start:stop:step".
std::vector<double> setting_values(const FigureSpec& fig, const char* key, const std::string& fallback) {
  const toml::node* node = fig.settings.get(key);
  std::vector<double> out;
  if (node != nullptr && node->is_array()) {
    for (const toml::node& item : *node->as_array()) out.push_back(item.value<double>().value_or(std::nan("")));
    return out;
  }
  if (node != nullptr && node->value<double>()) return {*node->value<double>()};
  const std::string text = node != nullptr ? node->value<std::string>().value_or(fallback) : fallback;
  std::string reason;
  const auto values = parse_values(text, reason);
  if (!values) throw InputError("invalid figure definition '" + fig.source + "': settings." + key + ": " + reason);
  return *values;
}

/// The derived geometry of a funnel, as the plots need it (the keys of fig08's "geometry").
nlohmann::ordered_json geometry_json(const Params& p, double release) {
  const Geometry g = make_geometry(p);
  return {{"theta", p.theta},         {"radius", g.radius},         {"half_gap", g.half_gap},
          {"y_bottom", g.y_bottom},   {"y_release", g.y_release},   {"half_width", g.half_width},
          {"y_face_end", g.y_face_end}, {"x_face_end", g.x_face_end}, {"release", release}};
}

/// CSV row of a pseudo-event (the release, or the return at the end of a period) of a panel.
std::string marker_row(const std::string& panel, double theta, const char* kind, double time, Vec2 r, Vec2 v) {
  Event e;
  e.kind = EventKind::ContactEnd;
  e.time = time;
  e.position = r;
  e.velocity_before = v;
  e.velocity_after = v;
  std::vector<std::string> row{panel, number(theta)};
  for (auto& s : event_row(e)) row.push_back(s);
  row[3] = kind;
  return csv_line(row);
}

std::string event_line(const std::string& panel, double theta, const Event& e) {
  std::vector<std::string> row{panel, number(theta)};
  for (auto& s : event_row(e)) row.push_back(s);
  return csv_line(row);
}

std::vector<std::string> panel_event_columns() {
  std::vector<std::string> cols{"panel", "theta"};
  for (const auto& c : event_columns()) cols.push_back(c);
  return cols;
}

// ---- self-retracing orbits shared by Fig. 14 and Fig. 2 explained ----

struct RetraceSetup {
  Params params;               ///< funnel of the search (closed unless settings.scan_gap says otherwise)
  std::vector<double> thetas;  ///< search grid, degrees
  retrace::Options options;    ///< rest turns always searched; figures filter by settings.turns
};

RetraceSetup retrace_setup(const FigureSpec& fig, int threads) {
  RetraceSetup s;
  s.params = retrace::frictionless(panel_params(fig, fig.panels.front()));
  s.params.gap = setting(fig, "scan_gap", 0.0);
  if (const auto err = validate(s.params)) throw InputError("invalid figure definition '" + fig.source + "': " + err->message());
  s.thetas = setting_values(fig, "theta", "30:85:0.05");
  s.options.max_bounces = static_cast<int>(setting(fig, "max_bounces", 6));
  s.options.scan_points = static_cast<int>(setting(fig, "scan_points", 1000));
  s.options.rest_turns = true;
  s.options.threads = threads;
  return s;
}

/// Scans are shared between the figures that ask for the same search.
const std::vector<retrace::Orbit>& cached_scan(const RetraceSetup& s) {
  static std::map<std::string, std::vector<retrace::Orbit>> cache;
  std::string key = number(s.params.radius) + "," + number(s.params.gap) + "," + std::to_string(s.options.max_bounces) +
                    "," + std::to_string(s.options.scan_points);
  for (const double t : s.thetas) key += "," + number(t);
  auto it = cache.find(key);
  if (it == cache.end()) it = cache.emplace(key, retrace::scan(s.params, s.thetas, s.options)).first;
  return it->second;
}

/// The orbits whose turn the figure wants (settings.turns: "wall" or "wall,rest").
std::vector<retrace::Orbit> wanted(const FigureSpec& fig, const std::vector<retrace::Orbit>& orbits) {
  const bool rest = parse_turns(setting_text(fig, "turns", "wall"));
  std::vector<retrace::Orbit> out;
  for (const auto& o : orbits) {
    if (o.turn == retrace::Turn::Wall || rest) out.push_back(o);
  }
  return out;
}

std::string family_name(const std::string& sequence, retrace::Turn turn) {
  return turn == retrace::Turn::Rest ? sequence + " (rest turn)" : sequence;
}

}  // namespace

// ---- Fig. 1 ----

FigureData funnel_sketch(const FigureSpec& fig) {
  FigureData out;
  const Params p = panel_params(fig, fig.panels.front());
  const Geometry g = make_geometry(p);
  const double release = fig.releases.empty() ? 0.4 : fig.releases.front();
  const Vec2 el = edge_point(g, Wall::Left), er = edge_point(g, Wall::Right);
  const Vec2 cl = el + g.radius * face_normal(g, Wall::Left), cr = er + g.radius * face_normal(g, Wall::Right);
  // The wall surfaces run from the edges up along (-cos, sin) and (cos, sin), to above the release line.
  const double top = g.y_release + 0.08;
  const double run = (top - g.y_bottom) / g.sin_t;
  const Vec2 wl{el.x - run * g.cos_t, top}, wr{er.x + run * g.cos_t, top};
  const Vec2 x0 = release_point(g, release);
  out.csv = csv_line({"name", "x", "y"});
  const std::vector<std::pair<const char*, Vec2>> points{
      {"origin", {0.0, 0.0}},      {"release", x0},          {"release_line_left", {-g.half_width, g.y_release}},
      {"release_line_right", {g.half_width, g.y_release}}, {"edge_left", el}, {"edge_right", er},
      {"face_end_left", cl},       {"face_end_right", cr},   {"wall_top_left", wl}, {"wall_top_right", wr},
      {"centre_line_top_left", {-top / g.tan_t, top}},       {"centre_line_top_right", {top / g.tan_t, top}}};
  for (const auto& [name, r] : points) out.csv += csv_line({name, number(r.x), number(r.y)});
  out.extra["geometry"] = geometry_json(p, release);
  out.extra["geometry"]["gap"] = p.gap;
  // The figure's symbols, computed from the geometry module, against their definitions in Sec. II.
  const double h_err = std::fabs(g.y_release - g.y_bottom - 1.0);
  const double l_err = std::fabs(g.half_width * g.tan_t - g.y_release);
  const Vec2 dc = cr - er;
  const double a_err = std::fabs(std::sqrt(dot(dc, dc)) - g.radius) + std::fabs(face_distance(g, Wall::Right, cr));
  // The wall surface is the centre line moved out by a: its distance from the centre line is a.
  const double wall_err = std::fabs(-face_distance(g, Wall::Left, wl) - g.radius);
  const double d_err = std::fabs(er.x - el.x - p.gap);
  const double worst = std::max({h_err, l_err, a_err, wall_err, d_err});
  out.check = verdict(claim_of(fig),
                      "θ = " + fmt(p.theta) + "°: y0 − y_b − H = " + fmt(g.y_release - g.y_bottom - 1.0, 2) +
                          ", L tanθ − y0 = " + fmt(g.half_width * g.tan_t - g.y_release, 2) +
                          ", |C* − E| − a = " + fmt(std::sqrt(dot(dc, dc)) - g.radius, 2) +
                          ", wall-to-centre-line distance − a = " + fmt(-face_distance(g, Wall::Left, wl) - g.radius, 2) +
                          ", edge spacing − d = " + fmt(er.x - el.x - p.gap, 2) + " (all in H)",
                      worst <= 1e-12);
  return out;
}

// ---- Fig. 9 ----

FigureData period2_orbits(const FigureSpec& fig) {
  FigureData out;
  out.csv = csv_line(panel_event_columns());
  const std::vector<double> y_stars = setting_values(fig, "y_star", "0.5,0.4");
  const double ratio = setting(fig, "ratio", 1.6);
  const int collisions = static_cast<int>(setting(fig, "collisions", 40));
  out.extra["geometry"] = nlohmann::ordered_json::object();
  out.extra["orbits"] = nlohmann::ordered_json::object();
  out.extra["panels"] = nlohmann::ordered_json::array();
  std::string measured;
  bool holds = fig.thetas.size() == 2;
  for (std::size_t i = 0; i < fig.thetas.size(); ++i) {
    Params p = panel_params(fig, fig.panels.front());
    p.theta = fig.thetas[i];
    p.max_collisions = collisions;
    const Geometry g = make_geometry(p);
    const orbit::OrbitParams op{p.theta, p.beta0, p.inertia, p.radius};
    const double y_star = i < y_stars.size() ? y_stars[i] : y_stars.back();
    const bool at45 = p.theta == 45.0;
    const orbit::State P = at45 ? orbit::fixed_point_45(y_star, ratio, op) : orbit::fixed_point(y_star, op);
    State s;
    s.r = {-y_star / g.tan_t, y_star};
    s.v = {P[1], P[2]};
    s.omega = P[3];
    EventLog log;
    simulate(p, g, s, &log);
    const std::string panel(1, static_cast<char>('a' + i));
    out.csv += marker_row(panel, p.theta, "start", 0.0, s.r, s.v);
    // Deviation from the orbit: each collision's height from y*, and the state after every second
    // collision (one period) from the starting one, on the scales sqrt(y*) and sqrt(y*)/a.
    double height_dev = 0.0, state_dev = 0.0;
    int faces = 0;
    bool alternates = true;
    std::optional<Wall> last;
    for (const Event& e : log.events) {
      out.csv += event_line(panel, p.theta, e);
      if (e.kind != EventKind::Face) {
        alternates = false;
        continue;
      }
      ++faces;
      alternates = alternates && (!last || *last != *e.wall);
      last = e.wall;
      height_dev = std::max(height_dev, std::fabs(e.position.y - y_star) / y_star);
      if (faces % 2 == 0) {
        const double r = std::sqrt(y_star);
        state_dev = std::max({state_dev, std::fabs(e.velocity_after.x - s.v.x) / r, std::fabs(e.velocity_after.y - s.v.y) / r,
                              std::fabs(e.omega_after - s.omega) * p.radius / r, std::fabs(e.position.x - s.r.x) / y_star});
      }
    }
    const double period = log.events.size() >= 2 ? log.events[1].time : 0.0;
    out.extra["geometry"][panel] = geometry_json(p, 0.0);
    out.extra["orbits"][panel] = {{"theta", p.theta}, {"y_star", y_star}, {"u", P[1]}, {"v", P[2]}, {"omega", P[3]},
                                  {"period", period}, {"collisions", faces}, {"height_deviation", height_dev},
                                  {"state_deviation", state_dev}};
    const std::string label = at45 ? "θ = 45°: rotating family, u′/v′ = " + fmt(ratio) + ", ω′ = " + fmt(P[3], 3)
                                   : "θ = " + fmt(p.theta) + "°: perpendicular impacts at y* = " + fmt(y_star);
    out.extra["panels"].push_back({{"id", panel}, {"label", label}});
    measured += (measured.empty() ? "" : "; ") + std::string("(") + panel + ") θ = " + fmt(p.theta) + "°: " +
                std::to_string(faces) + " collisions, heights within " + fmt(height_dev, 2) + " of y*, state after each period within " +
                fmt(state_dev, 2) + (alternates ? ", walls alternate" : ", walls do NOT alternate");
    holds = holds && faces == collisions && alternates && height_dev <= 1e-9 && state_dev <= 1e-9 && at45 == (i == 1);
  }
  out.check = verdict(claim_of(fig), measured, holds);
  return out;
}

// ---- Fig. 14 ----

FigureData retrace_orbits(const FigureSpec& fig, int threads) {
  FigureData out;
  const RetraceSetup setup = retrace_setup(fig, threads);
  const std::vector<retrace::Orbit> orbits = wanted(fig, cached_scan(setup));
  const auto wins = retrace::windows(orbits, setup.thetas);
  // Families with a stability window, simplest first: fewest collisions per period, then the widest window.
  struct Family {
    retrace::Window widest;
    int per_period;
  };
  std::map<std::pair<std::string, int>, Family> families;
  for (const auto& w : wins) {
    if (!w.stable) continue;
    const int per = w.turn == retrace::Turn::Wall ? 2 * static_cast<int>(w.sequence.size()) - 1 : 2 * static_cast<int>(w.sequence.size());
    auto [it, fresh] = families.try_emplace({w.sequence, static_cast<int>(w.turn)}, Family{w, per});
    if (!fresh && w.points > it->second.widest.points) it->second.widest = w;
  }
  std::vector<Family> ranked;
  for (const auto& [k, f] : families) ranked.push_back(f);
  std::sort(ranked.begin(), ranked.end(), [](const Family& a, const Family& b) {
    if (a.per_period != b.per_period) return a.per_period < b.per_period;
    if (a.widest.points != b.widest.points) return a.widest.points > b.widest.points;
    return a.widest.sequence < b.widest.sequence;
  });
  const std::size_t count = static_cast<std::size_t>(setting(fig, "count", 3));
  if (ranked.size() > count) ranked.resize(count);

  out.csv = csv_line(panel_event_columns());
  out.extra["geometry"] = nlohmann::ordered_json::object();
  out.extra["panels"] = nlohmann::ordered_json::array();
  out.extra["orbits"] = nlohmann::ordered_json::array();
  std::string measured;
  bool holds = ranked.size() == count;
  for (std::size_t i = 0; i < ranked.size(); ++i) {
    const retrace::Window& w = ranked[i].widest;
    // Drawn at the middle grid angle of its widest stability window.
    const auto first = std::find(setup.thetas.begin(), setup.thetas.end(), w.theta_from);
    if (setup.thetas.end() - first < w.points) {
      holds = false;
      continue;
    }
    const double theta = *(first + (w.points - 1) / 2);
    const auto o = std::find_if(orbits.begin(), orbits.end(), [&](const retrace::Orbit& x) {
      return x.theta == theta && x.sequence == w.sequence && x.turn == w.turn && x.stable;
    });
    if (o == orbits.end()) {
      holds = false;
      continue;
    }
    Params p = setup.params;
    p.theta = theta;
    p.t_max = o->period;
    const Geometry g = make_geometry(p);
    EventLog log;
    const Trajectory t = simulate_release(p, g, o->release, &log);
    const retrace::ReturnCheck rc = retrace::check_return(setup.params, *o);
    const std::string panel(1, static_cast<char>('a' + i));
    out.csv += marker_row(panel, theta, "release", 0.0, release_point(g, o->release), {0.0, 0.0});
    for (const Event& e : log.events) out.csv += event_line(panel, theta, e);
    out.csv += marker_row(panel, theta, "return", o->period, t.final_state.r, t.final_state.v);
    out.extra["geometry"][panel] = geometry_json(p, o->release);
    const std::string name = family_name(o->sequence, o->turn);
    out.extra["panels"].push_back({{"id", panel}, {"label", name + ", θ = " + fmt(theta) + "°"}});
    nlohmann::ordered_json oj = orbit_json({*o, rc});
    oj["window_from"] = w.theta_from;
    oj["window_to"] = w.theta_to;
    out.extra["orbits"].push_back(oj);
    measured += (measured.empty() ? "" : "; ") + name + " (" + std::to_string(o->collisions_per_period) +
                " collisions per period; stable for θ in " + fmt(w.theta_from) + "–" + fmt(w.theta_to) + "°; at " + fmt(theta) +
                "°: x0/L = " + fmt(o->release, 6) + ", period " + fmt(o->period, 5) + ", trace " + fmt(o->trace, 3) +
                "): back to rest within " + fmt(std::max(rc.position_error, rc.speed), 2);
    holds = holds && !rc.left && rc.position_error <= 1e-12 && rc.speed <= 1e-12;
  }
  out.extra["search"] = {{"theta_first", setup.thetas.front()}, {"theta_last", setup.thetas.back()},
                         {"theta_count", setup.thetas.size()}, {"max_bounces", setup.options.max_bounces},
                         {"scan_points", setup.options.scan_points}, {"turns", setting_text(fig, "turns", "wall")},
                         {"gap", setup.params.gap}};
  out.check = verdict(claim_of(fig), measured, holds);
  return out;
}

// ---- Fig. 2 explained (beyond the paper) ----

namespace {

/// A run of consecutive grid angles where the mean duration stands out of its neighbourhood.
struct Peak {
  double from = 0.0, to = 0.0;         ///< first and last grid angle of the run, degrees
  double theta_max = 0.0, max = 0.0;   ///< the highest point of the run
  double ratio = 0.0;                  ///< max / running median there
  std::vector<std::string> families;   ///< stable families whose window meets the run's cells
};

/// Median of the values whose angle lies within `half` degrees of each angle.
std::vector<double> running_median(const std::vector<double>& theta, const std::vector<double>& y, double half) {
  std::vector<double> out(y.size());
  for (std::size_t i = 0; i < y.size(); ++i) {
    std::vector<double> near;
    for (std::size_t j = 0; j < y.size(); ++j) {
      if (std::fabs(theta[j] - theta[i]) <= half + 1e-9) near.push_back(y[j]);
    }
    std::nth_element(near.begin(), near.begin() + static_cast<std::ptrdiff_t>(near.size() / 2), near.end());
    out[i] = near[near.size() / 2];
  }
  return out;
}

/// True if a window [from, to] meets the cells [a - h/2, b + h/2] of grid angles a..b.
bool meets(const retrace::Window& w, double a, double b, double h) {
  return w.theta_to >= a - 0.5 * h && w.theta_from <= b + 0.5 * h;
}

}  // namespace

FigureData retrace_windows(const FigureSpec& fig, const SweepCache& cache, int threads) {
  FigureData out;
  // The measured curve: the figure's theta sweep (shared with Fig. 2).
  const PanelSpec& panel = fig.panels.front();
  const Params base = panel_params(fig, panel);
  std::vector<double> theta, mean, sem;
  for (const Params& p : expand_grid(base, fig.grid)) {
    const EnsembleResult& r = cache.get(p, *parse_release_dist(fig.dists.front()), fig.samples);
    theta.push_back(p.theta);
    mean.push_back(r[Observable::Duration].mean);
    sem.push_back(r[Observable::Duration].sem);
  }
  const double h = theta.size() > 1 ? theta[1] - theta[0] : 1.0;
  // The orbits: found in the closed funnel, then carried over to the figure's (open) funnel,
  // where only those that stay above the faces' lower ends exist.
  const RetraceSetup setup = retrace_setup(fig, threads);
  std::vector<retrace::Orbit> open;
  for (const retrace::Orbit& o : wanted(fig, cached_scan(setup))) {
    if (o.release > 0.0) continue;  // mirror images: the same families
    if (const auto t = retrace::transfer(o, base, setup.options)) open.push_back(*t);
  }
  const auto wins = retrace::windows(open, setup.thetas);
  std::vector<retrace::Window> stable;
  for (const auto& w : wins) {
    if (w.stable) stable.push_back(w);
  }

  const double above = check_number(fig, "above", 45.0);
  const double half = check_number(fig, "median_halfwidth", 5.0);
  const double min_ratio = check_number(fig, "min_ratio", 1.3);
  const std::vector<double> baseline = running_median(theta, mean, half);
  std::vector<Peak> peaks;
  std::vector<bool> covered(theta.size(), false), elevated(theta.size(), false);
  for (std::size_t i = 0; i < theta.size(); ++i) {
    for (const auto& w : stable) covered[i] = covered[i] || meets(w, theta[i], theta[i], h);
    elevated[i] = theta[i] > above && mean[i] > min_ratio * baseline[i];
    if (!elevated[i]) continue;
    if (i == 0 || !elevated[i - 1]) peaks.push_back({theta[i], theta[i], theta[i], mean[i], mean[i] / baseline[i], {}});
    Peak& pk = peaks.back();
    pk.to = theta[i];
    if (mean[i] > pk.max) {
      pk.max = mean[i];
      pk.theta_max = theta[i];
      pk.ratio = mean[i] / baseline[i];
    }
  }
  int explained = 0;
  for (Peak& pk : peaks) {
    std::set<std::string> names;
    for (const auto& w : stable) {
      if (meets(w, pk.from, pk.to, h)) names.insert(family_name(w.sequence, w.turn));
    }
    pk.families.assign(names.begin(), names.end());
    explained += !pk.families.empty();
  }
  double in_sum = 0.0, out_sum = 0.0;
  int in_n = 0, out_n = 0;
  for (std::size_t i = 0; i < theta.size(); ++i) {
    if (theta[i] <= above) continue;
    (covered[i] ? in_sum : out_sum) += mean[i];
    (covered[i] ? in_n : out_n) += 1;
  }
  const double in_mean = in_n > 0 ? in_sum / in_n : std::nan(""), out_mean = out_n > 0 ? out_sum / out_n : std::nan("");

  out.csv = csv_line({"theta", "duration_mean", "duration_sem", "baseline", "elevated", "covered"});
  for (std::size_t i = 0; i < theta.size(); ++i) {
    out.csv += csv_line({number(theta[i]), number(mean[i]), number(sem[i]), number(baseline[i]), elevated[i] ? "1" : "0",
                         covered[i] ? "1" : "0"});
  }
  out.extra["windows"] = nlohmann::ordered_json::array();
  for (const auto& w : wins) out.extra["windows"].push_back(window_json(w));
  out.extra["peaks"] = nlohmann::ordered_json::array();
  std::string list, missing;
  for (const Peak& pk : peaks) {
    out.extra["peaks"].push_back({{"from", pk.from}, {"to", pk.to}, {"theta_max", pk.theta_max}, {"mean_max", pk.max},
                                  {"ratio", pk.ratio}, {"explained", !pk.families.empty()}, {"families", pk.families}});
    const std::string range = pk.from == pk.to ? fmt(pk.from) + "°" : fmt(pk.from) + "–" + fmt(pk.to) + "°";
    if (pk.families.empty()) {
      missing += (missing.empty() ? "" : ", ") + range;
      continue;
    }
    std::string names;
    for (const auto& n : pk.families) names += (names.empty() ? "" : ", ") + n;
    list += (list.empty() ? "" : "; ") + range + " (" + names + ")";
  }
  out.extra["coverage"] = {{"mean_in_stable_windows", in_mean}, {"mean_elsewhere", out_mean},
                           {"angles_in", in_n}, {"angles_elsewhere", out_n}};
  out.extra["search"] = {{"theta_first", setup.thetas.front()}, {"theta_last", setup.thetas.back()},
                         {"theta_count", setup.thetas.size()}, {"max_bounces", setup.options.max_bounces},
                         {"scan_points", setup.options.scan_points}, {"turns", setting_text(fig, "turns", "wall")},
                         {"gap", base.gap}};
  const double min_share = check_number(fig, "min_share", 0.5);
  const double min_contrast = check_number(fig, "min_contrast", 1.5);
  out.check = verdict(claim_of(fig),
                      std::to_string(explained) + " of " + std::to_string(peaks.size()) +
                          " peaks above " + fmt(above) + "° lie in a stability window: " + list +
                          (missing.empty() ? "" : "; not explained: " + missing) + ". Mean duration " + fmt(in_mean, 3) +
                          " at the angles of a stability window vs " + fmt(out_mean, 3) + " elsewhere (θ > " + fmt(above) + "°).",
                      !peaks.empty() && explained >= min_share * static_cast<double>(peaks.size()) &&
                          in_mean > min_contrast * out_mean);
  return out;
}

}  // namespace funnel::paper
