// The designer's outputs from the command line: exit state, wear, release control, random
// ensembles and their validation.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cmath>
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
  expect_rejected(run("ensemble --wear-bins 2000000" + out), "wear-bins", "2000000");
  EXPECT_EQ(file_count(), 0u);
}

TEST_F(Cli, SweepsVaryTheReleaseLikeAnyParameter) {
  const Result r = run("sweep --release-height 0.5,1 --release-v 0,-1 --samples 20 --out " + path("s.csv"));
  ASSERT_EQ(r.code, 0) << r.output;
  const std::string csv = read("s.csv");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 5);
  EXPECT_NE(csv.find(",0.5,0,-1,0,line,20,"), std::string::npos) << csv;
}

}  // namespace
