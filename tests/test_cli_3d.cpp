// `--space 3d` on trajectory, ensemble and sweep as a user meets it: options of the other space
// are refused (exit 2, name, value, range), an in-plane release gives the 2D numbers, the 3D log
// rebuilds its own flights, seeded ensembles repeat, and 2D outputs keep their columns.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "cli_util.hpp"

namespace {

using namespace funnel_test;
using nlohmann::json;

/// The fields of each line of a CSV text without quoted fields.
std::vector<std::vector<std::string>> csv_rows(const std::string& text) {
  std::vector<std::vector<std::string>> rows;
  for (std::size_t at = 0; at < text.size();) {
    const std::size_t end = text.find('\n', at);
    std::vector<std::string>& row = rows.emplace_back();
    for (std::size_t field = at;;) {
      const std::size_t comma = std::min(text.find(',', field), end);
      row.push_back(text.substr(field, comma - field));
      if (comma == end) break;
      field = comma + 1;
    }
    at = end + 1;
  }
  return rows;
}

bool near(double a, double b, double rel) { return std::fabs(a - b) <= rel * std::max(std::fabs(a), std::fabs(b)); }

TEST_F(Cli, OptionsOfTheOtherSpaceAreRefusedNamingTheParameterValueAndRange) {
  const std::string out = " --out " + path("x.json");
  const Result w = run("trajectory --release 0.3 --release-w 0.05" + out);
  expect_rejected(w, "release-w", "0.05");
  EXPECT_NE(w.output.find("--space 3d"), std::string::npos) << w.output;
  expect_rejected(run("ensemble --samples 8 --release-spin-x 2" + out), "release-spin-x", "2");
  expect_rejected(run("sweep --samples 8 --release-spin-y 0,1" + out), "release-spin-y", "1");
  expect_rejected(run("trajectory --space 3d --release 0.3 --wear-bins 4" + out), "wear-bins", "4");
  expect_rejected(run("ensemble --space 3d --samples 8 --wear-bins 4" + out), "wear-bins", "4");
  const Result dist = run("ensemble --space 3d --samples 8 --release-dist gaussian" + out);
  expect_rejected(dist, "release-dist", "gaussian");
  EXPECT_NE(dist.output.find("disk"), std::string::npos) << dist.output;
  expect_rejected(run("trajectory --space 4d --release 0.3" + out), "space", "4d");
  expect_rejected(run("trajectory --space 3d --release 0.3 --release-w nan" + out), "release-w", "nan");
  // The 2D shapes: the range says what the cone takes (it said "its 2D default").
  expect_rejected(run("ensemble --space 3d --samples 8 --theta 50 --theta-left 40" + out), "theta-left = 40",
                  "valid range is theta-left = theta (50) in 3d, the cone of theta and gap");
  expect_rejected(run("sweep --space 3d --samples 8 --spout-length 0,0.2" + out), "spout-length = 0.2",
                  "valid range is spout-length = 0 in 3d");
  EXPECT_EQ(file_count(), 0u);
}

TEST_F(Cli, AnInPlaneReleaseGivesTheTwoDimensionalTrajectory) {
  const std::string args = "trajectory --theta 50 --release 0.37 --release-spin 3 --events --out ";
  ASSERT_EQ(run(args + path("a.json")).code, 0);
  ASSERT_EQ(run(args + path("b.json") + " --space 3d").code, 0);
  const json a = json::parse(read("a.json")), b = json::parse(read("b.json"));
  EXPECT_EQ(b["space"], "3d");
  EXPECT_EQ(a["status"], b["status"]);
  for (const char* key : {"duration", "impulse", "normal_impulse", "energy_loss", "exit_x", "exit_u", "exit_v"}) {
    EXPECT_TRUE(near(a[key].get<double>(), b[key].get<double>(), 1e-12)) << key << " " << a[key] << " " << b[key];
  }
  EXPECT_EQ(a["collisions"], b["collisions"]);
  EXPECT_EQ(b["exit_z"].get<double>(), 0.0);
  EXPECT_EQ(b["orbits"].get<double>(), 0.0);
  ASSERT_EQ(a["events"].size(), b["events"].size());
  for (std::size_t i = 0; i < std::min<std::size_t>(a["events"].size(), 20); ++i) {
    const json& ea = a["events"][i];
    const json& eb = b["events"][i];
    EXPECT_EQ(ea["kind"], eb["kind"]) << i;
    for (const char* key : {"time", "x", "y", "u_after", "v_after", "omega_after"}) {
      EXPECT_NEAR(ea[key].get<double>(), eb[key].get<double>(), 1e-12 * (1.0 + std::fabs(ea[key].get<double>())))
          << i << " " << key;
    }
    EXPECT_EQ(eb["z"].get<double>(), 0.0);
    EXPECT_EQ(eb["w_after"].get<double>(), 0.0);
    EXPECT_EQ(eb["omega_x_after"].get<double>(), 0.0);
  }
}

TEST_F(Cli, TheThreeDimensionalEventLogRebuildsItsFlights) {
  // Between two collisions the centre flies a parabola: the log's positions and velocities
  // agree with it, and the spin is constant.
  ASSERT_EQ(run("trajectory --space 3d --theta 60 --release 0.5 --release-w 0.08 --release-spin-x 4 --events --out " +
                path("t.json"))
                .code,
            0);
  const json t = json::parse(read("t.json"));
  const json& ev = t["events"];
  ASSERT_GT(ev.size(), 5u);
  int flights = 0;
  for (std::size_t i = 0; i + 1 < ev.size(); ++i) {
    const json &a = ev[i], &b = ev[i + 1];
    if (a["kind"] != "face" && a["kind"] != "edge") continue;
    if (b["kind"] != "face" && b["kind"] != "edge") continue;
    const double dt = b["time"].get<double>() - a["time"].get<double>();
    EXPECT_NEAR(b["x"].get<double>(), a["x"].get<double>() + a["u_after"].get<double>() * dt, 1e-9);
    EXPECT_NEAR(b["z"].get<double>(), a["z"].get<double>() + a["w_after"].get<double>() * dt, 1e-9);
    EXPECT_NEAR(b["y"].get<double>(), a["y"].get<double>() + a["v_after"].get<double>() * dt - 0.5 * dt * dt, 1e-9);
    EXPECT_NEAR(b["w_before"].get<double>(), a["w_after"].get<double>(), 1e-12);
    EXPECT_EQ(b["omega_x_before"], a["omega_x_after"]);
    EXPECT_EQ(b["omega_y_before"], a["omega_y_after"]);
    ++flights;
  }
  EXPECT_GT(flights, 3);
  EXPECT_NE(ev[0]["omega_x_before"].get<double>(), 0.0);
}

TEST_F(Cli, SeededThreeDimensionalEnsemblesRepeatAndReportOrbits) {
  const std::string args = "ensemble --space 3d --theta 60 --samples 24 --velocity-sd 0.03 --out ";
  ASSERT_EQ(run(args + path("a.json") + " --seed 5 --threads 2").code, 0);
  ASSERT_EQ(run(args + path("b.json") + " --seed 5 --threads 1").code, 0);
  ASSERT_EQ(run(args + path("c.json") + " --seed 6 --threads 2").code, 0);
  json a = json::parse(read("a.json")), b = json::parse(read("b.json")), c = json::parse(read("c.json"));
  EXPECT_EQ(a["release_dist"], "disk");
  EXPECT_EQ(a["seed"], 5);
  EXPECT_EQ(a["duration"], b["duration"]);  // bit-identical for any thread count
  EXPECT_EQ(a["orbits"], b["orbits"]);
  EXPECT_NE(a["duration"]["mean"], c["duration"]["mean"]);
  EXPECT_GT(a["orbits"]["mean"].get<double>(), 0.0);
  EXPECT_TRUE(a.contains("exit_w") && a.contains("exit_spin_y"));
  EXPECT_TRUE(a["params"].contains("release_w"));
  // sigma = 0 and disk releases: every ball stays in its meridian plane.
  ASSERT_EQ(run("ensemble --space 3d --theta 60 --samples 24 --out " + path("d.json")).code, 0);
  EXPECT_EQ(json::parse(read("d.json"))["orbits"]["max"].get<double>(), 0.0);
}

TEST_F(Cli, RunsEndedByTheCollisionCapAreCountedAndWarnedOf) {
  // A trajectory: trapped at its 5th collision, with a warning that names the cap.
  const Result t = run("trajectory --theta 60 --release 0.3 --max-collisions 5 --out " + path("t.json"));
  ASSERT_EQ(t.code, 0) << t.output;
  const json tj = json::parse(read("t.json"));
  EXPECT_EQ(tj["status"], "trapped");
  EXPECT_EQ(tj["collisions"], 5);
  EXPECT_NE(t.output.find("funnel trajectory: warning: the run reached --max-collisions (5) inside the funnel"),
            std::string::npos) << t.output;
  // Ensembles (2D, mirror images included; 3D) count them in "capped", among the trapped.
  for (const std::string space : {"2d", "3d"}) {
    const Result e = run("ensemble --space " + space + " --theta 60 --samples 100 --max-collisions 50 --out " +
                         path("e.json"));
    ASSERT_EQ(e.code, 0) << e.output;
    const json ej = json::parse(read("e.json"));
    const std::int64_t capped = ej["capped"].get<std::int64_t>();
    EXPECT_GT(capped, 50) << space;
    EXPECT_LE(capped, ej["status_counts"]["trapped"].get<std::int64_t>()) << space;
    EXPECT_EQ(ej["stalled"], 0) << space;
    EXPECT_NE(e.output.find("funnel ensemble: warning: " + std::to_string(capped) +
                            " of 100 runs reached --max-collisions (50) inside the funnel"),
              std::string::npos) << space << e.output;
    EXPECT_NE(e.output.find("A higher --max-collisions lets them go on"), std::string::npos) << e.output;
  }
  // A sweep sums them over its points.
  const Result s = run("sweep --theta 50,60 --samples 10 --max-collisions 50 --out " + path("s.csv"));
  ASSERT_EQ(s.code, 0) << s.output;
  EXPECT_NE(s.output.find("funnel sweep: warning: 20 of 20 runs reached --max-collisions (50)"), std::string::npos)
      << s.output;
  // Resumed with the first point from a partial file, it still counts that point's runs, which
  // the partial file keeps beside the row (they were left out: "10 of 10 runs").
  const std::string text = read("s.csv");
  const std::string header = text.substr(0, text.find('\n'));
  const std::string first_row = text.substr(header.size() + 1, text.find('\n', header.size() + 1) - header.size());
  const std::string spec = nlohmann::ordered_json::parse(read("s.csv.json"))["spec"].dump();
  const std::string resume = "sweep --theta 50,60 --samples 10 --max-collisions 50 --resume --out " + path("r.csv");
  write("r.csv.partial", partial_start(spec, header) + "0,10,0," + first_row);
  const Result resumed = run(resume);
  ASSERT_EQ(resumed.code, 0) << resumed.output;
  EXPECT_EQ(json::parse(read("r.csv.json"))["resumed_points"], 1);
  EXPECT_EQ(read("r.csv"), text);
  EXPECT_NE(resumed.output.find("funnel sweep: warning: 20 of 20 runs reached"), std::string::npos) << resumed.output;
  // A count that is not a whole number of the point's runs marks a damaged line: its point is
  // computed again.
  for (const std::string bad : {"11", "-1", "2.5", "x", ""}) {
    write("r.csv.partial", partial_start(spec, header) + "0," + bad + ",0," + first_row);
    const Result again = run(resume);
    ASSERT_EQ(again.code, 0) << again.output;
    EXPECT_EQ(json::parse(read("r.csv.json"))["resumed_points"], 0) << bad;
    EXPECT_NE(again.output.find("1 row of"), std::string::npos) << bad << again.output;
    EXPECT_EQ(read("r.csv"), text) << bad;
    EXPECT_NE(again.output.find("funnel sweep: warning: 20 of 20 runs reached"), std::string::npos) << again.output;
  }
  // Under the default cap: no count, no warning.
  const Result plain = run("ensemble --theta 60 --samples 100 --out " + path("p.json"));
  ASSERT_EQ(plain.code, 0) << plain.output;
  EXPECT_EQ(json::parse(read("p.json"))["capped"], 0);
  EXPECT_EQ(plain.output.find("warning"), std::string::npos) << plain.output;
}

TEST_F(Cli, ARunStoppedByTheStepGuardIsFlaggedStalledAndWarnedOf) {
  // A ball hovering at the limit of rolling on an 86-degree cone (docs/robustness.md, finding 22):
  // with the default guard its contact takes 2e7 integrator steps, about 20 s.
  const std::string steep =
      "trajectory --space 3d --theta 86.01593143426537 --e 0.14390672371155014 --mu 0.8610508103691801 --beta0 "
      "-0.15092973196734505 --radius 0.00022010929764117512 --gap 0.0004446501503738709 --t-max 66.4595276798649 "
      "--release 0.6557602573781002 --release-spin 1.7457709304520292 --release-spin-x -20.732256122143752 "
      "--release-spin-y 17.483654399884536 --max-ode-steps 5000 --out ";
  const Result r = run(steep + path("a.json"));
  ASSERT_EQ(r.code, 0) << r.output;
  const json a = json::parse(read("a.json"));
  EXPECT_EQ(a["status"], "trapped");
  EXPECT_EQ(a["stalled"], true);
  EXPECT_LT(a["duration"].get<double>(), 66.0);
  EXPECT_EQ(a["params"]["max_ode_steps"], 5000);
  EXPECT_NE(r.output.find("funnel trajectory: warning: the run stalled"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("max-ode-steps"), std::string::npos) << r.output;
  // It names the usual cause and both bounds on the cost.
  EXPECT_NE(r.output.find("a ball that orbits the cone for a long time, rolling and sliding in turn"), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("A shorter --t-max or a lower --max-ode-steps bounds their cost"), std::string::npos)
      << r.output;
  // An ordinary run: not stalled, no warning, the default guard in its parameters.
  const Result plain = run("trajectory --space 3d --theta 60 --release 0.4 --release-w 0.05 --out " + path("b.json"));
  ASSERT_EQ(plain.code, 0) << plain.output;
  const json b = json::parse(read("b.json"));
  EXPECT_EQ(b["stalled"], false);
  EXPECT_EQ(b["params"]["max_ode_steps"], 20000000);
  EXPECT_EQ(plain.output.find("warning"), std::string::npos) << plain.output;
  // An ensemble counts its stalled runs among the trapped ones and says how many.
  const Result e = run("ensemble --space 3d --theta 50 --e 0.9 --mu 0.2 --gap 0 --t-max 60 --samples 61 "
                       "--velocity-sd 0.2 --seed 9 --max-ode-steps 20000 --out " + path("e.json"));
  ASSERT_EQ(e.code, 0) << e.output;
  const json ej = json::parse(read("e.json"));
  const std::int64_t stalled = ej["stalled"].get<std::int64_t>();
  EXPECT_GT(stalled, 0);
  EXPECT_LE(stalled, ej["status_counts"]["trapped"].get<std::int64_t>());
  EXPECT_NE(e.output.find("funnel ensemble: warning: " + std::to_string(stalled) + " of 61 runs stalled"),
            std::string::npos) << e.output;
  // Each sample says whether it stalled (the CSV's last column).
  ASSERT_EQ(run("ensemble --space 3d --theta 50 --e 0.9 --mu 0.2 --gap 0 --t-max 60 --samples 61 --velocity-sd 0.2 "
                "--seed 9 --max-ode-steps 20000 --per-sample --format csv --out " + path("p.csv")).code, 0);
  const std::vector<std::vector<std::string>> per = csv_rows(read("p.csv"));
  ASSERT_EQ(per.size(), 62u);
  EXPECT_EQ(per[0][per[0].size() - 2], "periodic");
  EXPECT_EQ(per[0].back(), "stalled");
  EXPECT_EQ(std::count_if(per.begin() + 1, per.end(), [](const auto& row) { return row.back() == "1"; }), stalled);
  // A sweep has a column of them per point, and its warning sums them over the grid.
  const Result s = run("sweep --space 3d --theta 50 --e 0.9 --mu 0.2 --gap 0 --t-max 60 --samples 61 "
                       "--velocity-sd 0.2 --seed 9 --max-ode-steps 20000,40000 --out " + path("s.csv"));
  ASSERT_EQ(s.code, 0) << s.output;
  const std::vector<std::vector<std::string>> sweep = csv_rows(read("s.csv"));
  ASSERT_EQ(sweep.size(), 3u);
  const auto column = static_cast<std::size_t>(std::find(sweep[0].begin(), sweep[0].end(), "stalled") - sweep[0].begin());
  ASSERT_LT(column, sweep[0].size());
  EXPECT_EQ(sweep[0][column - 1], "periodic");
  const std::int64_t first = std::stoll(sweep[1][column]), second = std::stoll(sweep[2][column]);
  EXPECT_EQ(first, stalled);  // the same ensemble as above
  EXPECT_LT(second, first);   // a higher guard lets more of them finish
  EXPECT_NE(s.output.find("funnel sweep: warning: " + std::to_string(first + second) + " of 122 runs stalled"),
            std::string::npos) << s.output;
  // Resumed with the first point from a partial file, the sweep still counts that point's.
  const std::string text = read("s.csv");
  const std::string first_row = text.substr(text.find('\n') + 1, text.find('\n', text.find('\n') + 1) - text.find('\n'));
  write("r.csv.partial", partial_start(nlohmann::ordered_json::parse(read("s.csv.json"))["spec"].dump(),
                                       text.substr(0, text.find('\n'))) +
                             "0,0," + std::to_string(first) + "," + first_row);
  const Result resumed = run("sweep --space 3d --theta 50 --e 0.9 --mu 0.2 --gap 0 --t-max 60 --samples 61 "
                             "--velocity-sd 0.2 --seed 9 --max-ode-steps 20000,40000 --resume --out " + path("r.csv"));
  ASSERT_EQ(resumed.code, 0) << resumed.output;
  EXPECT_EQ(json::parse(read("r.csv.json"))["resumed_points"], 1);
  EXPECT_EQ(read("r.csv"), text);
  EXPECT_NE(resumed.output.find("funnel sweep: warning: " + std::to_string(first + second) + " of 122 runs stalled"),
            std::string::npos) << resumed.output;
  // The guard is a 3D parameter: refused in 2D and out of its range, before any output.
  expect_rejected(run("trajectory --release 0.3 --max-ode-steps 5000 --out " + path("x.json")), "max-ode-steps", "5000");
  expect_rejected(run("trajectory --space 3d --release 0.3 --max-ode-steps 0 --out " + path("x.json")),
                  "max-ode-steps", "0");
  expect_rejected(run("ensemble --space 3d --samples 4 --max-ode-steps 2.5 --out " + path("x.json")),
                  "max-ode-steps", "2.5");
  EXPECT_FALSE(std::filesystem::exists(path("x.json")));
}

TEST_F(Cli, ASweepConfigSetsTheThreeDimensionalParameters) {
  // They were refused as unknown keys, so a 3D grid could not live in a config file.
  write("g.toml", "samples = 8\n[grid]\ntheta = [50, 60]\nrelease_w = 0.05\nmax-ode-steps = \"1000,2000\"\n");
  const Result r = run("sweep --space 3d --config " + path("g.toml") + " --out " + path("s.csv"));
  ASSERT_EQ(r.code, 0) << r.output;
  ASSERT_EQ(run("sweep --space 3d --theta 50,60 --release-w 0.05 --max-ode-steps 1000,2000 --samples 8 --out " +
                path("t.csv")).code, 0);
  EXPECT_EQ(read("s.csv"), read("t.csv"));
  // In 2D they are refused by name, before any output.
  expect_rejected(run("sweep --config " + path("g.toml") + " --out " + path("x.csv")), "release-w", "0.05");
  EXPECT_FALSE(std::filesystem::exists(path("x.csv")));
  // A misspelt one is still an unknown key, with the nearest valid one.
  write("bad.toml", "release-spin-q = 1\n");
  const Result bad = run("sweep --space 3d --config " + path("bad.toml") + " --out " + path("x.csv"));
  EXPECT_EQ(bad.code, 2) << bad.output;
  EXPECT_NE(bad.output.find("did you mean 'release-spin"), std::string::npos) << bad.output;
  // The command line's other name of the spin about z is its name in a config too (it was
  // refused, suggesting release-spin-x: the spin about another axis).
  write("z.toml", "samples = 8\ntheta = 50\nrelease-spin-z = 2\n");
  ASSERT_EQ(run("sweep --space 3d --config " + path("z.toml") + " --out " + path("z.csv")).code, 0);
  ASSERT_EQ(run("sweep --space 3d --theta 50 --release-spin 2 --samples 8 --out " + path("w.csv")).code, 0);
  EXPECT_EQ(read("z.csv"), read("w.csv"));
}

TEST_F(Cli, TwoDimensionalOutputsKeepTheirColumnsAndThreeDimensionalOnesAddTheirs) {
  ASSERT_EQ(run("trajectory --release 0.3 --events --format csv --out " + path("a.csv")).code, 0);
  const std::string a = read("a.csv");
  EXPECT_EQ(a.substr(0, a.find('\n')),
            "time,kind,wall,x,y,u_before,v_before,omega_before,u_after,v_after,omega_after,slip_before,regime,j_n,j_t,"
            "energy_lost");
  ASSERT_EQ(run("ensemble --samples 8 --format csv --out " + path("e.csv")).code, 0);
  EXPECT_EQ(read("e.csv").find("release_w"), std::string::npos);
  EXPECT_EQ(read("e.csv").find("orbits"), std::string::npos);
  ASSERT_EQ(run("sweep --space 3d --theta 50,60 --release-w 0,0.05 --samples 8 --out " + path("s.csv")).code, 0);
  const std::string s = read("s.csv");
  const std::string header = s.substr(0, s.find('\n'));
  EXPECT_NE(header.find("release_w"), std::string::npos) << header;
  EXPECT_NE(header.find("orbits_mean"), std::string::npos) << header;
  EXPECT_NE(header.find("exit_w_mean"), std::string::npos) << header;
  EXPECT_EQ(std::count(s.begin(), s.end(), '\n'), 5);  // the header and 2 x 2 points
}

}  // namespace
