// funnel under mpirun: the same bytes as one process for any number of ranks, resume across rank counts, faults.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <thread>

#include "cli_util.hpp"

namespace {

using namespace funnel_test;

/// The launcher prefix for `np` ranks on this one machine: oversubscribed (more ranks than
/// cores), allowed as root (containers), unbound (a rank may use every core), and shared-memory
/// transfers without the cross-memory attach that containers often forbid.
/// `exec` replaces the shell by the launcher, so that the pid is mpirun's.
std::string mpirun(int np, bool exec = false) {
  std::string cmd = "OMPI_MCA_btl_vader_single_copy_mechanism=none OMPI_MCA_rmaps_base_oversubscribe=1 ";
  cmd += (exec ? "exec " : "") + std::string(FUNNEL_MPIEXEC) + " --oversubscribe --bind-to none";
  if (geteuid() == 0) cmd += " --allow-run-as-root";
  return cmd + " -np " + std::to_string(np);
}

/// The text without the lines that may differ between runs (provenance: the command line).
std::string without_provenance(const std::string& text) {
  std::istringstream in(text);
  std::string out;
  for (std::string line; std::getline(in, line);) {
    if (line.find("\"command\"") == std::string::npos) out += line + "\n";
  }
  return out;
}

/// Starts `mpirun -np NP funnel ARGS` in the background, its stderr into `err`; returns mpirun's pid.
pid_t spawn_mpi(int np, const std::string& args, const std::string& err) {
  const pid_t pid = fork();
  if (pid == 0) {
    const std::string cmd = mpirun(np, true) + " " + FUNNEL_BINARY + " " + args + " > /dev/null 2> " + err;
    execl("/bin/sh", "sh", "-c", cmd.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  return pid;
}

/// The pid of rank `rank` among the children of mpirun `launcher` (0 if not found).
pid_t rank_pid(pid_t launcher, int rank) {
  const std::string want = "OMPI_COMM_WORLD_RANK=" + std::to_string(rank);
  for (const auto& task : fs::directory_iterator("/proc/" + std::to_string(launcher) + "/task")) {
    std::ifstream children(task.path() / "children");
    for (pid_t child; children >> child;) {
      std::ifstream env("/proc/" + std::to_string(child) + "/environ", std::ios::binary);
      for (std::string var; std::getline(env, var, '\0');) {
        if (var == want) return child;
      }
    }
  }
  return 0;
}

/// Complete data lines (after the spec and header lines) of a partial sweep file.
int partial_rows(const std::string& text) { return static_cast<int>(std::count(text.begin(), text.end(), '\n')) - 2; }

using Mpi = Cli;

TEST_F(Mpi, SweepEnsembleAndPaperGiveTheBytesOfOneProcessForAnyRanksAndThreads) {
  // Grid points dealt whole (many points) and ensembles dealt in chunks (one point): mirror
  // halving, per-sample outputs, random releases with a wear record. The sweep's mu descends, so
  // the order the points are dealt in (friction_order) is not the grid's.
  const std::string sweep = "sweep --theta 30:70:10 --mu 0.5,0 --samples 300 --out ";
  // (--max-collisions: a count of runs the cap ended, which the ranks' chunks carry too.)
  const std::string line = "ensemble --theta 47 --samples 1001 --per-sample --max-collisions 150 --out ";
  const std::string random =
      "ensemble --theta 55 --theta-right 65 --samples 2000 --release-dist uniform --velocity-sd 0.05 --seed 7 "
      "--wear-bins 5 --out ";  // asymmetric: each wall's own bin width crosses the ranks too
  const std::string paper = "paper --quick --only fig02,fig03,fig07 --no-plots --out ";
  ASSERT_EQ(run(sweep + path("one.csv") + " --threads 2").code, 0);
  ASSERT_EQ(run(line + path("one_line.json") + " --threads 2").code, 0);
  ASSERT_NE(read("one_line.json").find("\"capped\": "), std::string::npos);
  EXPECT_EQ(read("one_line.json").find("\"capped\": 0,"), std::string::npos);  // some runs capped
  ASSERT_EQ(run(random + path("one_random.csv") + " --format csv --threads 2").code, 0);
  ASSERT_EQ(run(paper + path("one_paper") + " --threads 2").code, 0);
  const std::string wear = read("one_random.csv");
  ASSERT_GT(std::count(wear.begin(), wear.end(), '\n'), 10);  // the wear table: one row per bin and wall
  for (const int np : {1, 2, 3}) {
    const std::string k = std::to_string(np);
    for (const int threads : {1, 2}) {
      const std::string t = " --threads " + std::to_string(threads);
      const Result r = run(sweep + path("mpi.csv") + t, mpirun(np));
      ASSERT_EQ(r.code, 0) << r.output;
      // Progress from the writing rank only: one summary line (stderr is not a terminal).
      const std::string summary = "points computed in";
      EXPECT_NE(r.output.find(summary), std::string::npos) << r.output;
      EXPECT_EQ(r.output.find(summary), r.output.rfind(summary)) << r.output;
      EXPECT_EQ(read("mpi.csv"), read("one.csv")) << np << " ranks, " << threads << " threads";
    }
    const Result l = run(line + path("mpi_line.json") + " --threads 1", mpirun(np));
    ASSERT_EQ(l.code, 0) << l.output;
    EXPECT_EQ(without_provenance(read("mpi_line.json")), without_provenance(read("one_line.json"))) << np;
    const Result u = run(random + path("mpi_random.csv") + " --format csv --threads 1", mpirun(np));
    ASSERT_EQ(u.code, 0) << u.output;
    EXPECT_EQ(read("mpi_random.csv"), read("one_random.csv")) << np;
    const Result p = run(paper + path("mpi_paper" + k) + " --threads 1", mpirun(np));
    ASSERT_EQ(p.code, 0) << p.output;
    for (const char* fig : {"fig02", "fig03", "fig07"}) {
      const std::string csv = std::string(fig) + "/" + fig + ".csv";
      EXPECT_EQ(read("mpi_paper" + k + "/" + csv), read("one_paper/" + csv)) << np << " " << fig;
    }
  }
}

TEST_F(Mpi, BadInputIsReportedOnceAndEveryRankExitsWithCode2) {
  // Each rank's exit code, printed by a shell around it.
  const std::string each = "sh -c '" + std::string(FUNNEL_BINARY) + " \"$@\"; echo rank exit $?' sh ";
  const std::string cmd = mpirun(3) + " " + each;
  for (const std::string& args : {"sweep --theta 95 --out " + path("x.csv"),            // every rank's input
                                  "ensemble --out " + path("missing/dir/e.json")}) {  // rank 0's file system
    Result r;
    FILE* pipe = popen((cmd + args + " 2>&1").c_str(), "r");
    ASSERT_NE(pipe, nullptr);
    char buf[4096];
    for (std::size_t n; (n = fread(buf, 1, sizeof buf, pipe)) > 0;) r.output.append(buf, n);
    pclose(pipe);
    std::size_t errors = 0, exits = 0;
    for (std::size_t at = 0; (at = r.output.find("funnel: error:", at)) != std::string::npos; ++at) ++errors;
    for (std::size_t at = 0; (at = r.output.find("rank exit 2", at)) != std::string::npos; ++at) ++exits;
    EXPECT_EQ(errors, 1u) << r.output;
    EXPECT_EQ(exits, 3u) << r.output;
  }
  const Result direct = run("sweep --theta 95 --out " + path("x.csv"), mpirun(2));
  EXPECT_EQ(direct.code, 2) << direct.output;
  EXPECT_NE(direct.output.find("invalid theta = 95"), std::string::npos) << direct.output;
  EXPECT_EQ(file_count(), 0u);
}

TEST_F(Mpi, SweepStoppedUnderThreeRanksOrByAKilledRankResumesUnderTwoAndAlone) {
  // Long enough (about 5 s on one core with the SIMD path, 15 s on the scalar one) that the stop
  // lands while points remain to be computed.
  const std::string grid = "sweep --theta 5:85:1 --samples 60000 --out ";
  ASSERT_EQ(run(grid + path("full.csv") + " --threads 2").code, 0);
  int rows = 0;
  // 1) The whole job stopped (SIGTERM to mpirun: Ctrl-C, a batch system's time limit) under 3
  //    ranks; 2) under 2 ranks, rank 1 killed (a node lost): the run stops with a message and a
  //    non-zero exit code, the finished points kept; 3) resumed by one process.
  for (const int np : {3, 2}) {
    const pid_t launcher = spawn_mpi(np, grid + path("cut.csv") + " --threads 1" + (np == 3 ? "" : " --resume"), path("err.txt"));
    bool stopped = false;
    for (int i = 0; i < 4000 && !stopped; ++i) {
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
      if (partial_rows(read("cut.csv.partial")) < rows + 3) continue;
      const pid_t target = np == 3 ? launcher : rank_pid(launcher, 1);
      stopped = target > 0 && kill(target, np == 3 ? SIGTERM : SIGKILL) == 0;
    }
    const int seen = partial_rows(read("cut.csv.partial"));
    int status = 0;
    waitpid(launcher, &status, 0);
    ASSERT_TRUE(stopped) << "the sweep ended before it could be stopped";
    EXPECT_FALSE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
    EXPECT_FALSE(fs::exists(path("cut.csv")));
    const std::string said = read("err.txt");
    // Open MPI may exit before it passes on rank 0's notice, whether mpirun was stopped or a rank
    // killed (seen with the machine loaded by other tests: err.txt empty, or only mpirun's own
    // lines; docs/cluster.md). When the notice arrived it must be whole and right; a killed rank
    // is named by mpirun itself. The partial file and the resume are checked always.
    if (said.find("funnel sweep: stopped") != std::string::npos) {
      EXPECT_NE(said.find("points are saved in '" + path("cut.csv.partial") + "'"), std::string::npos) << said;
      EXPECT_NE(said.find("any number of ranks"), std::string::npos) << said;
      EXPECT_NE(said.find("a rank of this MPI run died"), std::string::npos) << said;
    } else {
      std::cerr << "note: mpirun exited before passing on rank 0's notice:\n" << said << "\n";
    }
    if (np == 2) {
      EXPECT_TRUE(said.find("funnel sweep: stopped") != std::string::npos || said.find("signal 9") != std::string::npos)
          << said;
    }
    rows = partial_rows(read("cut.csv.partial"));
    EXPECT_GE(rows, seen);
    EXPECT_LT(rows, 81);
  }
  const Result r = run(grid + path("cut.csv") + " --resume");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("resuming: " + std::to_string(rows) + " of 81"), std::string::npos) << r.output;
  EXPECT_EQ(read("cut.csv"), read("full.csv"));
}

}  // namespace
