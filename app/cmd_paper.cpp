// `funnel paper`: every figure of the paper as data (CSV + JSON), pictures and an HTML report.
#include <fcntl.h>
#include <poll.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>
#include <set>
#include <sstream>

#include "cli_common.hpp"
#include "commands.hpp"
#include "funnel/version.hpp"
#include "funnel/paper/records.hpp"
#include "funnel/paper/figures.hpp"
#include "mpi_run.hpp"
#include "progress.hpp"

namespace funnel::cli {

namespace {

namespace fs = std::filesystem;

/// Creates `dir` and its parents, or throws the usage error naming --out and why it cannot.
void create_directory(const std::string& out, const fs::path& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (!ec && fs::is_directory(dir)) return;
  const bool in_the_way = fs::exists(fs::symlink_status(dir)) && !fs::is_directory(dir);
  throw UsageError("invalid out = '" + out + "': cannot create the directory '" + dir.string() + "': " +
                   (in_the_way ? std::string("a file that is not a directory is in the way") : ec.message()));
}

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

/// `relative` under the installation prefix of the running binary (PREFIX/bin/funnel), if that
/// directory exists: an installed funnel uses its own figure definitions and Python package.
std::string installed_dir(const std::string& relative) {
  if (relative.empty()) return {};
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec) return {};
  const fs::path dir = exe.parent_path().parent_path() / relative;
  return fs::is_directory(dir, ec) ? dir.string() : std::string();
}

std::string default_paper_dir() {
  const std::string installed = installed_dir(FUNNEL_INSTALL_PAPER_DIR);
  return installed.empty() ? FUNNEL_PAPER_DIR : installed;
}

/// Runs `python -m funnel.plot DIR` with a progress bar (figures whose PNG is written), showing
/// what Python says apart from its per-figure lines; returns false (after saying why) if it fails.
bool make_plots(const std::string& dir, const std::vector<FigureSpec>& figs) {
  const std::string python = python_interpreter();
  // An installed package is used only if it is there: a binary copied to a prefix whose
  // site-packages directory exists without it (e.g. /usr/local/bin, with Debian's
  // /usr/local/lib/python3.X/dist-packages) uses the build's.
  std::string path = installed_dir(FUNNEL_INSTALL_PYTHON_DIR);
  if (path.empty() || !fs::is_regular_file(fs::path(path) / "funnel" / "__init__.py")) path = FUNNEL_PYTHON_PATH;
  if (const char* old = std::getenv("PYTHONPATH"); old != nullptr && *old != '\0') path += std::string(":") + old;
  int pipe_fd[2];
  if (pipe2(pipe_fd, O_CLOEXEC) != 0) return false;
  // Files older than this are from an earlier run (one second of slack for coarse file clocks).
  const auto stage_start = fs::file_time_type::clock::now() - std::chrono::seconds(1);
  std::fflush(stderr);
  const pid_t pid = fork();
  if (pid == 0) {
    dup2(pipe_fd[1], STDERR_FILENO);
    setenv("PYTHONPATH", path.c_str(), 1);
    setenv("MPLBACKEND", "Agg", 1);
    execlp(python.c_str(), python.c_str(), "-m", "funnel.plot", dir.c_str(), static_cast<char*>(nullptr));
    std::perror(("funnel paper: cannot start " + python).c_str());
    _exit(127);
  }
  close(pipe_fd[1]);
  if (pid < 0) {
    close(pipe_fd[0]);
    return false;
  }
  std::string said;
  int status = 0;
  {
    ProgressBar bar("funnel paper: plots", true);
    const auto drawn = [&] {
      std::int64_t n = 0;
      for (const FigureSpec& f : figs) {
        std::error_code ec;
        const auto t = fs::last_write_time(fs::path(dir) / f.id / (f.id + ".png"), ec);
        n += !ec && t >= stage_start;
      }
      return n;
    };
    const auto total = static_cast<std::int64_t>(figs.size());
    for (;;) {
      pollfd pfd{pipe_fd[0], POLLIN, 0};
      if (poll(&pfd, 1, 100) > 0) {
        char buf[4096];
        const ssize_t n = read(pipe_fd[0], buf, sizeof buf);
        if (n == 0 || (n < 0 && errno != EINTR)) break;
        if (n > 0) said.append(buf, static_cast<std::size_t>(n));
      }
      bar.update(drawn(), total);
    }
    close(pipe_fd[0]);
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    bar.finish(std::to_string(drawn()) + " of " + std::to_string(total) + " figures drawn");
  }
  const bool ok = WIFEXITED(status) && WEXITSTATUS(status) == 0;
  std::istringstream lines(said);
  for (std::string line; std::getline(lines, line);) {
    const bool per_figure = line.rfind("funnel.plot: wrote ", 0) == 0 && line.find("index.html") == std::string::npos;
    if (!ok || !per_figure) std::cerr << line << "\n";
  }
  return ok;
}

struct PaperCommand {
  std::string out;
  std::string only;
  bool quick = false;
  bool no_plots = false;
  std::string threads = "0";
  std::string paper_dir = default_paper_dir();
  std::string command_line;

  void run() const {
    const auto start = std::chrono::steady_clock::now();
    const int n_threads = to_threads(threads);
    std::vector<FigureSpec> figs = load_figures(paper_dir, quick);
    if (!only.empty()) {
      std::set<std::string> wanted;
      for (const std::string& id : comma_items(only)) wanted.insert(id);
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
    // The output directory and each figure's, before any work: a file in the way (or no
    // permission) is said at once, not after minutes of computing.
    create_directory(out, out);
    for (const FigureSpec& f : figs) {
      create_directory(out, fs::path(out) / f.id);
      for (const char* ext : {".csv", ".json"}) check_writable((fs::path(out) / f.id / (f.id + ext)).string());
    }

    // Ensembles spread over the MPI ranks when run under mpirun (docs/cluster.md).
    SweepCache cache([](const std::vector<Params>& points, const EnsembleOptions& options, const Progress& progress) {
      return distributed_sweep(points, options, progress);
    });
    for (const FigureSpec& f : figs) request_sweeps(f, cache);
    std::cerr << "funnel paper: " << figs.size() << " figures, " << cache.size() << " ensembles of θ sweeps"
              << (quick ? " (quick preview)" : "") << "\n";
    const auto sweep_start = std::chrono::steady_clock::now();
    {
      ProgressBar bar("funnel paper: θ sweeps", true);
      cache.run(n_threads, [&bar](std::int64_t d, std::int64_t t) { bar.update(d, t); });
      bar.finish(std::to_string(cache.size()) + " ensembles");
    }
    const double sweep_time = seconds_since(sweep_start);
    const std::map<std::string, double> sweep_share = attributed_collisions(figs, cache);
    const auto sweep_collisions = static_cast<double>(cache.simulated_collisions());

    std::vector<std::pair<std::string, nlohmann::ordered_json>> checks;
    for (const FigureSpec& f : figs) {
      const auto t0 = std::chrono::steady_clock::now();
      FigureData data;
      {
        // The theta sweeps ran above; the other kinds run here (Figs. 7, 11, 12 take a while).
        ProgressBar bar("funnel paper: " + f.id);
        data = compute_figure(f, cache, n_threads, [&bar](std::int64_t d, std::int64_t t) { bar.update(d, t); });
      }
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
      const std::string dir = (fs::path(out) / f.id).string();  // created above
      write_output((fs::path(dir) / (f.id + ".csv")).string(), data.csv);
      write_output((fs::path(dir) / (f.id + ".json")).string(), meta.dump(2) + "\n");
      std::cerr << "funnel paper: " << f.id << " data written (" << static_cast<int>(run_time * 10) / 10.0 << " s)\n";
      checks.emplace_back(f.id, data.check);
    }

    if (no_plots) {
      std::cerr << "funnel paper: --no-plots: pictures and index.html not made\n";
    } else if (!make_plots(out, figs)) {
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
  nonempty(sub->add_option("--out", cmd->out, "output directory (created if needed)"), "out", "a directory path")->required()->type_name("DIR");
  nonempty(sub->add_option("--only", cmd->only, "comma-separated figures to make, e.g. fig03,fig07 (default: all)"), "only",
           "comma-separated figure ids, e.g. fig03,fig07")
      ->type_name("FIGS");
  sub->add_flag("--quick", cmd->quick, "coarse grids and few samples: a preview in well under a minute");
  sub->add_flag("--no-plots", cmd->no_plots, "write the data only, do not call the Python plotting module");
  sub->add_option("--threads", cmd->threads, "worker threads; integer 1 to 1024, or 0 = all cores (default 0)")->type_name("T");
  nonempty(sub->add_option("--paper-dir", cmd->paper_dir,
                           "directory of the figure definitions (default: the installation's share/funnel/paper, "
                           "else the source tree's paper/)"),
           "paper-dir", "a directory of figure definitions")
      ->type_name("DIR");
  sub->callback([cmd] { cmd->run(); });
}

}  // namespace funnel::cli
