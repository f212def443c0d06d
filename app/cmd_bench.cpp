// `funnel bench`: throughput of the reference ensemble and the reference sweep (docs/performance.md).
#include <algorithm>
#include <chrono>
#include <iostream>
#include <memory>

#include "cli_common.hpp"
#include "commands.hpp"
#include "funnel/ensemble.hpp"
#include "funnel/grid.hpp"
#include "funnel/simd.hpp"
#include "funnel/version.hpp"
#include "funnel/paper/records.hpp"

namespace funnel::cli {

namespace {

/// Median wall time of `repeat` runs of `work`, which returns the ensemble results.
template <class Work>
double median_seconds(int repeat, Work&& work) {
  std::vector<double> times;
  for (int i = 0; i < repeat; ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    work();
    times.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  std::sort(times.begin(), times.end());
  return times[times.size() / 2];
}

std::vector<double> theta_values() {
  std::vector<double> v;
  for (int theta = 20; theta <= 80; theta += 5) v.push_back(theta);
  return v;
}

struct BenchCommand {
  std::string threads = "1";
  std::string samples = "400000";
  std::string repeat = "5";
  std::string format = "text";
  std::string simd = "all";
  std::string command_line;

  /// The paths to compare: "all" (every path this CPU runs) or a comma-separated list.
  std::vector<std::string> paths() const {
    const std::vector<std::string> available = simd_paths();
    if (simd == "all") return available;
    std::vector<std::string> out;
    std::string joined;
    for (const std::string& a : available) joined += (joined.empty() ? "" : ", ") + a;
    for (const std::string& name : comma_items(simd)) {
      if (std::find(available.begin(), available.end(), name) == available.end()) {
        throw UsageError("invalid simd = '" + name + "': valid values on this CPU are all, " + joined);
      }
      out.push_back(name);
    }
    return out;
  }

  void run() const {
    const int n_threads = to_threads(threads);
    const std::int64_t n = to_samples(samples);
    const auto r = parse_number(repeat);
    if (!r || *r < 1 || *r > 1000 || *r != static_cast<int>(*r)) {
      throw UsageError("invalid repeat = '" + repeat + "': valid range is an integer 1 <= repeat <= 1000");
    }
    if (format != "text" && format != "json") throw UsageError("invalid format = '" + format + "': valid values are text, json");
    const int reps = static_cast<int>(*r);
    const std::vector<std::string> compared = paths();

    // Reference ensemble : theta = 60, e = 0.99, mu = 1, beta0 = 0, line release.
    const Params ref = default_params();
    EnsembleResult ens;
    const EnsembleOptions opt{n, ReleaseDist::Line, n_threads, false};
    const double t_ens = median_seconds(reps, [&] { ens = run_ensemble(ref, opt); });

    // The reference ensemble on each path, on one thread and on every core: computed collisions
    // per second by path (the results are the same bits on every path).
    const std::string in_use = simd_path();
    const int cores = resolve_threads(0);
    nlohmann::ordered_json by_path = nlohmann::ordered_json::array();
    for (const std::string& path : compared) {
      set_simd_path(path);
      for (const int t : {1, cores}) {
        if (t == cores && cores == 1) break;
        EnsembleResult res;
        const double wall = median_seconds(reps, [&] { res = run_ensemble(ref, {n, ReleaseDist::Line, t, false}); });
        by_path.push_back({{"path", path},
                           {"lanes", simd_lanes()},
                           {"threads", t},
                           {"wall_time_s", wall},
                           {"computed_collisions_per_second", static_cast<double>(res.simulated_collisions) / wall}});
      }
    }
    set_simd_path(in_use);

    // Reference sweep: theta = 20..80 in 5 degree steps, 4000 samples, on 1 thread and on T.
    const std::vector<Params> points = expand_grid(ref, {{"theta", theta_values()}});
    std::int64_t sweep_collisions = 0;
    auto sweep = [&](int t) {
      const auto res = run_sweep(points, {4000, ReleaseDist::Line, t, false});
      sweep_collisions = 0;
      for (const auto& x : res) sweep_collisions += x.simulated_collisions;
    };
    const int all = resolve_threads(n_threads == 1 ? 0 : n_threads);
    const double t_sweep1 = median_seconds(reps, [&] { sweep(1); });
    const double t_sweepn = median_seconds(reps, [&] { sweep(all); });

    nlohmann::ordered_json j;
    j["reference_ensemble"] = {
        {"params", params_json(ref)},
        {"samples", n},
        {"threads", resolve_threads(n_threads)},
        {"wall_time_s", t_ens},
        // The headline counts the collisions actually computed: a mirror-symmetric ensemble
        // simulates one half of its releases and counts each twice (docs/performance.md).
        {"computed_collisions_per_second", static_cast<double>(ens.simulated_collisions) / t_ens},
        {"computed_collisions", ens.simulated_collisions},
        {"collisions_with_mirror_images", ens.total_collisions},
        {"collisions_with_mirror_images_per_second", static_cast<double>(ens.total_collisions) / t_ens},
        {"trajectories_per_second", static_cast<double>(n) / t_ens},
        {"simd_path", in_use},
        {"lanes", simd_lanes()}};
    j["reference_ensemble_by_path"] = by_path;
    j["reference_sweep"] = {{"grid", "theta = 20:80:5, e = 0.99, mu = 1, beta0 = 0, N = 4000"},
                            {"points", points.size()},
                            {"simulated_collisions", sweep_collisions},
                            {"wall_time_1_thread_s", t_sweep1},
                            {"threads", all},
                            {"wall_time_s", t_sweepn},
                            {"speedup", t_sweep1 / t_sweepn},
                            {"trajectories_per_second", static_cast<double>(points.size() * 4000) / t_sweepn}};
    j["repeat"] = reps;
    j["statistic"] = "median wall time";
    j["provenance"] = provenance_json(command_line);
    if (format == "json") {
      std::cout << j.dump(2) << "\n";
      return;
    }
    const auto& e = j["reference_ensemble"];
    const auto& s = j["reference_sweep"];
    std::printf("funnel %s (%s), median of %d runs\n", std::string(version()).c_str(), std::string(git_commit()).c_str(), reps);
    std::printf("reference ensemble  theta 60, e 0.99, mu 1, beta0 0, N %lld, %d thread(s)\n",
                static_cast<long long>(n), e["threads"].get<int>());
    std::printf("  wall time                   %10.4f s\n", t_ens);
    std::printf("  computed collisions per second %10.3e  (headline)\n", e["computed_collisions_per_second"].get<double>());
    std::printf("  computed collisions         %10lld  (%lld with the mirror images, not computed)\n",
                static_cast<long long>(ens.simulated_collisions), static_cast<long long>(ens.total_collisions));
    std::printf("  trajectories per second     %10.3e\n", e["trajectories_per_second"].get<double>());
    std::printf("  path                        %10s  (%d lanes; FUNNEL_SIMD or --simd choose)\n", in_use.c_str(), simd_lanes());
    std::printf("reference ensemble by path  computed collisions per second\n");
    for (const auto& b : by_path) {
      std::printf("  %-8s %d lanes, %d thread(s) %10.3e  (%.4f s)\n", b["path"].get<std::string>().c_str(),
                  b["lanes"].get<int>(), b["threads"].get<int>(), b["computed_collisions_per_second"].get<double>(),
                  b["wall_time_s"].get<double>());
    }
    std::printf("reference sweep     %s\n", s["grid"].get<std::string>().c_str());
    std::printf("  wall time, 1 thread         %10.4f s\n", t_sweep1);
    std::printf("  wall time, %d threads        %10.4f s  (speedup %.2f)\n", all, t_sweepn, t_sweep1 / t_sweepn);
    std::printf("  trajectories per second     %10.3e\n", s["trajectories_per_second"].get<double>());
  }
};

}  // namespace

void add_bench_command(CLI::App& app, const std::string& command_line) {
  auto cmd = std::make_shared<BenchCommand>();
  cmd->command_line = command_line;
  CLI::App* sub = app.add_subcommand("bench", "Measure collisions per second on the reference ensemble and sweep.");
  sub->add_option("--threads", cmd->threads, "threads for the reference ensemble; 0 = all cores (default 1)")->type_name("T");
  sub->add_option("--samples", cmd->samples, "samples of the reference ensemble; integer 1 to 10^9 (default 400000)")->type_name("N");
  sub->add_option("--repeat", cmd->repeat, "runs per measurement, the median reported; integer 1 to 1000 (default 5)")->type_name("R");
  sub->add_option("--format", cmd->format, "text or json (default text)")->type_name("FMT");
  sub->add_option("--simd", cmd->simd,
                  "engine paths to compare on the reference ensemble: all, or a comma-separated list of scalar, sse4, "
                  "avx2, avx512 (those this CPU runs; default all)")
      ->type_name("PATHS");
  sub->callback([cmd] { cmd->run(); });
}

}  // namespace funnel::cli
