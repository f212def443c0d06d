// Loading the figure definitions of paper/*.toml.
#include "funnel/paper/cases.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "funnel/ensemble.hpp"
#include "funnel/paper/records.hpp"
#include "funnel/paper/retrace_records.hpp"


namespace funnel::paper {

namespace {

[[noreturn]] void fail(const std::string& file, const std::string& what) {
  throw InputError("invalid figure definition '" + file + "': " + what);
}

double number_of(const toml::node& node, const std::string& file, const std::string& key) {
  const auto v = node.value<double>();
  if (!v) fail(file, "'" + key + "' must be a number");
  return *v;
}

std::vector<double> numbers_of(const toml::node& node, const std::string& file, const std::string& key) {
  std::vector<double> out;
  if (const toml::array* arr = node.as_array()) {
    for (const toml::node& item : *arr) out.push_back(number_of(item, file, key));
  } else if (const auto text = node.value<std::string>()) {
    std::string reason;
    auto values = parse_values(*text, reason);
    if (!values) fail(file, "'" + key + "': " + reason);
    out = *values;
  } else {
    out.push_back(number_of(node, file, key));
  }
  return out;
}

std::vector<std::string> strings_of(const toml::node& node, const std::string& file, const std::string& key) {
  std::vector<std::string> out;
  if (const toml::array* arr = node.as_array()) {
    for (const toml::node& item : *arr) {
      const auto s = item.value<std::string>();
      if (!s) fail(file, "'" + key + "' must hold strings");
      out.push_back(*s);
    }
  } else if (const auto s = node.value<std::string>()) {
    out.push_back(*s);
  } else {
    fail(file, "'" + key + "' must be a string or an array of strings");
  }
  return out;
}

std::string canonical(std::string key) {
  std::replace(key.begin(), key.end(), '_', '-');
  return key;
}

bool is_model_parameter(const std::string& key) {
  const auto& names = sweep_parameter_names();
  return std::find(names.begin(), names.end(), key) != names.end();
}

void read_params(const toml::table& table, std::map<std::string, double>& into, const std::string& file) {
  for (auto&& [k, node] : table) {
    const std::string key = canonical(std::string(k.str()));
    if (key == "id" || key == "label") continue;
    if (!is_model_parameter(key)) fail(file, "unknown parameter '" + std::string(k.str()) + "'");
    into[key] = number_of(node, file, key);
  }
}

/// The kinds compute_figure knows (src/paper/figures.cpp).
const std::vector<std::string>& known_kinds() {
  static const std::vector<std::string> kinds{"theta_sweep",   "release_scan",      "trajectories",   "eigenvalues",
                                              "closed_final",  "periodic_fraction", "funnel_sketch",  "period2_orbits",
                                              "retrace_orbits", "retrace_windows",  "wear_profiles",  "cone_3d_sweep"};
  return kinds;
}

std::string joined(const std::vector<std::string>& items) {
  std::string out;
  for (const std::string& s : items) out += (out.empty() ? "" : ", ") + s;
  return out;
}

/// One [settings] value: each of its numbers must satisfy `ok` (integers where `integer`).
void check_setting(const FigureSpec& fig, const std::string& key, const toml::node& node, bool integer,
                   bool (*ok)(double), const std::string& range) {
  for (const double v : numbers_of(node, fig.source, "settings." + key)) {
    if (!ok(v) || (integer && v != std::floor(v))) {
      fail(fig.source, "invalid settings." + key + " = " + format_number(v) + ": valid range is " + range);
    }
  }
}

/// The kind-specific [settings] (with [quick.settings] merged under --quick): every key known,
/// every value in its range, as the command line's options of the same meaning are.
void validate_settings(const FigureSpec& fig) {
  for (auto&& [k, node] : fig.settings) {
    const std::string key(k.str());
    if (key == "theta") {
      check_setting(fig, key, node, false, [](double v) { return v > 0.0 && v < 90.0; }, "0 < theta < 90 (degrees)");
    } else if (key == "max_bounces") {
      check_setting(fig, key, node, true, [](double v) { return v >= 1.0 && v <= 20.0; }, "an integer 1 <= max_bounces <= 20");
    } else if (key == "scan_points") {
      check_setting(fig, key, node, true, [](double v) { return v >= 16.0 && v <= 1e6; },
                    "an integer 16 <= scan_points <= 10^6");
    } else if (key == "count" || key == "collisions") {
      check_setting(fig, key, node, true, [](double v) { return v >= 1.0 && v <= 1e6; }, "an integer 1 <= " + key + " <= 10^6");
    } else if (key == "bins") {
      check_setting(fig, key, node, true, [](double v) { return v >= 1.0 && v <= 1e4; }, "an integer 1 <= bins <= 10^4");
    } else if (key == "seed") {
      check_setting(fig, key, node, true, [](double v) { return v >= 0.0 && v < 9.0e15; }, "an integer 0 <= seed < 9e15");
    } else if (key == "velocity_sds") {
      check_setting(fig, key, node, false, [](double v) { return v >= 0.0 && v <= 1000.0; },
                    "0 <= velocity_sds <= 1000 (units of sqrt(gH))");
    } else if (key == "y_star" || key == "ratio") {
      check_setting(fig, key, node, false, [](double v) { return v > 0.0 && std::isfinite(v); }, key + " > 0 (finite)");
    } else if (key == "scan_gap") {
      check_setting(fig, key, node, false, [](double v) { return v >= 0.0 && std::isfinite(v); }, "scan_gap >= 0 (finite)");
      Params p = panel_params(fig, fig.panels.front());
      p.gap = numbers_of(node, fig.source, key).front();
      p.e = 1.0;
      p.mu = 0.0;
      if (const auto err = validate(p)) fail(fig.source, "settings.scan_gap: " + err->message());
    } else if (key == "turns") {
      const auto text = node.value<std::string>();
      if (!text) fail(fig.source, "settings.turns must be a string: wall or wall,rest");
      try {
        (void)parse_turns(*text);
      } catch (const InputError& e) {
        fail(fig.source, std::string(e.what()) + " (settings.turns)");
      }
    } else {
      fail(fig.source, "unknown setting '" + key + "'; valid settings are theta, max_bounces, scan_points, turns, "
                       "scan_gap, count, y_star, ratio, collisions, velocity_sds, seed, bins");
    }
  }
}

/// The [check] table: every key known, each a number or a text as the checks read it (an unknown
/// key, or tolerance = "x", was ignored and the check "held" against its default).
void validate_check(const FigureSpec& fig) {
  static const std::vector<std::string> texts{"claim", "type", "observable", "panel"};
  static const std::vector<std::string> numbers{"above", "below", "max_fraction", "median_halfwidth", "min_contrast",
                                                "min_ratio", "min_ratio_off_plane", "min_run", "min_share",
                                                "reference", "tolerance"};
  static const std::vector<std::string> either{"series_value", "series_low"};  // a series value: text or number
  const auto known = [](const std::vector<std::string>& keys, const std::string& key) {
    return std::find(keys.begin(), keys.end(), key) != keys.end();
  };
  for (auto&& [k, node] : fig.check) {
    const std::string key(k.str());
    if (known(texts, key)) {
      if (!node.is_string()) fail(fig.source, "[check] " + key + " must be a text (in quotes)");
    } else if (known(numbers, key)) {
      const auto v = node.value<double>();
      if (!v || !std::isfinite(*v)) fail(fig.source, "[check] " + key + " must be a finite number");
    } else if (known(either, key)) {
      if (!node.is_string() && !node.is_number()) fail(fig.source, "[check] " + key + " must be a number or a text");
    } else {
      std::string valid;
      for (const auto* list : {&texts, &numbers, &either}) {
        for (const std::string& name : *list) valid += (valid.empty() ? "" : ", ") + name;
      }
      fail(fig.source, "unknown [check] key '" + key + "'; valid keys are " + valid);
    }
  }
}

/// Every parameter set the figure can run, checked as the command line checks its own, before
/// any work: each panel at each grid point, and at each of the figure's thetas, mus and release
/// positions (a definition read through --paper-dir ran at theta = 95 or e = 7 without a word).
void validate_figure(const FigureSpec& fig) {
  const std::string& file = fig.source;
  for (const Axis& a : fig.grid) {
    if (a.values.empty()) fail(file, "[grid] " + a.name + " has no values");
  }
  // The 2D figures' release distributions, for the check that the funnel takes them (disk
  // releases in a mirror-symmetric funnel only), as the command line checks its own.
  std::vector<EnsembleOptions> releases;
  if (fig.kind != "cone_3d_sweep") {
    for (const std::string& d : fig.dists) {
      if (const auto dist = parse_release_dist(d)) {
        EnsembleOptions o;
        o.dist = *dist;
        releases.push_back(o);
      }
    }
  }
  for (const PanelSpec& panel : fig.panels) {
    const std::string where = fig.panels.size() > 1 ? " (panel '" + panel.id + "')" : "";
    Params base = panel_params(fig, panel);
    // theta given with both walls' angles would change nothing (refused on the command line).
    std::vector<GivenParameter> given;
    for (const auto* params : {&fig.params, &panel.params}) {
      for (const auto& [name, value] : *params) given.push_back({name, format_number(value)});
    }
    for (const Axis& a : fig.grid) given.push_back({a.name, ""});
    if (!fig.thetas.empty()) given.push_back({"theta", ""});
    if (const auto err = unused_given(given, nullptr)) fail(file, "invalid " + err->name + ": valid range is " + err->range + where);
    for (const Params& p : expand_grid(base, fig.grid)) {
      Params q = p;
      if (panel.theta_right_offset) {
        q.theta_right = q.theta + *panel.theta_right_offset;
        // The sweep leaves out the angles whose right wall the offset tips past vertical
        // (figures.cpp, sweep_points): they are not run, so not checked.
        if (!(q.theta_right > 0.0 && q.theta_right < 90.0)) continue;
      }
      if (const auto err = validate(q)) fail(file, err->message() + where);
      for (const EnsembleOptions& o : releases) {
        if (const auto err = validate(q, o)) fail(file, err->message() + where);
      }
      for (const double theta : fig.thetas) {
        Params t = q;
        t.theta = theta;
        if (const auto err = validate(t)) fail(file, "thetas: " + err->message() + where);
      }
      for (const double mu : fig.mus) {
        Params m = q;
        m.mu = mu;
        if (const auto err = validate(m)) fail(file, "mus: " + err->message() + where);
      }
    }
  }
  for (const double x : fig.releases) {
    if (!(x > -1.0 && x < 1.0)) {
      fail(file, "invalid releases = " + format_number(x) + ": valid range is -1 < release < 1 (x0/L)");
    }
  }
}

}  // namespace

FigureSpec load_figure(const std::string& path, bool quick) {
  toml::table tbl;
  try {
    tbl = toml::parse_file(path);
  } catch (const toml::parse_error& err) {
    fail(path, std::string(err.description()));
  }
  static const std::vector<std::string> top_level{"figure",  "kind",         "title",         "caption", "series",
                                                   "observables", "samples", "release_dist", "release_dists", "thetas",
                                                   "mus",     "releases",     "params",        "grid",    "panels",
                                                   "check",   "settings",     "quick"};
  for (auto&& [k, node] : tbl) {
    const std::string key(k.str());
    if (std::find(top_level.begin(), top_level.end(), key) == top_level.end()) {
      fail(path, "unknown key '" + key + "'; valid keys are " + joined(top_level));
    }
  }
  FigureSpec fig;
  fig.source = path;
  auto text = [&](const char* key, bool required) {
    const auto v = tbl[key].value<std::string>();
    if (!v && required) fail(path, std::string("missing string '") + key + "'");
    return v.value_or("");
  };
  fig.id = text("figure", true);
  fig.kind = text("kind", true);
  fig.title = text("title", true);
  fig.caption = text("caption", true);
  fig.series = text("series", false);
  if (const toml::node* n = tbl.get("observables")) fig.observables = n->as_array() && n->as_array()->empty()
                                                                         ? std::vector<std::string>{}
                                                                         : strings_of(*n, path, "observables");
  auto samples_of = [&](const toml::node& n) {
    const double v = number_of(n, path, "samples");
    if (!(v >= 1.0 && v <= 1e9 && v == std::floor(v))) {
      fail(path, "invalid samples = " + format_number(v) + ": valid range is an integer 1 <= samples <= 10^9");
    }
    return static_cast<std::int64_t>(v);
  };
  if (const toml::node* n = tbl.get("samples")) fig.samples = samples_of(*n);
  if (const toml::node* n = tbl.get("release_dist")) fig.dists = strings_of(*n, path, "release_dist");
  if (const toml::node* n = tbl.get("release_dists")) fig.dists = strings_of(*n, path, "release_dists");
  if (const toml::node* n = tbl.get("thetas")) fig.thetas = numbers_of(*n, path, "thetas");
  if (const toml::node* n = tbl.get("mus")) fig.mus = numbers_of(*n, path, "mus");
  if (const toml::node* n = tbl.get("releases")) fig.releases = numbers_of(*n, path, "releases");
  if (const toml::table* p = tbl["params"].as_table()) read_params(*p, fig.params, path);
  if (const toml::table* g = tbl["grid"].as_table()) {
    for (auto&& [k, node] : *g) {
      const std::string key = canonical(std::string(k.str()));
      if (!is_model_parameter(key)) fail(path, "unknown grid parameter '" + std::string(k.str()) + "'");
      fig.grid.push_back({key, numbers_of(node, path, key)});
    }
  }
  if (const toml::array* panels = tbl["panels"].as_array()) {
    for (const toml::node& node : *panels) {
      const toml::table* t = node.as_table();
      if (t == nullptr) fail(path, "each [[panels]] entry must be a table");
      PanelSpec panel;
      panel.id = (*t)["id"].value_or(std::string());
      panel.label = (*t)["label"].value_or(std::string());
      if (panel.id.empty()) fail(path, "a panel has no id");
      toml::table own = *t;
      if (const toml::node* off = own.get("theta-right-offset")) {
        panel.theta_right_offset = number_of(*off, path, "theta-right-offset");
        own.erase("theta-right-offset");
      }
      read_params(own, panel.params, path);
      fig.panels.push_back(panel);
    }
  }
  if (fig.panels.empty()) fig.panels.push_back({"a", "", {}, std::nullopt});
  if (const toml::table* c = tbl["check"].as_table()) fig.check = *c;
  if (const toml::table* s = tbl["settings"].as_table()) fig.settings = *s;
  if (quick) {
    if (const toml::table* q = tbl["quick"].as_table()) {
      for (auto&& [k, node] : *q) {
        const std::string key = canonical(std::string(k.str()));
        if (key == "settings" && node.is_table()) {
          for (auto&& [sk, sv] : *node.as_table()) fig.settings.insert_or_assign(sk, sv);
          continue;
        }
        if (key == "samples") {
          fig.samples = samples_of(node);
          continue;
        }
        auto axis = std::find_if(fig.grid.begin(), fig.grid.end(), [&](const Axis& a) { return a.name == key; });
        if (axis == fig.grid.end()) fail(path, "[quick] overrides '" + key + "', which is not a grid axis");
        axis->values = numbers_of(node, path, key);
      }
    }
  }
  if (std::find(known_kinds().begin(), known_kinds().end(), fig.kind) == known_kinds().end()) {
    fail(path, "invalid kind = '" + fig.kind + "': valid kinds are " + joined(known_kinds()));
  }
  for (const std::string& d : fig.dists) {
    if (!parse_release_dist(d)) fail(path, "unknown release_dist '" + d + "' (line, disk, uniform or gaussian)");
  }
  validate_figure(fig);
  validate_settings(fig);
  validate_check(fig);
  return fig;
}

std::vector<FigureSpec> load_figures(const std::string& dir, bool quick) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw InputError("invalid paper-dir = '" + dir + "': not a directory");
  std::vector<std::string> files;
  for (const auto& entry : fs::directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("fig", 0) == 0 && entry.path().extension() == ".toml") files.push_back(entry.path().string());
  }
  std::sort(files.begin(), files.end());
  std::vector<FigureSpec> figs;
  for (const std::string& f : files) figs.push_back(load_figure(f, quick));
  return figs;
}

Params panel_params(const FigureSpec& fig, const PanelSpec& panel) {
  Params p = default_params();
  for (const auto& [k, v] : fig.params) set_parameter(p, k, v);
  for (const auto& [k, v] : panel.params) set_parameter(p, k, v);
  return p;
}

}  // namespace funnel::paper
