// The designer's outputs from the command line: exit state, wear, release control, random
// ensembles and their validation.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

#include "cli_util.hpp"

namespace {

using namespace funnel_test;
using nlohmann::json;

json parse(const Result& r) {
  EXPECT_EQ(r.code, 0) << r.output;
  return json::parse(r.output.substr(r.output.find('{')));
}

TEST_F(Cli, TrajectoryReportsTheExitStateAndASimpleThrowMatchesTheClosedForm) {
  const json j = parse(run("trajectory --release 0 --release-v -0.5 --release-height 0.8"));
  EXPECT_EQ(j["status"], "exited");
  const double speed = std::sqrt(0.25 + 1.6);
  EXPECT_NEAR(j["duration"].get<double>(), speed - 0.5, 1e-14);
  EXPECT_NEAR(j["exit_speed"].get<double>(), speed, 1e-14);
  EXPECT_EQ(j["exit_angle"].get<double>(), 0.0);
  EXPECT_EQ(j["params"]["release_height"].get<double>(), 0.8);
  EXPECT_EQ(j["v0"].get<double>(), -0.5);
  for (const char* key : {"exit_x", "exit_u", "exit_v", "exit_spin", "edge_contacts"}) EXPECT_TRUE(j.contains(key)) << key;
  // A run that does not exit has no exit state: null in JSON, empty in CSV.
  const json trapped = parse(run("trajectory --release 0.3 --t-max 1"));
  EXPECT_EQ(trapped["status"], "trapped");
  EXPECT_TRUE(trapped["exit_speed"].is_null());
  const Result csv = run("trajectory --release 0.3 --t-max 1 --format csv");
  EXPECT_NE(csv.output.find(",trapped,"), std::string::npos) << csv.output;
  EXPECT_NE(csv.output.find(",,,,,\n"), std::string::npos) << csv.output;
}

TEST_F(Cli, WearBinsSumToTheTotalsInJsonAndCsv) {
  const json j = parse(run("trajectory --theta 30 --e 0.5 --release -0.6 --wear-bins 6"));
  const json& w = j["wear"];
  ASSERT_EQ(w["left"]["normal_impulse"].size(), 6u);
  double normal = 0.0, collisions = 0.0;
  for (const char* side : {"left", "right"}) {
    for (const auto& x : w[side]["normal_impulse"]) normal += x.get<double>();
    for (const auto& x : w[side]["collisions"]) collisions += x.get<double>();
    normal += w[side]["edge"]["normal_impulse"].get<double>();
    collisions += w[side]["edge"]["collisions"].get<double>();
  }
  EXPECT_NEAR(normal, j["normal_impulse"].get<double>(), 1e-12 * normal);
  EXPECT_EQ(collisions, j["collisions"].get<double>());
  EXPECT_NEAR(w["bin_width"].get<double>() * 6, 1.0 / std::sin(30.0 * M_PI / 180.0), 1e-12);
  // CSV: a header, then one row per wall and bin, and the edge of each wall.
  const Result csv = run("trajectory --theta 30 --e 0.5 --release -0.6 --wear-bins 6 --format csv");
  ASSERT_EQ(csv.code, 0) << csv.output;
  EXPECT_EQ(csv.output.rfind("wall,bin,s,collisions,normal_impulse,impulse\n", 0), 0u);
  EXPECT_EQ(std::count(csv.output.begin(), csv.output.end(), '\n'), 1 + 2 * 7);
  // The event log and the wear table do not share one CSV.
  expect_rejected(run("trajectory --release 0.1 --wear-bins 3 --events --format csv"), "wear-bins", "events");
}

TEST_F(Cli, EachWallOfAnAsymmetricFunnelIsBinnedOverItsOwnLength) {
  // 30 and 70 degrees: the walls are 1/sin(30) = 2 and 1/sin(70) = 1.064 long up to the release
  // height; each wall's bins, and the positions s of their centres, are its own.
  const std::string cmd = "ensemble --theta-left 30 --theta-right 70 --samples 40 --wear-bins 10";
  const json j = parse(run(cmd));
  const json& w = j["wear"];
  const double left = 1.0 / std::sin(30.0 * M_PI / 180.0), right = 1.0 / std::sin(70.0 * M_PI / 180.0);
  EXPECT_NEAR(w["left"]["bin_width"].get<double>() * 10, left, 1e-12);
  EXPECT_NEAR(w["right"]["bin_width"].get<double>() * 10, right, 1e-12);
  EXPECT_EQ(w["bin_width"], w["left"]["bin_width"]);
  EXPECT_NEAR(w["left"]["s"].back().get<double>(), 0.95 * left, 1e-12);
  EXPECT_NEAR(w["right"]["s"].back().get<double>(), 0.95 * right, 1e-12);
  // The CSV's s column: the right wall's last bin is centred 0.95 of its own length up.
  const Result csv = run(cmd + " --format csv");
  ASSERT_EQ(csv.code, 0) << csv.output;
  std::istringstream lines(csv.output);
  std::string line, last_right;
  while (std::getline(lines, line)) {
    if (line.rfind("right,9,", 0) == 0) last_right = line;
  }
  ASSERT_FALSE(last_right.empty()) << csv.output;
  const std::string s = last_right.substr(8, last_right.find(',', 8) - 8);
  EXPECT_NEAR(std::stod(s), 0.95 * right, 1e-12) << last_right;
}

TEST_F(Cli, TheGaussiansMeanAndSpreadAreRefusedWithAnotherDistribution) {
  // They were ignored: the run looked as asked for and was the plain line's.
  const std::string out = " --out " + path("e.json");
  for (const std::string& command : {"ensemble --samples 20 --release 0.5" + out,
                                     "ensemble --samples 20 --release-dist uniform --release-sd 0.2" + out,
                                     "ensemble --space 3d --samples 20 --release 0.5 --release-sd 0.2" + out,
                                     "closed --samples 20 --release 0.5" + out,
                                     "sweep --samples 20 --theta 40,50 --release-sd 0.2 --out " + path("s.csv")}) {
    const Result r = run(command);
    EXPECT_EQ(r.code, 2) << command << "\n" << r.output;
    EXPECT_NE(r.output.find("valid range is -1 < release < 1, with --release-dist gaussian only") != std::string::npos ||
                  r.output.find("valid range is 0 < release-sd <= 10, with --release-dist gaussian only"), std::string::npos) << command << "\n" << r.output;
  }
  EXPECT_EQ(file_count(), 0u);
  EXPECT_EQ(run("ensemble --samples 20 --release-dist gaussian --release 0.5 --release-sd 0.2" + out).code, 0);
}

TEST_F(Cli, RandomEnsemblesAreTheSameForAnyThreadCountAndChangeWithTheSeed) {
  const std::string base = "ensemble --theta 52 --samples 300 --release-dist gaussian --release 0.2 "
                           "--release-sd 0.3 --velocity-sd 0.05 --wear-bins 4 ";
  json one = parse(run(base + "--seed 7 --threads 1"));
  json two = parse(run(base + "--seed 7 --threads 2"));
  one.erase("provenance");
  two.erase("provenance");
  EXPECT_EQ(one.dump(), two.dump());
  EXPECT_EQ(one["seed"], 7);
  EXPECT_EQ(one["simulated_collisions"], one["total_collisions"]);  // nothing mirrored
  json other = parse(run(base + "--seed 8 --threads 2"));
  EXPECT_NE(other["duration"]["mean"], one["duration"]["mean"]);
  const json u = parse(run("ensemble --samples 200 --release-dist uniform"));
  EXPECT_EQ(u["release_dist"], "uniform");
  EXPECT_EQ(u["status_counts"]["exited"], 200);
}

TEST_F(Cli, ReleaseAndEnsembleOptionsAreValidated) {
  const std::string out = " --out " + path("x.json");
  expect_rejected(run("trajectory --release 0 --release-height 0" + out), "release-height", "0");
  expect_rejected(run("trajectory --release 0 --release-height -1" + out), "release-height", "-1");
  expect_rejected(run("trajectory --release 0 --release-u nan" + out), "release-u", "nan");
  expect_rejected(run("trajectory --release 0 --release-spin 1e9" + out), "release-spin", "1e+09");
  expect_rejected(run("trajectory --release 0 --wear-bins -2" + out), "wear-bins", "-2");
  expect_rejected(run("ensemble --release-dist gaussian --release-sd 0" + out), "release-sd", "0");
  expect_rejected(run("ensemble --release-dist gaussian --release 1" + out), "release", "1");
  expect_rejected(run("ensemble --velocity-sd -0.1" + out), "velocity-sd", "-0.1");
  expect_rejected(run("ensemble --seed -4" + out), "seed", "-4");
  // A seed where nothing is random would look like another sample: refused, in 2D and 3D.
  expect_rejected(run("ensemble --seed 3" + out), "seed = 3", "with random releases or velocities only");
  expect_rejected(run("sweep --theta 40,50 --seed 3 --out " + path("s.csv")), "seed = 3", "random releases");
  expect_rejected(run("ensemble --space 3d --seed 3" + out), "seed = 3",
                  "with random velocities only (--velocity-sd > 0: in 3d the releases are line or disk;");
  // funnel closed has no --velocity-sd: its refusal does not send the user to it.
  expect_rejected(run("closed --seed 3" + out), "seed = 3", "with random releases only (--release-dist uniform or gaussian;");
  expect_rejected(run("ensemble --wear-bins 2000000" + out), "wear-bins", "2000000");
  // An ensemble keeps a record per chunk: 10^6 bins took 12 GB; at most 10^4 (about 120 MB).
  expect_rejected(run("ensemble --wear-bins 10001" + out), "wear-bins = 10001",
                  "valid range is an integer 0 <= wear-bins <= 10^4");
  // A list or a range where one value is taken says so ("not a finite number" before).
  expect_rejected(run("ensemble --theta 40,50" + out), "theta = '40,50'",
                  "a list or range of 2 values, where one value is taken; valid range is 0 < theta < 90");
  expect_rejected(run("trajectory --release 0 --e 0.5:0.9:0.1" + out), "e = '0.5:0.9:0.1'", "range of 5 values");
  expect_rejected(run("trajectory --release 0 --e half" + out), "e = 'half'", "not a finite number; valid range");
  // A whole number beyond the int64 cap is out of range, not "not an integer"; the range says so.
  expect_rejected(run("trajectory --release 0 --max-collisions 9223372036854775807" + out), "max-collisions",
                  "'9223372036854775807': out of range; valid range is 1 <= max-collisions < 9e18 (an integer)");
  expect_rejected(run("trajectory --release 0 --max-collisions 1.5" + out), "max-collisions",
                  "'1.5': 1.5 is not an integer");
  // A sweep's values say the same (it called 1e19 "not an integer").
  expect_rejected(run("sweep --samples 10 --max-collisions 5,1e19 --out " + path("s.csv")), "max-collisions",
                  "'5,1e19': out of range; valid range is 1 <= max-collisions < 9e18 (an integer)");
  expect_rejected(run("sweep --samples 10 --max-collisions 2.5 --out " + path("s.csv")), "max-collisions",
                  "'2.5': 2.5 is not an integer");
  EXPECT_EQ(file_count(), 0u);
}

TEST_F(Cli, SweepsVaryTheReleaseLikeAnyParameter) {
  const Result r = run("sweep --release-height 0.5,1 --release-v 0,-1 --samples 20 --out " + path("s.csv"));
  ASSERT_EQ(r.code, 0) << r.output;
  const std::string csv = read("s.csv");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 5);
  EXPECT_NE(csv.find(",0.5,0,-1,0,60,60,0,line,20,"), std::string::npos) << csv;
}

TEST_F(Cli, AGeometryFileGivesAnyFunnelAndItsWallsInTheJson) {
  write("hopper.toml", "mirror = true\n[left]\nvertices = [[-2.0, 1.6], [-0.5, 0.734], [-0.1, -0.365]]\n");
  const json t = parse(run("trajectory --geometry " + path("hopper.toml") + " --release 0"));
  // Released at rest on the axis of a symmetric funnel: a free fall from 1 above the outlet.
  EXPECT_EQ(t["status"], "exited");
  EXPECT_EQ(t["collisions"], 0);
  EXPECT_NEAR(t["exit_speed"].get<double>(), std::sqrt(2.0), 1e-14);
  EXPECT_EQ(t["geometry"]["source"], path("hopper.toml"));
  EXPECT_TRUE(t["geometry"]["symmetric"].get<bool>());
  EXPECT_EQ(t["geometry"]["walls"]["right"].back()[0].get<double>(), 0.1);
  EXPECT_EQ(t["geometry"]["walls"]["left"].size(), 3u);
  const json e = parse(run("ensemble --geometry " + path("hopper.toml") + " --samples 200"));
  EXPECT_EQ(e["simulated_collisions"].get<std::int64_t>() * 2, e["total_collisions"].get<std::int64_t>());
  // Sweeps take the geometry for every point.
  const Result s = run("sweep --geometry " + path("hopper.toml") + " --e 0.5,0.9 --samples 50 --out " + path("s.csv"));
  ASSERT_EQ(s.code, 0) << s.output;
  const std::string csv = read("s.csv");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 3);
}

TEST_F(Cli, TheGeometryRecordOfAVAsAFileIsTheVBitForBit) {
  // The record of a spouted asymmetric V, written as a geometry file with 17 digits: the same
  // per-sample results as the V's shortcuts.
  const std::string v = " --theta 40 --theta-right 52 --spout-length 0.2 --gap 0.08";
  const json g = parse(run("trajectory --release 0 --t-max 1" + v))["geometry"];
  std::string toml = "bottom = " + g["bottom"].dump() + "\n";
  for (const char* side : {"left", "right"}) toml += std::string("[") + side + "]\nvertices = " + g["walls"][side].dump() + "\n";
  write("v.toml", toml);
  const std::string common = "ensemble --samples 600 --per-sample --format csv --t-max 300";
  const Result a = run(common + v), b = run(common + " --geometry " + path("v.toml"));
  ASSERT_EQ(a.code, 0) << a.output;
  ASSERT_EQ(b.code, 0) << b.output;
  EXPECT_EQ(std::count(a.output.begin(), a.output.end(), '\n'), 601);
  EXPECT_EQ(a.output, b.output);
}

TEST_F(Cli, BenchHeadlinesTheCollisionsActuallyComputed) {
  const json b = parse(run("bench --samples 2000 --repeat 1 --format json"));
  const json& e = b["reference_ensemble"];
  const auto computed = e["computed_collisions"].get<std::int64_t>();
  // The reference V is mirror symmetric: one half is computed, the other counted as its mirror.
  EXPECT_EQ(2 * computed, e["collisions_with_mirror_images"].get<std::int64_t>());
  EXPECT_GT(computed, 100000);
  EXPECT_NEAR(e["computed_collisions_per_second"].get<double>() * e["wall_time_s"].get<double>(),
              static_cast<double>(computed), 1e-6 * static_cast<double>(computed));
  EXPECT_FALSE(e.contains("collisions_per_second"));  // no unlabelled mirrored count
  // Every path this CPU runs, on one thread and on every core, with the same collisions.
  const json& paths = b["reference_ensemble_by_path"];
  ASSERT_GE(paths.size(), 1U);
  EXPECT_EQ(paths[0]["path"], "scalar");
  EXPECT_EQ(paths[0]["lanes"], 1);
  for (const json& p : paths) {
    EXPECT_NEAR(p["computed_collisions_per_second"].get<double>() * p["wall_time_s"].get<double>(),
                static_cast<double>(computed), 1e-6 * static_cast<double>(computed)) << p.dump();
  }
  const json one = parse(run("bench --samples 500 --repeat 1 --simd scalar --format json"));
  ASSERT_GE(one["reference_ensemble_by_path"].size(), 1U);
  for (const json& p : one["reference_ensemble_by_path"]) EXPECT_EQ(p["path"], "scalar");
  const Result bad = run("bench --simd avx1024");
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.output.find("invalid simd = 'avx1024': valid values on this CPU are all, scalar"), std::string::npos)
      << bad.output;
}

TEST_F(Cli, EveryEnginePathWritesTheSameBytes) {
  // FUNNEL_SIMD chooses the engine's path; the results are the same bits on every one (a name
  // this CPU cannot run is ignored: the widest path is used).
  const std::string sweep = "sweep --theta 30,46,60 --mu 0.1,1 --samples 300 --out ";
  const std::string closed = "closed --theta 50 --mu 0.01 --samples 100 --format csv --out ";
  for (const std::string path : {"scalar", "sse4", "avx2", "avx512", "avx1024"}) {
    const std::string env = "FUNNEL_SIMD=" + path;
    ASSERT_EQ(run(sweep + this->path(path + ".csv"), env).code, 0);
    ASSERT_EQ(run(closed + this->path(path + "_closed.csv"), env).code, 0);
    EXPECT_EQ(read(path + ".csv"), read("scalar.csv")) << path;
    EXPECT_EQ(read(path + "_closed.csv"), read("scalar_closed.csv")) << path;
  }
}

TEST_F(Cli, TheVsShortcutsSweepAndAsymmetryIsNotHalved) {
  const json e = parse(run("ensemble --theta-left 40 --theta-right 50 --samples 200"));
  EXPECT_EQ(e["simulated_collisions"], e["total_collisions"]);  // not mirror symmetric: no halving
  EXPECT_EQ(e["params"]["theta_left"].get<double>(), 40.0);
  const json spout = parse(run("trajectory --spout-length 0.5 --release 0"));
  EXPECT_NEAR(spout["exit_speed"].get<double>(), std::sqrt(3.0), 1e-14);
  const Result s = run("sweep --theta-right 50,55 --samples 20 --out " + path("a.csv"));
  ASSERT_EQ(s.code, 0) << s.output;
  EXPECT_NE(read("a.csv").find(",60,55,0,line,20,"), std::string::npos) << read("a.csv");
}

TEST_F(Cli, BadGeometriesAreRefusedNamingTheFileTheKeyAndTheRule) {
  const std::string out = " --out " + path("never.json");
  write("typo.toml", "mirror = true\n[left]\nvertice = [[-1, 1], [0, 0]]\n");
  Result r = run("ensemble --geometry " + path("typo.toml") + out);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("did you mean 'vertices'"), std::string::npos) << r.output;
  write("overhang.toml", "mirror = true\n[left]\nvertices = [[-1, 1], [-1.5, 0.5], [-0.1, 0]]\n");
  r = run("ensemble --geometry " + path("overhang.toml") + out);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("geometry left segment 0-1"), std::string::npos) << r.output;
  write("narrow.toml", "[left]\nvertices = [[-1, 1], [-0.005, 0]]\n[right]\nvertices = [[1, 1], [0.005, 0]]\n");
  r = run("trajectory --release 0 --geometry " + path("narrow.toml") + out);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("geometry outlet"), std::string::npos) << r.output;
  r = run("ensemble --geometry " + path("missing.toml") + out);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("no such file"), std::string::npos) << r.output;
  write("ok.toml", "mirror = true\n[left]\nvertices = [[-1, 1], [-0.1, 0]]\n");
  r = run("ensemble --geometry " + path("ok.toml") + " --spout-length 0.1" + out);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("spout-length"), std::string::npos) << r.output;
  expect_rejected(run("ensemble --theta-left 95" + out), "theta-left", "95");
  expect_rejected(run("ensemble --gap 0 --spout-length 0.1" + out), "spout-length", "0.1");
  // A bottom that puts the release line below the exit level (the particle "exited" at once,
  // after no time), or one beyond the vertices' range.
  write("low.toml", "mirror = true\nbottom = -1.37\n[left]\nvertices = [[-1, 1], [-0.1, 0]]\n");
  expect_rejected(run("trajectory --release 0.3 --geometry " + path("low.toml") + out), "geometry bottom = -1.37",
                  "above the exit level y = 0");
  write("high.toml", "mirror = true\nbottom = 1e300\n[left]\nvertices = [[-1, 1], [-0.1, 0]]\n");
  expect_rejected(run("trajectory --release 0.3 --geometry " + path("high.toml") + out), "geometry bottom = 1e+300",
                  "|bottom| <= 1e6");
  EXPECT_EQ(file_count(), 6u);  // the six geometry files, no output
}

TEST_F(Cli, TheVsAnglesAndGapAreRefusedWithAGeometryFile) {
  // The file defines the walls: --theta or --gap would be ignored, yet recorded in the output as
  // if used, and a sweep over them would label equal rows as different funnels.
  write("ok.toml", "mirror = true\n[left]\nvertices = [[-1, 1], [-0.1, 0]]\n");
  const std::string geometry = " --geometry " + path("ok.toml");
  const std::string message = "valid range is not with a geometry file";
  for (const std::string& command :
       {"trajectory --release 0.3 --theta 50" + geometry + " --out " + path("t.json"),
        "ensemble --samples 20 --gap 0.1" + geometry + " --out " + path("e.json"),
        "closed --samples 20 --theta 50" + geometry + " --out " + path("c.json"),
        "sweep --samples 20 --theta 40,50" + geometry + " --out " + path("s.csv")}) {
    const Result r = run(command);
    EXPECT_EQ(r.code, 2) << command << "\n" << r.output;
    EXPECT_NE(r.output.find(message), std::string::npos) << r.output;
    EXPECT_TRUE(r.output.find("invalid theta = 50") != std::string::npos ||
                r.output.find("invalid gap = 0.1") != std::string::npos ||
                r.output.find("invalid theta = 40,50") != std::string::npos)
        << r.output;
  }
  write("sweep.toml", "[grid]\ntheta = [40, 50]\n");
  const Result from_config = run("sweep --samples 20 --config " + path("sweep.toml") + geometry + " --out " + path("s.csv"));
  EXPECT_EQ(from_config.code, 2) << from_config.output;
  EXPECT_NE(from_config.output.find("invalid theta = 40,50: valid range is not with a geometry file"), std::string::npos)
      << from_config.output;
  EXPECT_EQ(file_count(), 2u);  // the geometry file and the config, no output
  // The particle's parameters still go with a file.
  EXPECT_EQ(run("trajectory --release 0.3 --e 0.9 --radius 0.02" + geometry).code, 0);
}

TEST_F(Cli, ThetaIsRefusedWithBothWallsAnglesAndReportedAsNone) {
  // With both --theta-left and --theta-right, --theta changed nothing, yet a sweep over it wrote
  // equal rows labelled 40 and 50.
  for (const std::string& command : {"ensemble --samples 20 --theta 40 --theta-left 30 --theta-right 35 --out " + path("e.json"),
                                     "sweep --samples 20 --theta 40,50 --theta-left 30 --theta-right 35 --out " + path("s.csv"),
                                     "closed --samples 20 --theta 40 --theta-left 30 --theta-right 35 --out " + path("c.json")}) {
    const Result r = run(command);
    EXPECT_EQ(r.code, 2) << command << "\n" << r.output;
    EXPECT_NE(r.output.find("valid range is not with both theta-left and theta-right"), std::string::npos) << r.output;
  }
  EXPECT_EQ(file_count(), 0u);
  // Without it the output shows no theta (null, an empty field), not the default 60.
  const json j = parse(run("ensemble --samples 20 --theta-left 30 --theta-right 35"));
  EXPECT_TRUE(j["params"]["theta"].is_null());
  EXPECT_EQ(j["params"]["theta_left"].get<double>(), 30.0);
  const Result csv = run("sweep --samples 20 --theta-left 30,40 --theta-right 35 --out -");
  ASSERT_EQ(csv.code, 0) << csv.output;
  EXPECT_NE(csv.output.find("\n,0.99,1,0,"), std::string::npos) << csv.output;
  EXPECT_EQ(csv.output.find("\n60,"), std::string::npos) << csv.output;
  // One wall's angle still leaves theta the other's.
  EXPECT_EQ(parse(run("ensemble --samples 20 --theta 40 --theta-right 35"))["params"]["theta"].get<double>(), 40.0);
}

TEST_F(Cli, DiskReleasesAreRefusedInAFunnelThatIsNotMirrorSymmetric) {
  // x0 = r > 0 only: in an asymmetric funnel the left half was never released from, and the
  // mirror funnel gave another mean duration (21.3 against 15.9).
  write("lopsided.toml", "[left]\nvertices = [[-1, 1], [-0.1, 0]]\n[right]\nvertices = [[1, 1], [0.5, 0.6], [0.1, 0]]\n");
  for (const std::string& command :
       {"ensemble --samples 20 --release-dist disk --theta-left 30 --theta-right 70 --out " + path("e.json"),
        "ensemble --samples 20 --release-dist disk --geometry " + path("lopsided.toml") + " --out " + path("e.json"),
        "sweep --samples 20 --release-dist disk --theta 40 --theta-right 40,50 --out " + path("s.csv"),
        "closed --samples 20 --release-dist disk --theta-right 50 --out " + path("c.json")}) {
    const Result r = run(command);
    EXPECT_EQ(r.code, 2) << command << "\n" << r.output;
    EXPECT_NE(r.output.find("invalid release-dist = disk: valid range is line, uniform or gaussian in a funnel that is "
                            "not mirror symmetric"),
              std::string::npos)
        << r.output;
  }
  EXPECT_EQ(file_count(), 1u);  // the geometry file only
  // In a grid where only some funnels are asymmetric, the refusal says at which point.
  const Result part = run("sweep --samples 20 --release-dist disk --theta-right 60,65 --mu 0,1 --out " + path("s.csv"));
  EXPECT_EQ(part.code, 2) << part.output;
  EXPECT_NE(part.output.find("(at the grid point mu = 0, theta-right = 65)"), std::string::npos) << part.output;
  // A symmetric funnel, given either way, takes them.
  EXPECT_EQ(run("ensemble --samples 20 --release-dist disk --theta-left 40 --theta-right 40").code, 0);
  EXPECT_EQ(run("ensemble --samples 20 --release-dist disk --spout-length 0.2").code, 0);
}

TEST_F(Cli, AMaterialParameterThatEveryWallSetsIsRefusedWithItsFile) {
  // Both walls set their own mu: --mu would change nothing, and a sweep over it labelled equal
  // rows as different. One wall's own e leaves --e the other wall's, which goes with the file.
  write("lined.toml", "[left]\nvertices = [[-2, 1.6], [-0.1, -0.365]]\nmu = 0.1\n"
                      "[right]\nvertices = [[0.9, 1.6], [0.1, -0.365]]\ne = 0.5\nmu = 1.2\n");
  const std::string geometry = " --geometry " + path("lined.toml");
  const std::string walls = ": valid range is not with a geometry file whose walls all set their own mu (" +
                            path("lined.toml") + ": left 0.1, right 1.2)";
  for (const std::string& command : {"trajectory --release 0.3 --mu 0.5" + geometry + " --out " + path("t.json"),
                                     "ensemble --samples 20 --mu 0.5" + geometry + " --out " + path("e.json"),
                                     "closed --samples 20 --mu 0.5" + geometry + " --out " + path("c.json")}) {
    const Result r = run(command);
    EXPECT_EQ(r.code, 2) << command << "\n" << r.output;
    EXPECT_NE(r.output.find("invalid mu = 0.5" + walls), std::string::npos) << r.output;
  }
  const Result sweep = run("sweep --samples 20 --mu 0:5:1" + geometry + " --out " + path("s.csv"));
  EXPECT_EQ(sweep.code, 2) << sweep.output;
  EXPECT_NE(sweep.output.find("invalid mu = 0:5:1" + walls), std::string::npos) << sweep.output;
  EXPECT_EQ(file_count(), 1u);  // the geometry file, no output
  // --e reaches the left wall: two values, two results.
  const Result e = run("sweep --samples 200 --e 0.5,0.9" + geometry + " --out " + path("e.csv"));
  ASSERT_EQ(e.code, 0) << e.output;
  std::stringstream rows(read("e.csv"));
  std::string header, a, b;
  std::getline(rows, header);
  std::getline(rows, a);
  std::getline(rows, b);
  const auto stats = [](const std::string& row) { return row.substr(row.find(",line,")); };
  EXPECT_NE(stats(a), stats(b));
  // The parameters the file replaces have no value in the outputs (not the default V's theta):
  // the V's, and mu, which both walls set; e, which the left wall takes, keeps its value.
  EXPECT_EQ(header.rfind("theta,e,mu,beta0,radius,gap,", 0), 0u) << header;
  EXPECT_EQ(a.rfind(",0.5,,0,0.01,,", 0), 0u) << a;
  EXPECT_NE(header.find(",theta_left,theta_right,spout_length,release_dist,"), std::string::npos) << header;
  EXPECT_NE(a.find(",,,,line,"), std::string::npos) << a;
  ASSERT_EQ(run("trajectory --release 0.3" + geometry + " --out " + path("t.json")).code, 0);
  const json params = json::parse(read("t.json"))["params"];
  for (const char* unused : {"theta", "gap", "theta_left", "theta_right", "spout_length", "mu"}) {
    EXPECT_TRUE(params[unused].is_null()) << unused << " " << params.dump();
  }
  EXPECT_EQ(params["e"], 0.99);
  EXPECT_EQ(params["radius"], 0.01);
  // A V keeps every value.
  ASSERT_EQ(run("trajectory --release 0.3 --out " + path("v.json")).code, 0);
  EXPECT_EQ(json::parse(read("v.json"))["params"]["theta"], 60.0);
  // funnel closed's own default e = 1 is not a given e: a closed wedge whose walls set their own
  // e runs (it was refused, "invalid e = 1", with no --e given), and reports no e.
  write("wedge.toml", "mirror = true\n[left]\nvertices = [[-1.0, 1.2], [0.0, 0.0]]\ne = 1\nmu = 0.5\n");
  const Result wedge = run("closed --samples 4 --threads 1 --geometry " + path("wedge.toml") + " --out " + path("w.json"));
  ASSERT_EQ(wedge.code, 0) << wedge.output;
  const json closed = json::parse(read("w.json"));
  EXPECT_TRUE(closed["params"]["e"].is_null()) << closed["params"].dump();
  EXPECT_EQ(closed["periodic_fraction"], 1.0);
}

TEST_F(Cli, ASweepOfAGeometryFileResumesOnlyTheSameWalls) {
  // The partial file of an interrupted sweep records the walls and materials as read: edited
  // walls are another funnel, whose rows must not be mixed in; a renamed file is the same one.
  const std::string walls = "mirror = true\n[left]\nvertices = [[-2.0, 1.6], [-0.5, 0.734], [-0.1, -0.365]]\n";
  write("a.toml", walls);
  write("renamed.toml", "# the same walls\n" + walls);
  std::string edited = walls;
  edited.replace(edited.find("-0.1,"), 5, "-0.12,");
  write("b.toml", edited);
  const std::string grid = "sweep --e 0.5,0.7,0.9 --samples 200 --threads 1 --geometry ";
  ASSERT_EQ(run(grid + path("a.toml") + " --out " + path("full.csv")).code, 0);
  const nlohmann::ordered_json spec = nlohmann::ordered_json::parse(read("full.csv.json"))["spec"];
  ASSERT_TRUE(spec.contains("geometry")) << spec.dump();
  EXPECT_EQ(spec["geometry"]["left"]["vertices"][2][0].get<double>(), -0.1);
  std::stringstream in(read("full.csv"));
  std::string header, first;
  std::getline(in, header);
  std::getline(in, first);
  // One finished point, as an interrupted run leaves it.
  const std::string partial = partial_start(spec.dump(), header) + "0,0,0," + first + "\n";
  write("cut.csv.partial", partial);
  expect_rejected(run(grid + path("b.toml") + " --out " + path("cut.csv") + " --resume"), "resume", "geometry");
  EXPECT_EQ(read("cut.csv.partial"), partial);
  const Result r = run(grid + path("renamed.toml") + " --out " + path("cut.csv") + " --resume");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("resuming: 1 of 3 points"), std::string::npos) << r.output;
  EXPECT_EQ(read("cut.csv"), read("full.csv"));
}

TEST_F(Cli, ResumeWithNothingToResumeSaysSoAndAnEmptyPartialFileBlocksNothing) {
  const std::string grid = "sweep --theta 40,50 --samples 20 --out " + path("s.csv");
  // --resume without a partial file runs every point, and says that nothing was continued.
  const Result fresh = run(grid + " --resume");
  ASSERT_EQ(fresh.code, 0) << fresh.output;
  EXPECT_NE(fresh.output.find("--resume: no finished point in '" + path("s.csv.partial") + "' to continue (no such file)"),
            std::string::npos) << fresh.output;
  const std::string full = read("s.csv");
  // A partial file left before its first point was finished holds nothing to lose: not refused.
  const std::string spec = nlohmann::ordered_json::parse(read("s.csv.json"))["spec"].dump();
  write("s.csv.partial", partial_start(spec, full.substr(0, full.find('\n'))));
  fs::remove(path("s.csv"));
  const Result again = run(grid);
  ASSERT_EQ(again.code, 0) << again.output;
  EXPECT_EQ(read("s.csv"), full);
  EXPECT_FALSE(fs::exists(path("s.csv.partial")));
  // Nor with --resume, even empty (it was called "made by a different sweep").
  write("s.csv.partial", "");
  const Result empty = run(grid + " --resume");
  ASSERT_EQ(empty.code, 0) << empty.output;
  EXPECT_NE(empty.output.find("--resume: no finished point in"), std::string::npos) << empty.output;
  EXPECT_EQ(read("s.csv"), full);
  // A line cut by a kill (no newline) is not counted among the finished points.
  const std::string first = full.substr(full.find('\n') + 1, full.find('\n', full.find('\n') + 1) - full.find('\n'));
  write("s.csv.partial", partial_start(spec, full.substr(0, full.find('\n'))) + "0,0,0," + first + "1,0,0,50,0.9");
  const Result refused = run(grid);
  EXPECT_EQ(refused.code, 2) << refused.output;
  EXPECT_NE(refused.output.find("holds 1 finished point of"), std::string::npos) << refused.output;
  // A directory where the partial file goes is named as such, with or without --resume.
  fs::remove(path("s.csv.partial"));
  fs::create_directories(path("s.csv.partial"));
  expect_rejected(run(grid + " --resume"), "s.csv.partial", "is a directory");
  expect_rejected(run(grid), "s.csv.partial", "is a directory");
  fs::remove(path("s.csv.partial"));
  // A partial file of an earlier funnel sweep (no counts in its lines) is named as such.
  write("s.csv.partial", "# funnel sweep spec: " + spec + "\npoint," + full.substr(0, full.find('\n') + 1) + "0," + first);
  expect_rejected(run(grid + " --resume"), "s.csv.partial", "written by an earlier funnel sweep");
}

TEST_F(Cli, SamplesMayBeWrittenAsAnyWholeNumber) {
  // 2e1 as --max-collisions 1e8 is: the same run as 20; 1.5 and 1e10 are refused.
  json a = parse(run("ensemble --samples 2e1"));
  json b = parse(run("ensemble --samples 20"));
  a.erase("provenance");
  b.erase("provenance");
  EXPECT_EQ(a, b);
  EXPECT_EQ(a["samples"], 20);
  expect_rejected(run("ensemble --samples 1.5"), "samples", "'1.5': valid range is an integer 1 <= samples <= 10^9");
  expect_rejected(run("ensemble --samples 1e10"), "samples", "1e10");
  // So may --wear-bins and --seed (they were refused as "not an integer" in that form).
  for (const auto& [form, plain] : std::vector<std::pair<std::string, std::string>>{
           {"--wear-bins 1e1", "--wear-bins 10"}, {"--seed 1e3 --release-dist uniform", "--seed 1000 --release-dist uniform"}}) {
    json x = parse(run("ensemble --samples 20 " + form));
    json y = parse(run("ensemble --samples 20 " + plain));
    ASSERT_FALSE(x.is_null()) << form;
    x.erase("provenance");
    y.erase("provenance");
    EXPECT_EQ(x, y) << form;
  }
  expect_rejected(run("ensemble --wear-bins 2.5"), "wear-bins", "'2.5': not an integer");
  expect_rejected(run("ensemble --seed 1.5 --release-dist uniform"), "seed", "'1.5'");
}

}  // namespace
