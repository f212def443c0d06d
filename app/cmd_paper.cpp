// `funnel paper`: every figure of the paper as data (CSV + JSON), pictures and an HTML report.
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>
#include <set>

#include "cli_common.hpp"
#include "commands.hpp"
#include "funnel/version.hpp"
#include "output.hpp"
#include "paper_figures.hpp"
#include "progress.hpp"

namespace funnel::cli {

namespace {

namespace fs = std::filesystem;

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

nlohmann::ordered_json metadata(const FigureSpec& fig, const FigureData& data, double run_time, bool quick,
                                const std::string& command_line) {
  nlohmann::ordered_json j;
  j["figure"] = fig.id;
  j["kind"] = fig.kind;
  j["title"] = fig.title;
  j["caption"] = fig.caption;
  j["params"] = nlohmann::ordered_json::object();
  for (const auto& [k, v] : fig.params) j["params"][k] = v;
  j["grid"] = nlohmann::ordered_json::object();
  for (const Axis& a : fig.grid) {
    j["grid"][a.name] = {{"first", a.values.front()}, {"last", a.values.back()}, {"count", a.values.size()}};
  }
  j["panels"] = nlohmann::ordered_json::array();
  for (const PanelSpec& p : fig.panels) {
    nlohmann::ordered_json pj{{"id", p.id}, {"label", p.label}};
    for (const auto& [k, v] : p.params) pj[k] = v;
    j["panels"].push_back(pj);
  }
  j["series"] = fig.series;
  j["observables"] = fig.observables;
  j["samples"] = fig.samples;
  j["release_dists"] = fig.dists;
  j["quick"] = quick;
  j["version"] = version();
  j["git_commit"] = git_commit();
  j["command"] = command_line;
  j["run_time_s"] = run_time;
  j["check"] = data.check;
  j.update(data.extra);
  return j;
}

/// The interpreter used for the plots: $FUNNEL_PYTHON, else Debian's python3.
std::string python_interpreter() {
  if (const char* env = std::getenv("FUNNEL_PYTHON"); env != nullptr && *env != '\0') return env;
  return fs::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
}

/// Runs `python -m funnel.plot DIR`; returns false (after saying why) if it cannot.
bool make_plots(const std::string& dir) {
  const std::string python = python_interpreter();
  std::string path = FUNNEL_PYTHON_PATH;
  if (const char* old = std::getenv("PYTHONPATH"); old != nullptr && *old != '\0') path += std::string(":") + old;
  const pid_t pid = fork();
  if (pid == 0) {
    setenv("PYTHONPATH", path.c_str(), 1);
    setenv("MPLBACKEND", "Agg", 1);
    execlp(python.c_str(), python.c_str(), "-m", "funnel.plot", dir.c_str(), static_cast<char*>(nullptr));
    std::perror("funnel paper: cannot start python");
    _exit(127);
  }
  int status = 0;
  if (pid < 0 || waitpid(pid, &status, 0) < 0) return false;
  return WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

struct PaperCommand {
  std::string out;
  std::string only;
  bool quick = false;
  bool no_plots = false;
  std::string threads = "0";
  std::string paper_dir = FUNNEL_PAPER_DIR;
  std::string command_line;

  void run() const {
    const auto start = std::chrono::steady_clock::now();
    const int n_threads = to_threads(threads);
    std::vector<FigureSpec> figs = load_figures(paper_dir, quick);
    if (!only.empty()) {
      std::set<std::string> wanted;
      for (std::size_t pos = 0; pos <= only.size();) {
        const std::size_t comma = std::min(only.find(',', pos), only.size());
        wanted.insert(only.substr(pos, comma - pos));
        pos = comma + 1;
      }
      std::vector<FigureSpec> chosen;
      for (const FigureSpec& f : figs) {
        if (wanted.erase(f.id) > 0) chosen.push_back(f);
      }
      if (!wanted.empty()) {
        std::string known;
        for (const FigureSpec& f : figs) known += (known.empty() ? "" : ", ") + f.id;
        throw UsageError("invalid only = '" + only + "': unknown figure '" + *wanted.begin() + "'; valid: " + known);
      }
      figs = chosen;
    }
    std::error_code ec;
    fs::create_directories(out, ec);
    if (ec || !fs::is_directory(out)) throw UsageError("invalid out = '" + out + "': cannot create the directory");

    SweepCache cache;
    for (const FigureSpec& f : figs) request_sweeps(f, cache);
    std::cerr << "funnel paper: " << figs.size() << " figures, " << cache.size() << " ensembles of θ sweeps"
              << (quick ? " (quick preview)" : "") << "\n";
    const auto sweep_start = std::chrono::steady_clock::now();
    {
      ProgressBar bar("θ sweeps");
      cache.run(n_threads, [&bar](std::int64_t d, std::int64_t t) { bar.update(d, t); });
    }
    const double sweep_time = seconds_since(sweep_start);
    const std::map<std::string, double> sweep_share = attributed_collisions(figs, cache);
    const auto sweep_collisions = static_cast<double>(cache.simulated_collisions());

    std::vector<std::pair<std::string, nlohmann::ordered_json>> checks;
    for (const FigureSpec& f : figs) {
      const auto t0 = std::chrono::steady_clock::now();
      const FigureData data = compute_figure(f, cache, n_threads);
      // Theta-sweep figures are computed in one shared batch: each is attributed the batch time
      // in proportion to the collisions simulated for its ensembles (docs/paper.md).
      double run_time = seconds_since(t0);
      nlohmann::ordered_json meta = metadata(f, data, run_time, quick, command_line);
      if (f.kind == "theta_sweep") {
        const double share = sweep_collisions > 0 ? sweep_share.at(f.id) / sweep_collisions : 0.0;
        run_time += share * sweep_time;
        meta["run_time_s"] = run_time;
        meta["run_time_basis"] = {{"batch_time_s", sweep_time}, {"batch_collisions", sweep_collisions},
                                  {"figure_collisions", sweep_share.at(f.id)}};
      }
      const std::string dir = (fs::path(out) / f.id).string();
      fs::create_directories(dir);
      write_output((fs::path(dir) / (f.id + ".csv")).string(), data.csv);
      write_output((fs::path(dir) / (f.id + ".json")).string(), meta.dump(2) + "\n");
      std::cerr << "funnel paper: " << f.id << " data written (" << static_cast<int>(run_time * 10) / 10.0 << " s)\n";
      checks.emplace_back(f.id, data.check);
    }

    if (no_plots) {
      std::cerr << "funnel paper: --no-plots: pictures and index.html not made\n";
    } else if (!make_plots(out)) {
      std::cerr << "funnel paper: pictures not made: Python 3 with numpy and matplotlib is needed\n"
                   "  (Debian: apt-get install python3-numpy python3-matplotlib; or set FUNNEL_PYTHON);\n"
                   "  the data (CSV + JSON) is complete in "
                << out << "\n";
    }
    std::cout << "figure  holds  measured\n";
    for (const auto& [id, check] : checks) {
      std::cout << id << "   " << (check.value("holds", false) ? "yes  " : "NO   ") << "  "
                << check.value("measured", std::string()) << "\n";
    }
    std::cout << "funnel paper: total wall time " << static_cast<int>(seconds_since(start) * 10) / 10.0 << " s\n";
  }
};

}  // namespace

void add_paper_command(CLI::App& app, const std::string& command_line) {
  auto cmd = std::make_shared<PaperCommand>();
  cmd->command_line = command_line;
  CLI::App* sub = app.add_subcommand(
      "paper", "Reproduce the paper's figures: data, pictures and an HTML report in DIR (figures defined in paper/*.toml).");
  sub->add_option("--out", cmd->out, "output directory (created if needed)")->required()->type_name("DIR");
  sub->add_option("--only", cmd->only, "comma-separated figures to make, e.g. fig03,fig07 (default: all)")->type_name("FIGS");
  sub->add_flag("--quick", cmd->quick, "coarse grids and few samples: a preview in well under a minute");
  sub->add_flag("--no-plots", cmd->no_plots, "write the data only, do not call the Python plotting module");
  sub->add_option("--threads", cmd->threads, "worker threads; integer >= 1, or 0 = all cores (default 0)")->type_name("T");
  sub->add_option("--paper-dir", cmd->paper_dir, "directory of the figure definitions (default: the source tree's paper/)")
      ->type_name("DIR");
  sub->callback([cmd] { cmd->run(); });
}

}  // namespace funnel::cli
