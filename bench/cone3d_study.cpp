// The 3D cone study (docs/performance.md, docs/model.md §9):
//   funnel_cone3d_study speed [--samples N] [--repeat R]
//       collisions per second of the 3D engine on the reference case (theta = 60, e = 0.99,
//       mu = 1, beta0 = 0, N = 4000 disk releases, sigma = 0.03, one thread)
//   funnel_cone3d_study sigma --theta a,b,c --sigma s1,s2 [--samples N] [--threads T]
//                              [--max-collisions C] [--t-max T]
//       mean duration, impulse and energy loss vs theta for random horizontal release velocities
//       of standard deviation sigma (units sqrt(gH)), one CSV row per (theta, sigma)
// A plain program (no options library): the study's numbers, reproducible from the command line.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

#include "funnel/ensemble3d.hpp"

namespace {

std::vector<double> list(const char* text) {
  std::vector<double> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) out.push_back(std::strtod(item.c_str(), nullptr));
  return out;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

funnel::Params reference_params() {
  funnel::Params p = funnel::default_params();  // theta 60, e 0.99, mu 1, beta0 0, a 0.01, d 0.04
  return p;
}

int speed(int argc, char** argv) {
  std::int64_t samples = 4000;
  int repeat = 3;
  for (int i = 2; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--samples")) samples = std::atol(argv[i + 1]);
    if (!std::strcmp(argv[i], "--repeat")) repeat = std::atoi(argv[i + 1]);
  }
  funnel::Ensemble3Options o;
  o.samples = samples;
  o.velocity_sd = 0.03;
  o.seed = 1;
  o.threads = 1;
  std::printf("run,wall_s,collisions,collisions_per_s,trajectories_per_s,ode_steps,exited,trapped\n");
  for (int r = 0; r < repeat; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    const funnel::Ensemble3Result res = funnel::run_ensemble_3d(reference_params(), o);
    const double wall = seconds_since(t0);
    std::printf("%d,%.4f,%lld,%.4g,%.4g,%lld,%lld,%lld\n", r, wall, static_cast<long long>(res.total_collisions),
                static_cast<double>(res.total_collisions) / wall, static_cast<double>(samples) / wall,
                static_cast<long long>(res.ode_steps), static_cast<long long>(res.exited),
                static_cast<long long>(res.trapped));
  }
  return 0;
}

int sigma(int argc, char** argv) {
  std::vector<double> thetas{30, 40, 44, 46, 50, 60, 70, 80}, sigmas{0.0, 0.01, 0.03, 0.1};
  funnel::Ensemble3Options o;
  o.seed = 1;
  funnel::Params base = reference_params();
  for (int i = 2; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--theta")) thetas = list(argv[i + 1]);
    if (!std::strcmp(argv[i], "--sigma")) sigmas = list(argv[i + 1]);
    if (!std::strcmp(argv[i], "--samples")) o.samples = std::atol(argv[i + 1]);
    if (!std::strcmp(argv[i], "--threads")) o.threads = std::atoi(argv[i + 1]);
    if (!std::strcmp(argv[i], "--max-collisions")) base.max_collisions = std::atol(argv[i + 1]);
    if (!std::strcmp(argv[i], "--t-max")) base.t_max = std::strtod(argv[i + 1], nullptr);
  }
  std::printf(
      "theta,sigma,samples,duration_mean,duration_sem,impulse_mean,impulse_sem,energy_loss_mean,energy_loss_sem,"
      "exited,trapped,periodic,orbits_mean,collisions_mean,contact_time_mean,ode_steps,wall_s\n");
  using funnel::Observable;
  for (const double s : sigmas) {
    for (const double theta : thetas) {
      funnel::Params p = base;
      p.theta = theta;
      o.velocity_sd = s;
      const auto t0 = std::chrono::steady_clock::now();
      const funnel::Ensemble3Result r = funnel::run_ensemble_3d(p, o);
      std::printf("%g,%g,%lld,%.8g,%.4g,%.8g,%.4g,%.8g,%.4g,%lld,%lld,%lld,%.6g,%.6g,%.6g,%lld,%.2f\n", theta, s,
                  static_cast<long long>(r.samples), r[Observable::Duration].mean, r[Observable::Duration].sem,
                  r[Observable::Impulse].mean, r[Observable::Impulse].sem, r[Observable::EnergyLoss].mean,
                  r[Observable::EnergyLoss].sem, static_cast<long long>(r.exited), static_cast<long long>(r.trapped),
                  static_cast<long long>(r.periodic), r[Observable::Orbits].mean, r[Observable::Collisions].mean,
                  r[Observable::ContactTime].mean, static_cast<long long>(r.ode_steps), seconds_since(t0));
      std::fflush(stdout);
    }
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc >= 2 && !std::strcmp(argv[1], "speed")) return speed(argc, argv);
  if (argc >= 2 && !std::strcmp(argv[1], "sigma")) return sigma(argc, argv);
  std::fprintf(stderr, "usage: funnel_cone3d_study speed [--samples N] [--repeat R]\n"
                       "       funnel_cone3d_study sigma [--theta list] [--sigma list] [--samples N] [--threads T]\n"
                       "                                 [--max-collisions C] [--t-max T]\n");
  return 2;
}
