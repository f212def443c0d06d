// The command line as a user meets it: bad input exits 2 naming the parameter, and writes nothing.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>
#include <thread>

#include <nlohmann/json.hpp>

#include "cli_util.hpp"

namespace {

using namespace funnel_test;
using nlohmann::json;

TEST_F(Cli, OutOfRangeNanInfAndNonNumbersNameTheParameterValueAndRange) {
  const std::string base = "trajectory --release 0.3 --out " + path("t.json") + " ";
  const Result theta = run(base + "--theta 95");
  expect_rejected(theta, "theta", "95");
  EXPECT_NE(theta.output.find("0 < theta < 90"), std::string::npos);
  expect_rejected(run(base + "--e nan"), "e", "nan");
  expect_rejected(run(base + "--mu inf"), "mu", "inf");
  expect_rejected(run(base + "--gap abc"), "gap", "abc");
  expect_rejected(run(base + "--gap 0.015"), "gap", "0.015");
  expect_rejected(run(base + "--beta0 -2"), "beta0", "-2");
  expect_rejected(run(base + "--inertia 0"), "inertia", "0");
  expect_rejected(run(base + "--max-collisions 2.5"), "max-collisions", "2.5");
  expect_rejected(run("trajectory --release 1.5 --out " + path("t.json")), "release", "1.5");
  expect_rejected(run("ensemble --samples 0 --out " + path("t.json")), "samples", "0");
  expect_rejected(run("ensemble --release-dist cube --out " + path("t.json")), "release-dist", "cube");
  expect_rejected(run("ensemble --threads -3 --out " + path("t.json")), "threads", "-3");
  EXPECT_EQ(file_count(), 0u);
}

TEST_F(Cli, EmptyFileAndListValuesAreRefusedNotTakenAsAbsent) {
  // `--out ""` wrote to standard output, `--geometry ""` ran the V, `--only ""` made every figure:
  // each read an empty value as an option not given.
  const std::string dir = " --out " + path("d");
  for (const auto& [command, name] : std::vector<std::pair<std::string, std::string>>{
           {"trajectory --release 0.3 --out ''", "out"},
           {"ensemble --samples 10 --out ''", "out"},
           {"sweep --samples 10 --theta 40 --out ''", "out"},
           {"orbit --theta 60 --out ''", "out"},
           {"trajectory --release 0.3 --geometry '' --out " + path("t.json"), "geometry"},
           {"sweep --samples 10 --theta 40 --config '' --out " + path("s.csv"), "config"},
           {"paper --quick --no-plots --only ''" + dir, "only"},
           {"paper --quick --no-plots --paper-dir ''" + dir, "paper-dir"},
           {"paper --quick --no-plots --out ''", "out"}}) {
    const Result r = run(command);
    EXPECT_EQ(r.code, 2) << command << "\n" << r.output;
    EXPECT_NE(r.output.find("invalid " + name + " = ''"), std::string::npos) << command << "\n" << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << command << "\n" << r.output.substr(0, 300);
  }
  EXPECT_EQ(file_count(), 0u);
}

TEST_F(Cli, AFileNameWithoutRoomForItsTemporaryFileIsRefusedBeforeAnyWork) {
  // 255 characters is the usual limit of a name; the temporary file adds 11 (".tmp.XXXXXX") and
  // a sweep's partial file 8 more. Such names ran the whole computation, then failed (exit 1).
  const std::string long_name(250, 'a'), sweep_name(240, 'b');
  Result r = run("ensemble --samples 3000000 --threads 1 --out " + path(long_name));
  expect_rejected(r, "out", "a file name of 250 characters");
  EXPECT_NE(r.output.find("at most 244 characters"), std::string::npos) << r.output;
  r = run("sweep --samples 10 --theta 40 --out " + path(sweep_name));
  expect_rejected(r, "out", "a file name of 240 characters");
  EXPECT_NE(r.output.find("at most 236 characters"), std::string::npos) << r.output;
  EXPECT_EQ(file_count(), 0u);
  // A name with room for its temporary file is written as usual.
  ASSERT_EQ(run("ensemble --samples 10 --out " + path(sweep_name)).code, 0);
  EXPECT_EQ(file_count(), 1u);
}

TEST_F(Cli, UnknownOptionIsRejected) {
  const Result r = run("ensemble --bogus 3 --out " + path("e.json"));
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("--bogus"), std::string::npos) << r.output;
  EXPECT_EQ(file_count(), 0u);
}

TEST_F(Cli, MalformedRangesAndBadConfigsLeaveExistingFilesUntouched) {
  write("keep.csv", "precious\n");
  const std::string out = " --out " + path("keep.csv");
  expect_rejected(run("sweep --theta 5:85" + out), "theta", "5:85");
  expect_rejected(run("sweep --theta 85:5:1" + out), "theta", "85:5:1");
  expect_rejected(run("sweep --mu 0,x,1" + out), "mu", "0,x,1");
  expect_rejected(run("sweep --theta 10:100:10" + out), "theta", "90");  // the first value out of range
  expect_rejected(run("sweep --config " + path("missing.toml") + out), "config", "missing.toml");
  write("bad.toml", "theta = [40, 95]\n");
  expect_rejected(run("sweep --config " + path("bad.toml") + out), "theta", "95");
  write("syntax.toml", "theta = [40, \n");
  expect_rejected(run("sweep --config " + path("syntax.toml") + out), "config", "syntax.toml");
  write("key.toml", "thetta = 40\n");
  expect_rejected(run("sweep --config " + path("key.toml") + out), "thetta", "key.toml");
  EXPECT_EQ(read("keep.csv"), "precious\n");
  EXPECT_EQ(file_count(), 4u);  // keep.csv and the three configs: no temporary file left behind
}

TEST_F(Cli, HelpDocumentsEveryModelOptionWithItsRange) {
  const Result r = run("ensemble --help");
  EXPECT_EQ(r.code, 0);
  for (const char* opt : {"--theta", "--e", "--mu", "--beta0", "--radius", "--gap", "--inertia", "--t-max",
                          "--max-collisions", "--samples", "--release-dist", "--threads"}) {
    EXPECT_NE(r.output.find(opt), std::string::npos) << opt;
  }
  EXPECT_NE(r.output.find("-1 <= beta0 <= 1"), std::string::npos);
}

TEST_F(Cli, TrajectoryJsonHasTheDocumentedKeys) {
  const Result r = run("trajectory --theta 50 --e 0.9 --release -0.4 --events --out " + path("t.json"));
  ASSERT_EQ(r.code, 0) << r.output;
  const std::string json = read("t.json");
  for (const char* key : {"\"params\"", "\"status\"", "\"duration\"", "\"impulse\"", "\"normal_impulse\"",
                          "\"energy_loss\"", "\"collisions\"", "\"edge_collisions\"", "\"contact_time\"",
                          "\"events\"", "\"exited\"", "\"git_commit\""}) {
    EXPECT_NE(json.find(key), std::string::npos) << key;
  }
}

TEST_F(Cli, SweepWritesOneRowPerGridPointAndConfigAndOptionsCombine) {
  write("grid.toml", "theta = \"40:60:10\"\nmu = [0, 1]\nsamples = 50\n");
  const Result r = run("sweep --config " + path("grid.toml") + " --e 0.9 --threads 2 --out " + path("s.csv"));
  ASSERT_EQ(r.code, 0) << r.output;
  const std::string csv = read("s.csv");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 7);  // header + 3 x 2 points
  EXPECT_EQ(csv.rfind("theta,e,mu,beta0,radius,gap,inertia,t_max,max_collisions,release_height,release_u,release_v,release_spin,theta_left,theta_right,spout_length,release_dist,samples,duration_mean", 0), 0u);
  EXPECT_NE(csv.find("\n60,0.9,1,0,0.01,0.04,0.4,1e+05,100000000,1,0,0,0,60,60,0,line,50,"), std::string::npos) << csv;
}

TEST_F(Cli, EnsembleCsvAndJsonAgree) {
  ASSERT_EQ(run("ensemble --samples 40 --theta 55 --out " + path("e.json")).code, 0);
  ASSERT_EQ(run("ensemble --samples 40 --theta 55 --format csv --out " + path("e.csv")).code, 0);
  const std::string json = read("e.json");
  const std::string csv = read("e.csv");
  const auto pos = json.find("\"duration\"");
  ASSERT_NE(pos, std::string::npos);
  const auto mean_pos = json.find("\"mean\": ", pos) + 8;
  const std::string mean = json.substr(mean_pos, json.find(',', mean_pos) - mean_pos);
  EXPECT_NE(csv.find("," + mean + ","), std::string::npos) << mean << "\n" << csv;
}

TEST_F(Cli, OrbitReportsEigenvaluesStabilityAndJacobianAgreement) {
  const Result r = run("orbit --theta 44,46 --beta0 0.31 --format csv --out " + path("o.csv"));
  ASSERT_EQ(r.code, 0) << r.output;
  const std::string csv = read("o.csv");
  EXPECT_EQ(csv.rfind("theta,beta0,inertia,radius,re1,im1,mod1", 0), 0u);
  // 44 degrees: unstable (stable = 0); 46 degrees: stable (1).
  const auto at44 = csv.find("\n44,0.31,0.4,0.01,");
  const auto at46 = csv.find("\n46,0.31,0.4,0.01,");
  ASSERT_NE(at44, std::string::npos) << csv;
  ASSERT_NE(at46, std::string::npos) << csv;
  // The columns by name: "stable" and "jacobian_max_rel_diff" (printed vs finite-difference Jacobian).
  auto fields = [](const std::string& line) {
    std::vector<std::string> out;
    std::stringstream in(line);
    for (std::string f; std::getline(in, f, ',');) out.push_back(f);
    return out;
  };
  const std::vector<std::string> header = fields(csv.substr(0, csv.find('\n')));
  const auto column = [&](const char* name) {
    return static_cast<std::size_t>(std::find(header.begin(), header.end(), name) - header.begin());
  };
  const std::vector<std::string> row44 = fields(csv.substr(at44 + 1, at46 - at44 - 1));
  const std::vector<std::string> row46 = fields(csv.substr(at46 + 1, csv.find('\n', at46 + 1) - at46 - 1));
  ASSERT_LT(column("jacobian_max_rel_diff"), row44.size());
  EXPECT_EQ(row44[column("stable")], "0");
  EXPECT_EQ(row46[column("stable")], "1");
  for (const auto* row : {&row44, &row46}) EXPECT_LT(std::stod((*row)[column("jacobian_max_rel_diff")]), 1e-8);
  ASSERT_EQ(run("orbit --theta 60 --out " + path("o.json")).code, 0);
  for (const char* key : {"\"eigenvalues\"", "\"real\"", "\"imag\"", "\"modulus\"", "\"stable\"",
                          "\"jacobian_max_rel_diff\""}) {
    EXPECT_NE(read("o.json").find(key), std::string::npos) << key;
  }
  expect_rejected(run("orbit --theta 60 --e 0.5 --out " + path("x.json")), "--e = '0.5'", "orbit");
  expect_rejected(run("orbit --theta 60 --y-star -1 --out " + path("x.json")), "y-star", "-1");
  // The orbit does not depend on the funnel's gap: a radius above half the default gap (0.04) is
  // the orbit theory's like any other (it was refused, naming the gap the command does not take).
  const Result wide = run("orbit --theta 60 --radius 0.02,0.5 --format csv --out " + path("w.csv"));
  ASSERT_EQ(wide.code, 0) << wide.output;
  EXPECT_NE(read("w.csv").find("\n60,0,0.4,0.5,"), std::string::npos) << read("w.csv");
  expect_rejected(run("orbit --theta 60 --radius 1 --out " + path("x.json")), "radius", "1");
  expect_rejected(run("orbit --theta 90 --out " + path("x.json")), "theta", "90");
  // Below 1e-3 degrees its eigenvalues are not resolved (1e-8 came out "stable"): refused.
  expect_rejected(run("orbit --theta 1e-8,60 --out " + path("x.json")), "theta = 1e-08",
                  "1e-3 <= theta < 90 (degrees) for the orbit");
  ASSERT_EQ(run("orbit --theta 1e-3 --out " + path("small.json")).code, 0);
  EXPECT_EQ(json::parse(read("small.json"))["points"][0]["stable"], false);
}

TEST_F(Cli, ClosedReportsThePeriodicFraction) {
  const Result r = run("closed --theta 70 --e 1 --mu 1 --samples 50 --out " + path("c.json"));
  ASSERT_EQ(r.code, 0) << r.output;
  const std::string json = read("c.json");
  EXPECT_NE(json.find("\"periodic_fraction\": 1.0"), std::string::npos) << json.substr(0, 600);
  EXPECT_NE(json.find("\"x_last_over_L\""), std::string::npos);
  expect_rejected(run("closed --gap 0.04 --out " + path("x.json")), "gap", "0.04");
  expect_rejected(run("closed --t-max 0 --out " + path("x.json")), "t-max", "0");
  // A collision that never happened has no position: an empty field, not the vertex's 0.
  const Result one = run("closed --theta 50 --samples 2 --max-collisions 1 --format csv");
  ASSERT_EQ(one.code, 0) << one.output;
  EXPECT_NE(one.output.find("\n-0.5,undecided,-0.5"), std::string::npos) << one.output;
  EXPECT_NE(one.output.find(",,0.49222138086569"), std::string::npos) << one.output;
  EXPECT_NE(one.output.find(",,1,0.99219"), std::string::npos) << one.output;
  const Result none = run("closed --theta 50 --samples 2 --t-max 0.01 --format csv");
  EXPECT_NE(none.output.find("\n-0.5,undecided,,,,,0,0.01\n"), std::string::npos) << none.output;
}

TEST_F(Cli, PaperRunsTheFrictionlessCurveOnceForEveryBeta0) {
  // Fig. 3's quick grid: 81 angles x 6 mu x 3 beta0, the mu = 0 curve shared by the three panels
  // (beta0 changes no bit without friction; Ensemble.FrictionlessEnsemblesDoNotDependOnBeta0).
  const Result r = run("paper --quick --no-plots --only fig03 --out " + path("p"));
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find(" " + std::to_string(81 * (6 * 3 - 2)) + " ensembles of θ sweeps"), std::string::npos) << r.output;
  // Its rows, beta0 and the panel apart, are the same in the three panels.
  std::map<std::string, std::set<std::string>> rows;  // theta -> the mu = 0 rows without panel, beta0
  std::istringstream csv(read("p/fig03/fig03.csv"));
  std::string line;
  std::getline(csv, line);
  while (std::getline(csv, line)) {
    std::vector<std::string> f;
    std::stringstream ss(line);
    for (std::string x; std::getline(ss, x, ',');) f.push_back(x);
    ASSERT_GT(f.size(), 5u);
    if (f[3] != "0") continue;
    std::string rest;
    for (std::size_t i = 0; i < f.size(); ++i) rest += i == 0 || i == 4 ? std::string(",") : f[i] + ",";
    rows[f[1]].insert(rest);
  }
  EXPECT_EQ(rows.size(), 81u);
  for (const auto& [theta, variants] : rows) EXPECT_EQ(variants.size(), 1u) << theta;
}

TEST_F(Cli, PaperQuickWritesEveryFigureAndEveryClaimHolds) {
  const Result r = run("paper --quick --no-plots --out " + path("paper"));
  ASSERT_EQ(r.code, 0) << r.output;
  const std::pair<const char*, const char*> figures[] = {
      {"fig02", "panel,theta,e,mu,beta0,radius,gap,inertia,t_max,max_collisions,release_height,release_u,release_v,release_spin,theta_left,theta_right,spout_length,release_dist,samples,duration_mean"},
      {"fig03", "panel,theta,e,mu,beta0"},
      {"fig04", "panel,theta,e,mu,beta0"},
      {"fig05", "panel,theta,e,mu,beta0"},
      {"fig06", "panel,theta,e,mu,beta0"},
      {"fig07", "panel,theta,release,duration,status,collisions\n"},
      {"fig08", "panel,theta,time,kind,wall,x,y,u_before,v_before,omega_before,u_after,v_after,omega_after"},
      {"fig10", "theta,mod1,mod2,mod3,mod4,stable\n"},
      {"fig11", "panel,mu,release,state,x_last_over_L,x_prev_over_L\n"},
      {"fig12", "theta,mu,periodic_fraction\n"},
      {"fig13", "panel,theta,e,mu,beta0"},
      {"fig01", "name,x,y\n"},
      {"fig02x", "theta,duration_mean,duration_sem,baseline,elevated,covered\n"},
      {"fig09", "panel,theta,time,kind,wall,x,y,u_before,v_before,omega_before,u_after,v_after,omega_after"},
      {"fig14", "panel,theta,time,kind,wall,x,y,u_before,v_before,omega_before,u_after,v_after,omega_after"}};
  for (const auto& [fig, header] : figures) {
    const std::string dir = std::string("paper/") + fig + "/" + fig;
    const std::string csv = read(dir + ".csv");
    const std::string json = read(dir + ".json");
    EXPECT_EQ(csv.rfind(header, 0), 0u) << fig << ": " << csv.substr(0, 200);
    EXPECT_GT(std::count(csv.begin(), csv.end(), '\n'), 10) << fig;
    EXPECT_NE(json.find("\"holds\": true"), std::string::npos) << fig << ": " << json.substr(json.find("\"check\""), 400);
    EXPECT_NE(json.find("\"git_commit\""), std::string::npos) << fig;
  }
  // The summary table names every figure with its verdict.
  EXPECT_EQ(r.output.find(" NO "), std::string::npos) << r.output;
  expect_rejected(run("paper --quick --only fig99 --out " + path("p2")), "only", "fig99");
  // A file where a figure's directory goes is said before any work (it was an internal error,
  // exit 1, once the θ sweeps had run), and nothing is written.
  fs::create_directories(path("p3"));
  write("p3/fig03", "not a directory\n");
  const Result blocked = run("paper --quick --no-plots --only fig01,fig03 --out " + path("p3"));
  expect_rejected(blocked, "out", "fig03");
  EXPECT_NE(blocked.output.find("in the way"), std::string::npos) << blocked.output;
  EXPECT_EQ(blocked.output.find("θ sweeps"), std::string::npos) << blocked.output;
  EXPECT_FALSE(fs::exists(path("p3/fig01/fig01.csv")));
}

/// Starts `funnel ARGS` in the background, its stderr into `err`; returns its pid.
pid_t spawn(const std::string& args, const std::string& err = "/dev/null") {
  const pid_t pid = fork();
  if (pid == 0) {
    const std::string cmd = "exec " + std::string(FUNNEL_BINARY) + " " + args + " > /dev/null 2> " + err;
    execl("/bin/sh", "sh", "-c", cmd.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  return pid;
}

/// Complete data lines (after the spec and header lines) of a partial sweep file.
int partial_rows(const std::string& text) {
  int lines = static_cast<int>(std::count(text.begin(), text.end(), '\n'));
  return lines - 2;
}

TEST_F(Cli, InterruptedSweepResumesToTheIdenticalResult) {
  // About 1.5 s on 2 cores (the SIMD path): long enough to interrupt it after a few points.
  const std::string grid = "sweep --theta 5:85:1 --samples 20000 --threads 2 --out ";
  ASSERT_EQ(run(grid + path("full.csv")).code, 0);
  // Interrupt twice (Ctrl-C, then kill -9) once a few points are in, then resume to the end.
  int resumed_from = 0;
  for (const int sig : {SIGINT, SIGKILL}) {
    const pid_t pid = spawn(grid + path("cut.csv") + (sig == SIGKILL ? " --resume" : ""), path("stderr.txt"));
    bool killed = false;
    for (int i = 0; i < 2000 && !killed; ++i) {
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
      if (partial_rows(read("cut.csv.partial")) >= resumed_from + 3) killed = kill(pid, sig) == 0;
    }
    int status = 0;
    waitpid(pid, &status, 0);
    ASSERT_TRUE(killed) << "the sweep ended before it could be interrupted";
    EXPECT_TRUE(WIFSIGNALED(status));
    EXPECT_FALSE(fs::exists(path("cut.csv")));  // no final file from an interrupted run
    const std::string partial = read("cut.csv.partial");
    EXPECT_EQ(partial.rfind("# funnel sweep spec: ", 0), 0u);
    EXPECT_GE(partial_rows(partial), resumed_from + 3);
    resumed_from = partial_rows(partial);
    if (sig == SIGINT) {
      // Ctrl-C says where the finished points are and how to continue.
      const std::string said = read("stderr.txt");
      EXPECT_NE(said.find("interrupted"), std::string::npos) << said;
      EXPECT_NE(said.find(path("cut.csv.partial")), std::string::npos) << said;
      EXPECT_NE(said.find(path("cut.csv") + " --resume"), std::string::npos) << said;
      // The same sweep again without --resume does not silently throw those points away.
      const Result again = run(grid + path("cut.csv"));
      EXPECT_EQ(again.code, 2) << again.output;
      EXPECT_NE(again.output.find("--resume"), std::string::npos) << again.output;
      EXPECT_NE(again.output.find("--overwrite"), std::string::npos) << again.output;
      EXPECT_EQ(read("cut.csv.partial"), partial);
    }
  }
  const Result r = run(grid + path("cut.csv") + " --resume");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("resuming"), std::string::npos) << r.output;
  EXPECT_EQ(read("cut.csv"), read("full.csv"));
  EXPECT_FALSE(fs::exists(path("cut.csv.partial")));
  EXPECT_NE(read("cut.csv.json").find("\"resumed_points\""), std::string::npos);
  // A partial file of another sweep is refused, not mixed in; --overwrite discards it.
  write("other.csv.partial", "# funnel sweep spec: {}\npoint,theta\n0,40\n");
  const std::string other = "sweep --theta 40 --samples 10 --out " + path("other.csv");
  expect_rejected(run(other + " --resume"), "resume", "different sweep");
  expect_rejected(run(other + " --resume --overwrite"), "--resume and --overwrite", "exclude");
  ASSERT_EQ(run(other + " --overwrite").code, 0);
  const std::string csv = read("other.csv");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 2);
  EXPECT_FALSE(fs::exists(path("other.csv.partial")));
}

TEST_F(Cli, ResumeRecomputesPartialRowsThatAreNotTheGridsOwn) {
  // A partial file of the same sweep whose rows were edited or damaged: a row with another
  // theta, one with a word among its statistics, one with a column missing. Each such point is
  // computed again, so the result is the uninterrupted sweep's, byte for byte.
  const std::string grid = "sweep --theta 40:44:1 --samples 200 --threads 1 --out ";
  ASSERT_EQ(run(grid + path("full.csv")).code, 0);
  const std::string spec = nlohmann::ordered_json::parse(read("full.csv.json"))["spec"].dump();
  std::vector<std::string> rows;
  std::stringstream in(read("full.csv"));
  std::string header;
  std::getline(in, header);
  for (std::string line; std::getline(in, line);) rows.push_back(line);
  ASSERT_EQ(rows.size(), 5u);
  std::string partial = partial_start(spec, header);
  partial += "0,0,0,99" + rows[0].substr(rows[0].find(',')) + "\n";             // another theta
  partial += "1,0,0," + rows[1].substr(0, rows[1].rfind(',')) + ",oops\n";      // a word
  partial += "2,0,0," + rows[2].substr(0, rows[2].rfind(',')) + "\n";           // a column short
  partial += "3,0,0," + rows[3] + "\n";                                         // intact
  partial += "4,0,0," + rows[4].substr(0, rows[4].rfind(',')) + ",nan\n";      // nan: the sweep writes none
  write("cut.csv.partial", partial);
  const Result r = run(grid + path("cut.csv") + " --resume");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("4 rows of"), std::string::npos) << r.output;
  EXPECT_EQ(read("cut.csv"), read("full.csv"));
  EXPECT_EQ(json::parse(read("cut.csv.json"))["resumed_points"], 1);
}

TEST_F(Cli, ResumeKeepsRowsWithUndefinedStatistics) {
  // In a closed funnel nothing exits: the exit statistics are empty fields. Such rows are the
  // sweep's own and must be kept (they were dropped and recomputed as "not the grid's").
  const std::string grid = "sweep --gap 0 --e 0.9 --theta 40:44:1 --samples 50 --threads 1 --out ";
  ASSERT_EQ(run(grid + path("full.csv")).code, 0);
  EXPECT_NE(read("full.csv").find(",,"), std::string::npos);  // the case: undefined statistics
  const std::string spec = nlohmann::ordered_json::parse(read("full.csv.json"))["spec"].dump();
  std::stringstream in(read("full.csv"));
  std::string header, partial;
  std::getline(in, header);
  partial = partial_start(spec, header);
  int i = 0;
  for (std::string line; std::getline(in, line) && i < 3; ++i) partial += std::to_string(i) + ",0,0," + line + "\n";
  write("cut.csv.partial", partial);
  const Result r = run(grid + path("cut.csv") + " --resume");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_EQ(r.output.find("did not match"), std::string::npos) << r.output;
  EXPECT_EQ(json::parse(read("cut.csv.json"))["resumed_points"], 3);
  EXPECT_EQ(read("cut.csv"), read("full.csv"));
}

TEST_F(Cli, RetraceListsOrbitsAndWindowsAndRejectsAnotherMaterial) {
  ASSERT_EQ(run("retrace --theta 60,61 --format csv --out " + path("r.csv")).code, 0);
  const std::string csv = read("r.csv");
  EXPECT_EQ(csv.rfind("theta,release,sequence,turn,bounces,collisions_per_period,period,trace,stable,y0,turn_x,"
                      "min_height,residual,return_position_error,return_speed\n", 0), 0u) << csv.substr(0, 300);
  EXPECT_NE(csv.find(",LRLR,wall,4,7,"), std::string::npos) << csv;  // the 60-degree orbit of Fig. 2's peak
  EXPECT_NE(csv.find(",RLRL,wall,4,7,"), std::string::npos) << csv;  // and its mirror image
  ASSERT_EQ(run("retrace --theta 59:62:0.5 --turns wall,rest --format csv --windows --out " + path("w.csv")).code, 0);
  const std::string w = read("w.csv");
  EXPECT_EQ(w.rfind("sequence,turn,bounces,window,theta_from,theta_to,points\n", 0), 0u) << w;
  EXPECT_NE(w.find("LRLR,rest,4,stable,59.5,"), std::string::npos) << w;
  const std::size_t files = file_count();
  const std::string out = " --out " + path("x.json");
  expect_rejected(run("retrace --e 0.99" + out), "e", "0.99");
  expect_rejected(run("retrace --mu 1" + out), "mu", "1");
  expect_rejected(run("retrace --theta 95" + out), "theta", "95");
  expect_rejected(run("retrace --gap 0.01" + out), "gap", "0.01");
  expect_rejected(run("retrace --max-bounces 0" + out), "max-bounces", "0");
  expect_rejected(run("retrace --scan-points 2.5" + out), "scan-points", "2.5");
  expect_rejected(run("retrace --turns sideways" + out), "turns", "sideways");
  expect_rejected(run("retrace --windows" + out), "windows", "csv");
  // A grid of millions of angles is refused at once (it ran for hours without a word).
  expect_rejected(run("retrace --theta 1:89:0.0000089 --max-bounces 1" + out), "grid", "at most 100000 points");
  EXPECT_EQ(file_count(), files);  // nothing written
  // Its progress is drawn on request (as on a terminal) and ends at 100%.
  const Result shown = run("retrace --theta 40:50:1 --out " + path("p.json"), "FUNNEL_PROGRESS=always");
  ASSERT_EQ(shown.code, 0) << shown.output;
  EXPECT_NE(shown.output.find("funnel retrace ["), std::string::npos) << shown.output;
  EXPECT_NE(shown.output.find("100%"), std::string::npos) << shown.output;
}

TEST_F(Cli, PaperRetraceChecksCanFail) {
  // With at most one collision before the turn there is no self-retracing orbit (a fall from rest
  // never meets a wall head-on): no peak of Fig. 2 can be explained, and the check must say so.
  fs::create_directories(path("defs"));
  std::string fig = read_source(FUNNEL_SOURCE_DIR "/paper/fig02x.toml");
  const auto at = fig.find("max_bounces = 6\n");
  ASSERT_NE(at, std::string::npos);
  fig.replace(at, 16, "max_bounces = 1\n");
  write("defs/fig02x.toml", fig);
  const Result r = run("paper --quick --no-plots --paper-dir " + path("defs") + " --out " + path("p"));
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(read("p/fig02x/fig02x.json").find("\"holds\": false"), std::string::npos);
}

TEST_F(Cli, PaperRefusesFigureDefinitionsOutOfRangeBeforeAnyWork) {
  // A definition read through --paper-dir is input like any other: it ran at theta = 95, e = 7 or
  // mu = nan without a word, and an unknown kind failed only after other figures were written.
  const std::string fig12 = read_source(FUNNEL_SOURCE_DIR "/paper/fig12.toml");
  const std::string fig10 = read_source(FUNNEL_SOURCE_DIR "/paper/fig10.toml");
  const auto edited = [](std::string text, const std::string& from, const std::string& to) {
    const auto at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) text.replace(at, from.size(), to);
    return text;
  };
  const std::vector<std::pair<std::string, std::string>> cases{
      {edited(fig12, "thetas = [50, 60, 70]", "thetas = [50, 60, 95]"), "thetas: invalid theta = 95"},
      {edited(fig12, "e = 1\n", "e = 7\n"), "invalid e = 7"},
      {edited(fig12, "mus = [0.001,", "mus = [nan,"), "mus: invalid mu = nan"},
      {edited(fig12, "samples = 4000", "samples = -5"), "invalid samples = -5: valid range is an integer"},
      {edited(fig12, "kind = \"periodic_fraction\"", "kind = \"bogus\""), "invalid kind = 'bogus': valid kinds are"},
      {edited(fig12, "samples = 4000", "samples = 4000\nbogus_key = 3"), "unknown key 'bogus_key'"},
      {fig12 + "\n[settings]\nbins = 0\n", "invalid settings.bins = 0: valid range is an integer 1 <= bins <= 10^4"},
      {fig12 + "\n[settings]\nbins = 1e5\n", "invalid settings.bins = 1e+05: valid range is an integer 1 <= bins <= 10^4"},
      {fig12 + "\n[settings]\ntheta = \"30:95:1\"\n", "invalid settings.theta = 90: valid range is 0 < theta < 90"},
      {fig12 + "\n[settings]\nscan_gap = 0.001\n", "settings.scan_gap: invalid gap = 0.001"},
      {fig12 + "\n[settings]\nturns = \"walls\"\n", "invalid turns = 'walls'"},
      {fig12 + "\n[settings]\nbogus = 1\n", "unknown setting 'bogus'"},
      {edited(fig12, "[check]\n", "[check]\ntolerance = \"x\"\n"), "[check] tolerance must be a finite number"},
      {edited(fig12, "[check]\n", "[check]\nmin_ratoi = 2\n"), "unknown [check] key 'min_ratoi'; valid keys are"}};
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const std::string dir = path("defs" + std::to_string(i));
    fs::create_directories(dir);
    write("defs" + std::to_string(i) + "/fig10.toml", fig10);  // a good figure first: nothing of it written either
    write("defs" + std::to_string(i) + "/fig12.toml", cases[i].first);
    const Result r = run("paper --quick --no-plots --paper-dir " + dir + " --out " + path("out" + std::to_string(i)));
    EXPECT_EQ(r.code, 2) << cases[i].second << "\n" << r.output;
    EXPECT_NE(r.output.find(cases[i].second), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("fig12.toml"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(path("out" + std::to_string(i)))) << cases[i].second;
  }
  // As on the command line: disk releases in an asymmetric V (they skip its left half), and theta
  // with both walls' angles (equal rows labelled apart).
  const std::string fig13 = read_source(FUNNEL_SOURCE_DIR "/paper/fig13.toml");
  const std::vector<std::pair<std::string, std::string>> releases{
      {edited(fig13, "[params]\n", "[params]\ntheta_right = 50\n"),
       "invalid release-dist = disk: valid range is line, uniform or gaussian in a funnel that is not mirror symmetric"},
      {edited(fig13, "[params]\n", "[params]\ntheta_right = 50\ntheta_left = 40\n"),
       "invalid theta: valid range is not with both theta-left and theta-right"}};
  for (std::size_t i = 0; i < releases.size(); ++i) {
    const std::string dir = "rdefs" + std::to_string(i);
    fs::create_directories(path(dir));
    write(dir + "/fig13.toml", releases[i].first);
    const Result r = run("paper --quick --no-plots --only fig13 --paper-dir " + path(dir) + " --out " + path(dir + "_out"));
    EXPECT_EQ(r.code, 2) << r.output;
    EXPECT_NE(r.output.find(releases[i].second), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(path(dir + "_out")));
  }
  // A panel whose right wall follows theta by an offset leaves out the angles it tips past
  // vertical, as the sweep does: they are not refused (every definition is checked at its full
  // grid even when another figure is made).
  fs::create_directories(path("shape"));
  write("shape/figshape.toml", edited(read_source(FUNNEL_SOURCE_DIR "/paper/figshape.toml"), "theta = \"5:79:1\"",
                                      "theta = \"5:85:1\""));
  write("shape/fig01.toml", read_source(FUNNEL_SOURCE_DIR "/paper/fig01.toml"));
  const Result shape = run("paper --no-plots --only fig01 --paper-dir " + path("shape") + " --out " + path("shape_out"));
  EXPECT_EQ(shape.code, 0) << shape.output;
}

TEST_F(Cli, PaperChecksCanFail) {
  // Fig. 2's check (narrow peaks only) applied to a frictional particle, where almost every
  // angle above 45 degrees holds the particle longer than 44 degrees: it must say so.
  fs::create_directories(path("defs"));
  std::string fig = read_source(FUNNEL_SOURCE_DIR "/paper/fig02.toml");
  const auto at = fig.find("mu = 0\n");
  ASSERT_NE(at, std::string::npos);
  fig.replace(at, 7, "mu = 1\n");
  write("defs/fig02.toml", fig);
  const Result r = run("paper --quick --no-plots --paper-dir " + path("defs") + " --out " + path("p"));
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(read("p/fig02/fig02.json").find("\"holds\": false"), std::string::npos);
}

}  // namespace
