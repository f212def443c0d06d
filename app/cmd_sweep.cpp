// `funnel sweep`: one ensemble per point of a parameter grid, written as CSV.
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <charconv>
#include <cmath>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>

#include "cli_common.hpp"
#include "commands.hpp"
#include "funnel/ensemble.hpp"
#include "funnel/funnel.hpp"
#include "funnel/version.hpp"
#include "mpi_run.hpp"
#include "funnel/paper/records.hpp"
#include "output3d.hpp"
#include "run3d.hpp"
#include "progress.hpp"
#include "sweep_config.hpp"

namespace funnel::cli {

namespace {

/// The value of an integer parameter that every point of the grid shares, or 0 when it varies
/// (what the warnings quote as the guard in effect).
std::int64_t common_value(const std::vector<Params>& points, std::int64_t Params::*field) {
  const std::int64_t first = points.front().*field;
  return std::all_of(points.begin(), points.end(), [&](const Params& p) { return p.*field == first; }) ? first : 0;
}

/// Cost of one trajectory in the run-time estimate, seconds per thread: the reference ensemble
/// (theta = 60, e = 0.99, mu = 1; docs/performance.md) runs 223 000 trajectories per second on
/// one thread, 4.5 us each, rounded up. Long-lived trajectories (e near 1, mu = 0) cost more.
constexpr double seconds_per_trajectory = 5e-6;
/// The same in 3D: the 3D reference case (theta = 60, sigma = 0.03; docs/performance.md) runs
/// about 1000 trajectories per second on one thread, 1 ms each.
constexpr double seconds_per_trajectory_3d = 1e-3;
/// A sweep with more points, or a longer estimate, runs only with --yes.
constexpr double max_points_unasked = 1e6;
constexpr double max_seconds_unasked = 3600.0;

std::string duration_text(double s) {
  char buf[64];
  if (s < 120.0) {
    std::snprintf(buf, sizeof buf, "%.0f s", s);
  } else if (s < 7200.0) {
    std::snprintf(buf, sizeof buf, "%.0f min", s / 60.0);
  } else if (s < 172800.0) {
    std::snprintf(buf, sizeof buf, "%.1f h", s / 3600.0);
  } else {
    std::snprintf(buf, sizeof buf, "%.1f days", s / 86400.0);
  }
  return buf;
}

// ---- What an interruption (Ctrl-C, kill) prints ----
// Prepared before the run: a signal handler may only call async-signal-safe functions.
std::string interrupt_head;
std::string interrupt_tail;
std::atomic<std::int64_t> points_saved{0};
static_assert(std::atomic<std::int64_t>::is_always_lock_free);

void write_stderr(const char* text, std::size_t n) {
  while (n > 0) {
    const ssize_t k = ::write(STDERR_FILENO, text, n);
    if (k <= 0) return;
    text += k;
    n -= static_cast<std::size_t>(k);
  }
}

void on_interrupt(int sig) {
  write_stderr(interrupt_head.data(), interrupt_head.size());
  char digits[24];
  int n = 0;
  std::int64_t v = points_saved.load();
  do {
    digits[sizeof digits - 1 - n++] = static_cast<char>('0' + v % 10);
    v /= 10;
  } while (v > 0 && n < 20);
  write_stderr(digits + sizeof digits - n, static_cast<std::size_t>(n));
  write_stderr(interrupt_tail.data(), interrupt_tail.size());
  // SA_RESETHAND restored the default action: once this returns, the signal ends the process
  // as it would have without the handler (the exit status still says "killed by SIGINT").
  raise(sig);
}

/// Prints where the finished points are and how to resume if SIGINT or SIGTERM arrives while
/// it lives; the previous handlers are restored at the end.
class InterruptNotice {
 public:
  InterruptNotice(std::string head, std::string tail) {
    interrupt_head = std::move(head);
    interrupt_tail = std::move(tail);
    struct sigaction sa {};
    sa.sa_handler = on_interrupt;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESETHAND;
    sigaction(SIGINT, &sa, &old_int_);
    sigaction(SIGTERM, &sa, &old_term_);
  }
  ~InterruptNotice() {
    sigaction(SIGINT, &old_int_, nullptr);
    sigaction(SIGTERM, &old_term_, nullptr);
  }
  InterruptNotice(const InterruptNotice&) = delete;
  InterruptNotice& operator=(const InterruptNotice&) = delete;

 private:
  struct sigaction old_int_ {};
  struct sigaction old_term_ {};
};

/// The command line to continue an interrupted run: --overwrite dropped, --resume added.
std::string resume_command(const std::string& command_line) {
  std::string cmd = " " + command_line + " ";
  for (std::size_t at; (at = cmd.find(" --overwrite ")) != std::string::npos;) cmd.erase(at, 12);
  cmd = cmd.substr(1, cmd.size() - 2);
  if ((" " + cmd + " ").find(" --resume ") == std::string::npos) cmd += " --resume";
  return cmd;
}

/// A geometry file's funnel as read: each wall's vertices and its own materials, and the bottom.
nlohmann::ordered_json profile_json(const ProfileSpec& profile) {
  nlohmann::ordered_json j;
  for (const int i : {0, 1}) {
    auto& w = j[i == 0 ? "left" : "right"];
    w["vertices"] = nlohmann::ordered_json::array();
    for (const Vec2 v : profile.sides[static_cast<std::size_t>(i)]) w["vertices"].push_back({v.x, v.y});
    const auto own = [&](const char* key, const std::array<std::optional<double>, 2>& value) {
      if (value[static_cast<std::size_t>(i)]) w[key] = *value[static_cast<std::size_t>(i)];
    };
    own("e", profile.e);
    own("mu", profile.mu);
    own("beta0", profile.beta0);
  }
  if (profile.bottom) j["bottom"] = *profile.bottom;
  return j;
}

/// A finished point of a sweep: its CSV row (newline included) and how many of its runs the
/// collision cap and a guard ended (the warnings' counts, which the CSV has no column for in 2D).
struct SavedPoint {
  std::string row;
  std::int64_t capped = 0;
  std::int64_t stalled = 0;
};

/// The columns of a partial file: the grid index and the two counts, then the CSV's.
std::string partial_header(const std::string& header) { return "point,capped,stalled," + header; }

/// The line of a partial file that saves point i.
std::string partial_line(std::size_t i, const SavedPoint& p) {
  return std::to_string(i) + "," + std::to_string(p.capped) + "," + std::to_string(p.stalled) + "," + p.row;
}

/// Finished points in a partial file: its complete lines (a line cut by a kill has no newline
/// and is computed again) after the spec and the header.
std::int64_t partial_points(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  const auto lines = static_cast<std::int64_t>(
      std::count(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>(), '\n'));
  return std::max<std::int64_t>(0, lines - 2);
}

struct SweepCommand {
  ModelOptions model;
  EnsembleText ens;
  std::string config;
  std::string out;
  bool resume = false;
  bool overwrite = false;
  bool yes = false;
  std::string space = "2d";
  std::string command_line;

  /// Refuses, without --yes, a grid over 10^6 points or an estimated run time over an hour.
  void check_size(const std::vector<Axis>& axes, const EnsembleOptions& options) const {
    const double points = grid_points(axes);
    const std::string dims = grid_dims(axes);
    const int threads = resolve_threads(options.threads);
    const double trajectories = points * static_cast<double>(options.samples);
    const bool three_d = to_space(space) == Space::ThreeD;
    const double seconds = trajectories * (three_d ? seconds_per_trajectory_3d : seconds_per_trajectory) / threads;
    if (yes || (points <= max_points_unasked && seconds <= max_seconds_unasked)) return;
    throw UsageError("this sweep needs --yes: " + count_text(points) + " points" +
                     (dims.empty() ? "" : " (" + dims + ")") + " x " + std::to_string(options.samples) + " samples = " +
                     count_text(trajectories) + " trajectories, estimated " + duration_text(seconds) + " on " +
                     std::to_string(threads) + (threads == 1 ? " thread" : " threads") +
                     (three_d ? " (at 1 ms per 3D trajectory and thread; more with larger sideways velocities). "
                              : " (at 5 us per trajectory and thread; more when e is near 1 or mu = 0). ") +
                     "Over 10^6 points or "
                     "an hour, add --yes to run it, or use a coarser grid or fewer samples");
  }

  void run(bool samples_given, bool dist_given) const {
    const auto start = std::chrono::steady_clock::now();
    ModelOptions merged = model;
    EnsembleText merged_ens = ens;
    if (!config.empty()) {
      const SweepConfig file = read_sweep_config(config);
      for (const auto& [name, text] : file.params) merged.given.emplace(name, text);  // the command line wins
      if (file.samples && !samples_given) merged_ens.samples = *file.samples;
      if (file.release_dist && !dist_given) merged_ens.release_dist = *file.release_dist;
    }
    if (resume && overwrite) throw UsageError("invalid options: --resume and --overwrite exclude each other");
    const Space sp = to_space(space);
    // Even with --yes: each point's row (about 2 kB) is held in memory, and copied once more
    // into the output.
    const std::vector<Axis> axes =
        to_axes(merged, max_sweep_points, "even with --yes: every point's row, about 2 kB, is held in memory twice");
    const EnsembleOptions options = to_ensemble_options(merged_ens, sp);
    const Ensemble3Options options3 =
        sp == Space::ThreeD ? to_ensemble3_options(options, dist_given) : Ensemble3Options{};
    const ReleaseDist dist = sp == Space::ThreeD ? options3.dist : options.dist;
    // A point's row begins with its parameters and the distribution (then its statistics).
    const auto row_start = [&](const Params& p) {
      std::vector<std::string> row = param_row(p, sp);
      row.emplace_back(to_string(dist));
      return row;
    };
    check_size(axes, options);
    const std::vector<Params> points = expand_grid(base_params(merged), axes);
    validate_all(points, sp, options);
    const OutputTarget target = resolve_output(out, sizeof(".partial") - 1);
    const std::vector<InputFile> inputs{{"config", config}, {"geometry", model.geometry}};
    check_not_input(out, target, inputs);
    // The side file of the provenance, before any work: a directory or an unwritable file in its
    // place would otherwise be found only once every point is computed.
    if (target.regular()) check_writable(target.path + ".json", inputs);

    std::vector<std::string> cols = param_columns(sp);
    cols.push_back("release_dist");
    for (const auto& c : sp == Space::ThreeD ? ensemble_columns_3d() : ensemble_columns()) cols.push_back(c);
    const std::string header = csv_line(cols);
    // What the rows depend on: a partial file is continued only if this is the same.
    nlohmann::ordered_json spec;
    spec["version"] = version();
    if (sp == Space::ThreeD) spec["space"] = "3d";
    spec["samples"] = options.samples;
    spec["release_dist"] = to_string(dist);
    spec["seed"] = options.seed;
    spec["release"] = options.release_mean;
    spec["release_sd"] = options.release_sd;
    spec["velocity_sd"] = options.velocity_sd;
    spec["grid"] = nlohmann::ordered_json::array();
    for (const Axis& a : axes) spec["grid"].push_back({{"name", a.name}, {"values", a.values}});
    // The funnel of a geometry file, as read (its walls and materials, not the file's name): a
    // partial file of another funnel, or of the same file edited since, is not continued.
    if (!points.empty() && points.front().profile) spec["geometry"] = profile_json(*points.front().profile);
    const std::string spec_line = "# funnel sweep spec: " + spec.dump() + "\n";

    // Points already computed by an interrupted run ("point,capped,stalled,<row>"), by grid
    // index. A partial file lives beside a regular output file only (not beside a device, FIFO
    // or stdout).
    std::string partial;
    std::map<std::size_t, SavedPoint> done;
    if (target.regular()) {
      partial = target.path + ".partial";
      // Before anything reads it: a directory of that name, or the run's own input, is refused.
      check_writable(partial, inputs);
      // A partial file without a finished point holds nothing to lose: it is started again.
      if (const std::int64_t saved = !resume && !overwrite && std::filesystem::exists(partial) ? partial_points(partial) : 0;
          saved > 0) {
        throw UsageError("'" + partial + "' holds " + std::to_string(saved) + " finished point" + (saved == 1 ? "" : "s") +
                         " of an interrupted sweep: add --resume to continue it (same grid and options), or "
                         "--overwrite to discard " + (saved == 1 ? "it" : "them") + " and start again");
      }
      if (resume) {
        std::vector<std::string> prefixes;  // each point's parameter columns and release_dist, as written
        for (const Params& p : points) {
          std::string line = csv_line(row_start(p));
          line.back() = ',';
          prefixes.push_back(std::move(line));
        }
        if (std::filesystem::exists(partial) && partial_points(partial) > 0) {
          done = read_partial(partial, spec_line, header, prefixes, options.samples);
        } else {
          std::cerr << "funnel sweep: --resume: no finished point in '" << partial << "' to continue"
                    << (std::filesystem::exists(partial) ? "" : " (no such file)") << "; running every point\n";
        }
      }
      write_partial_start(partial, spec_line, header, done);
      if (!done.empty()) {
        std::cerr << "funnel sweep: resuming: " << done.size() << " of " << points.size() << " points already done\n";
      }
    } else if (resume) {
      throw UsageError("invalid resume: --out '" + out + "' is not a regular file, so there is no partial file to resume from");
    }

    std::vector<Params> todo;
    std::vector<std::size_t> todo_index;
    for (std::size_t i = 0; i < points.size(); ++i) {
      if (done.count(i) == 0) {
        todo.push_back(points[i]);
        todo_index.push_back(i);
      }
    }
    const std::string total = std::to_string(points.size());
    points_saved = static_cast<std::int64_t>(done.size());
    {
      const InterruptNotice notice =
          target.regular()
              ? InterruptNotice(mpi_size() > 1 ? "\nfunnel sweep: stopped (interrupted, or a rank of this MPI run died: "
                                                 "see mpirun's note); "
                                               : "\nfunnel sweep: interrupted; ",
                                " of " + total + " points are saved in '" + partial +
                                    "'.\nTo continue without recomputing them, run the same command with --resume" +
                                    (mpi_size() > 1 ? " (under mpirun with any number of ranks, or alone)" : "") + ":\n  " +
                                    resume_command(command_line) + "\n")
              : InterruptNotice("\nfunnel sweep: interrupted after ",
                                " of " + total + " points; nothing is saved: --out '" + out +
                                    "' is not a regular file, so there is no partial file to resume from.\n");
      // Each finished point is appended (one write, flushed) so that an interruption keeps it.
      std::FILE* f = nullptr;
      if (target.regular()) {
        f = std::fopen(partial.c_str(), "ab");
        if (f == nullptr) throw OutputError("cannot append to '" + partial + "': " + std::strerror(errno));
      }
      int append_error = 0;
      ProgressBar bar("funnel sweep", true);
      // One finished point: its row (the statistics' part from 2D or 3D) is kept and appended.
      auto point_done = [&](std::size_t k, const std::vector<std::string>& stats, std::int64_t capped,
                            std::int64_t stalled) {
            const std::size_t i = todo_index[k];
            std::vector<std::string> row = row_start(points[i]);
            for (const auto& v : stats) row.push_back(v);
            done[i] = SavedPoint{csv_line(row), capped, stalled};
            if (f != nullptr) {
              const std::string line = partial_line(i, done[i]);
              if ((std::fwrite(line.data(), 1, line.size(), f) != line.size() || std::fflush(f) != 0) && append_error == 0) {
                append_error = errno;
              }
            }
            ++points_saved;
          };
      const auto progress = [&bar](std::int64_t d, std::int64_t t) { bar.update(d, t); };
      if (sp == Space::ThreeD) {
        run_sweep_3d(todo, options3, progress, [&](std::size_t k, const Ensemble3Result& r) {
          point_done(k, ensemble_row(r), r.capped, r.stalled);
        });
      } else {
        distributed_sweep(todo, options, progress, [&](std::size_t k, const EnsembleResult& r) {
          point_done(k, ensemble_row(r), r.capped, r.stalled);
        });
      }
      bar.finish(std::to_string(todo.size()) + " of " + total + " points computed");
      if (f != nullptr) std::fclose(f);
      if (append_error != 0) {
        std::cerr << "funnel sweep: warning: could not append to '" << partial << "': " << std::strerror(append_error)
                  << " (an interruption would have lost points; the result below is complete)\n";
      }
    }

    std::string text = header;
    for (std::size_t i = 0; i < points.size(); ++i) text += done.at(i).row;
    write_output(out, text);
    // The warnings count every point's runs, those resumed from a partial file included.
    std::int64_t capped = 0, stalled = 0;
    for (const auto& [i, saved] : done) {
      capped += saved.capped;
      stalled += saved.stalled;
    }
    const std::int64_t runs = static_cast<std::int64_t>(points.size()) * options.samples;
    if (sp == Space::ThreeD) {
      warn_stalled("funnel sweep", sp, stalled, runs, "the column stalled", common_value(points, &Params::max_ode_steps));
    } else {
      warn_stalled("funnel sweep", sp, stalled, runs);
    }
    warn_capped("funnel sweep", capped, runs, common_value(points, &Params::max_collisions));
    if (!target.regular()) {
      std::cerr << "funnel sweep: provenance (FILE.csv.json) not written: --out '" << out << "' is not a regular file\n";
      return;
    }
    nlohmann::ordered_json meta;
    meta["provenance"] = provenance_json(command_line);
    meta["spec"] = spec;
    meta["points"] = points.size();
    meta["resumed_points"] = points.size() - todo.size();
    meta["wall_time_s"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    write_output(target.path + ".json", meta.dump(2) + "\n");
    std::remove(partial.c_str());
  }

  /// A row of this sweep for the point whose columns begin with `prefix`: that prefix, then as
  /// many fields as the header has columns left, each a finite number or empty (an undefined
  /// statistic, e.g. the exit ones where nothing exited, is written as an empty field).
  static bool valid_row(const std::string& row, const std::string& prefix, const std::string& header) {
    if (row.empty() || row.back() != '\n' || row.compare(0, prefix.size(), prefix) != 0) return false;
    const auto columns = std::count(header.begin(), header.end(), ',') + 1;
    if (std::count(row.begin(), row.end(), ',') + 1 != columns) return false;
    for (std::size_t pos = prefix.size(); pos < row.size();) {
      const std::size_t end = row.find_first_of(",\n", pos);
      if (end == pos) {  // empty: undefined
        pos = end + 1;
        continue;
      }
      double v = 0.0;
      const auto [ptr, ec] = std::from_chars(row.data() + pos, row.data() + end, v);
      // The sweep writes an undefined value as an empty field, never nan or inf.
      if (ec != std::errc() || ptr != row.data() + end || !std::isfinite(v)) return false;
      pos = end + 1;
    }
    return true;
  }

  /// Valid points of a partial file made by the same sweep; an empty map if there is none. A
  /// line whose parameters are not its point's, whose counts are not whole numbers from 0 to the
  /// sample count, or that is not a row of numbers (an edited or damaged file), is dropped, and
  /// that point computed again.
  static std::map<std::size_t, SavedPoint> read_partial(const std::string& path, const std::string& spec_line,
                                                         const std::string& header,
                                                         const std::vector<std::string>& prefixes,
                                                         std::int64_t samples) {
    const std::size_t n_points = prefixes.size();
    std::map<std::size_t, SavedPoint> rows;
    std::ifstream in(path, std::ios::binary);
    if (!in) return rows;
    std::stringstream buffer;
    buffer << in.rdbuf();
    const std::string text = buffer.str();
    if (text.rfind(spec_line + "point," + header, 0) == 0) {
      throw UsageError("invalid resume: '" + path + "' was written by an earlier funnel sweep, whose lines lack the "
                       "counts of capped and stalled runs that the warnings need; run with --overwrite instead of "
                       "--resume to compute its points again");
    }
    if (text.rfind(spec_line + partial_header(header), 0) != 0) {
      throw UsageError("invalid resume: '" + path + "' was made by a different sweep (grid, samples, release-dist, "
                       "geometry or funnel version); run with --overwrite instead of --resume to discard it");
    }
    std::size_t pos = spec_line.size() + partial_header(header).size();
    std::size_t dropped = 0;
    for (std::size_t eol; (eol = text.find('\n', pos)) != std::string::npos; pos = eol + 1) {
      const std::string line = text.substr(pos, eol + 1 - pos);  // a line cut by a kill has no newline
      const std::size_t comma = line.find(',');
      const auto index = parse_number(line.substr(0, comma));
      if (comma == std::string::npos || !index || *index < 0 || *index >= static_cast<double>(n_points) ||
          *index != std::floor(*index)) {
        continue;
      }
      const auto i = static_cast<std::size_t>(*index);
      // The two counts, each a whole number of runs of this point.
      SavedPoint saved;
      std::size_t start = comma + 1;
      bool counts_valid = true;
      for (std::int64_t* count : {&saved.capped, &saved.stalled}) {
        const std::size_t end = line.find(',', start);
        const auto value = end == std::string::npos ? std::nullopt : parse_number(line.substr(start, end - start));
        counts_valid = counts_valid && value && *value >= 0 && *value <= static_cast<double>(samples) &&
                       *value == std::floor(*value);
        if (!counts_valid) break;
        *count = static_cast<std::int64_t>(*value);
        start = end + 1;
      }
      saved.row = counts_valid ? line.substr(start) : std::string();
      if (!counts_valid || !valid_row(saved.row, prefixes[i], header)) {
        ++dropped;
        continue;
      }
      rows[i] = std::move(saved);
    }
    if (dropped > 0) {
      std::cerr << "funnel sweep: resuming: " << dropped << " row" << (dropped == 1 ? "" : "s") << " of '" << path
                << "' did not match the grid's points and will be computed again\n";
    }
    return rows;
  }

  /// (Re)writes the partial file with its spec, header and the rows kept, atomically.
  static void write_partial_start(const std::string& path, const std::string& spec_line, const std::string& header,
                                  const std::map<std::size_t, SavedPoint>& rows) {
    std::string text = spec_line + partial_header(header);
    for (const auto& [i, saved] : rows) text += partial_line(i, saved);
    write_output(path, text);
  }
};

}  // namespace

void add_sweep_command(CLI::App& app, const std::string& command_line) {
  auto cmd = std::make_shared<SweepCommand>();
  cmd->command_line = command_line;
  CLI::App* sub = app.add_subcommand(
      "sweep", "Run one ensemble per point of a parameter grid (Cartesian product of lists/ranges) to CSV.");
  add_model_options(*sub, cmd->model, true, Space::ThreeD);
  add_space_option(*sub, cmd->space);
  add_geometry_option(*sub, cmd->model);
  add_ensemble_options(*sub, cmd->ens, true, false);
  nonempty(sub->add_option("--config", cmd->config,
                           "TOML file with the grid: model parameters (number, array or \"start:stop:step\") at the "
                           "top level or in a [grid] table, samples, release-dist; command-line options override it"),
           "config", "a file path")
      ->type_name("FILE.toml");
  sub->add_flag("--resume", cmd->resume,
                "continue an interrupted sweep from FILE.csv.partial: finished points are not recomputed");
  sub->add_flag("--overwrite", cmd->overwrite,
                "discard the finished points of an interrupted sweep (FILE.csv.partial) and start again");
  sub->add_flag("--yes", cmd->yes,
                "run a grid of more than 10^6 points, or one estimated to take over an hour (points x samples x "
                "5 us / threads), without refusing");
  sub->add_option("--out", cmd->out,
                  "output CSV file, one row per grid point, written atomically at the end (with FILE.csv.json: "
                  "provenance); while running, finished points are appended to FILE.csv.partial")
      ->required()
      ->type_name("FILE.csv");
  sub->callback([cmd, sub] { cmd->run(sub->count("--samples") > 0, sub->count("--release-dist") > 0); });
}

}  // namespace funnel::cli
