// What a newcomer meets: --out never destroys what is not a regular file, typos get the nearest
// name, configs say how to write them, big sweeps ask first, long stages show their progress.
#include <gtest/gtest.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <future>
#include <string>

#include "cli_util.hpp"

namespace {

using namespace funnel_test;

/// Reads a FIFO to its end on a thread, as `cat fifo` would. If no writer ever comes (a broken
/// funnel replaced the FIFO instead of writing to it), the reader is released through a second
/// name of the FIFO made for that purpose, so that the test fails instead of hanging.
class FifoReader {
 public:
  FifoReader(std::string path, std::string spare_name)
      : spare_(std::move(spare_name)), reader_(std::async(std::launch::async, [path] {
          std::ifstream in(path, std::ios::binary);
          std::stringstream s;
          s << in.rdbuf();
          return s.str();
        })) {}
  std::string text() {
    if (reader_.wait_for(std::chrono::seconds(10)) != std::future_status::ready) {
      const int fd = open(spare_.c_str(), O_WRONLY | O_NONBLOCK);
      if (fd >= 0) close(fd);
    }
    return reader_.get();
  }

 private:
  std::string spare_;
  std::future<std::string> reader_;
};

bool is_fifo(const std::string& p) { return fs::is_fifo(fs::symlink_status(p)); }
bool is_char_device(const std::string& p) { return fs::is_character_file(fs::symlink_status(p)); }

TEST_F(Cli, OutWritesThroughAFifoAndThroughALinkToOne) {
  ASSERT_EQ(mkfifo(path("fifo").c_str(), 0644), 0) << std::strerror(errno);
  fs::create_hard_link(path("fifo"), path("spare"));
  fs::create_symlink("fifo", path("link"));
  for (const char* out : {"fifo", "link"}) {
    FifoReader reader(path("fifo"), path("spare"));
    const Result r = run("trajectory --release 0.3 --out " + path(out));
    const std::string text = reader.text();
    EXPECT_EQ(r.code, 0) << r.output;
    EXPECT_NE(text.find("\"duration\""), std::string::npos) << out << ": " << text;
    EXPECT_TRUE(is_fifo(path("fifo"))) << out;
  }
  EXPECT_TRUE(fs::is_symlink(path("link")));
  // A sweep writes its CSV through too, and puts no partial or provenance file beside a FIFO.
  FifoReader reader(path("fifo"), path("spare"));
  const Result r = run("sweep --theta 40,50 --samples 10 --out " + path("fifo"));
  const std::string csv = reader.text();
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 3) << csv;
  EXPECT_EQ(file_count(), 3u);  // fifo, spare and link only
  expect_rejected(run("sweep --theta 40 --samples 10 --resume --out " + path("fifo")), "resume", "not a regular file");
}

TEST_F(Cli, OutThroughASymlinkReplacesItsTargetAndKeepsTheLinkAndTheMode) {
  fs::create_directories(path("data"));
  write("data/real.json", "old\n");
  ASSERT_EQ(chmod(path("data/real.json").c_str(), 0640), 0);
  fs::create_symlink("data/real.json", path("link.json"));
  const Result r = run("trajectory --release 0.3 --out " + path("link.json"));
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(fs::is_symlink(path("link.json")));
  EXPECT_NE(read("data/real.json").find("\"duration\""), std::string::npos);
  EXPECT_EQ(fs::status(path("data/real.json")).permissions() & fs::perms::all,
            fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read);
  EXPECT_EQ(std::distance(fs::directory_iterator(path("data")), {}), 1);  // no temporary file left
  // A dangling link creates its target; a link into a missing directory is refused up front.
  fs::create_symlink("data/new.json", path("dangling.json"));
  ASSERT_EQ(run("trajectory --release 0.3 --out " + path("dangling.json")).code, 0);
  EXPECT_TRUE(fs::is_symlink(path("dangling.json")));
  EXPECT_NE(read("data/new.json").find("\"duration\""), std::string::npos);
  fs::create_symlink("nowhere/x.json", path("broken.json"));
  const Result broken = run("trajectory --release 0.3 --out " + path("broken.json"));
  expect_rejected(broken, "broken.json", "does not exist");
  // Each refusal of a path says what --out takes.
  EXPECT_NE(broken.output.find("valid values are a file path in an existing, writable directory, or -"),
            std::string::npos) << broken.output;
  EXPECT_TRUE(fs::is_symlink(path("broken.json")));
}

TEST_F(Cli, OutThroughALinkToStandardOutputWritesToTheShellsStdout) {
  // The layout of /dev/stdout (a link to /proc/self/fd/1), made here, not in /dev.
  fs::create_symlink("/proc/self/fd/1", path("stdout"));
  const Result r = run("trajectory --release 0.3 --out " + path("stdout"));
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("\"duration\""), std::string::npos) << r.output;
  EXPECT_TRUE(fs::is_symlink(path("stdout")));
  EXPECT_EQ(file_count(), 1u);
}

TEST_F(Cli, OutNeverReplacesTheRunsOwnInputs) {
  // --out naming the --config or --geometry file (directly or through a link) is refused
  // before any work, and the input is left as it was.
  write("grid.toml", "theta = \"40:50:5\"\nsamples = 20\n");
  expect_rejected(run("sweep --config " + path("grid.toml") + " --out " + path("grid.toml")), "grid.toml",
                  "is the --config file");
  EXPECT_EQ(read("grid.toml"), "theta = \"40:50:5\"\nsamples = 20\n");
  // Nor its side file: a config named like the partial file is not overwritten, then removed.
  write("s.csv.partial", "theta = \"40:50:5\"\nsamples = 20\n");
  expect_rejected(run("sweep --config " + path("s.csv.partial") + " --overwrite --out " + path("s.csv")),
                  "s.csv.partial", "is the --config file");
  EXPECT_EQ(read("s.csv.partial"), "theta = \"40:50:5\"\nsamples = 20\n");
  fs::remove(path("s.csv.partial"));
  write("walls.toml", "mirror = true\n[left]\nvertices = [[-2, 1.6], [-0.1, -0.365]]\n");
  fs::create_symlink("walls.toml", path("link.toml"));
  for (const std::string command : {"trajectory --release 0.3", "ensemble --samples 10", "sweep --e 0.5,0.9 --samples 10"}) {
    expect_rejected(run(command + " --geometry " + path("walls.toml") + " --out " + path("link.toml")), "link.toml",
                    "is the --geometry file");
  }
  EXPECT_EQ(read("walls.toml"), "mirror = true\n[left]\nvertices = [[-2, 1.6], [-0.1, -0.365]]\n");
  EXPECT_EQ(file_count(), 3u);  // the inputs and the link, nothing else
}

TEST_F(Cli, ASideFileOrAFiguresFileInTheWayIsRefusedBeforeAnyWork) {
  // A directory where a sweep's provenance (FILE.json) goes: refused at once, without the CSV or
  // a partial file (it was found only after every point had been computed, leaving both).
  fs::create_directories(path("s.csv.json"));
  expect_rejected(run("sweep --theta 30:60:1 --samples 100 --out " + path("s.csv")), "s.csv.json",
                  "is a directory; valid values are a file path");
  EXPECT_FALSE(fs::exists(path("s.csv")));
  EXPECT_FALSE(fs::exists(path("s.csv.partial")));
  // The same for a figure's data file: no figure's data is written.
  fs::create_directories(path("out/fig07/fig07.csv"));
  expect_rejected(run("paper --out " + path("out") + " --only fig03,fig07 --quick --no-plots"), "fig07.csv",
                  "is a directory");
  EXPECT_FALSE(fs::exists(path("out/fig03/fig03.csv")));
}

TEST_F(Cli, ADescriptorThatIsNotOpenForWritingIsRefusedBeforeAnyWork) {
  // It was found only when the result was written, after the work (exit code 1).
  expect_rejected(run("ensemble --samples 30 --out /proc/self/fd/9"), "'/proc/self/fd/9'", "descriptor 9 is not open");
  write("in.json", "{}\n");
  expect_rejected(run("ensemble --samples 30 --out /dev/fd/9 9<" + path("in.json")), "'/dev/fd/9'",
                  "descriptor 9 is open for reading only");
  EXPECT_EQ(read("in.json"), "{}\n");
  // Open for writing, it is written through.
  ASSERT_EQ(run("ensemble --samples 30 --out /dev/fd/9 9>" + path("out.json")).code, 0);
  EXPECT_NE(read("out.json").find("\"duration\""), std::string::npos);
}

TEST_F(Cli, OutToADeviceWritesThroughAndReportsAFullDevice) {
  // Device nodes like /dev/null (1, 3) and /dev/full (1, 7), made in the scratch directory.
  if (geteuid() != 0) GTEST_SKIP() << "mknod of a character device needs root; not run";
  if (mknod(path("null").c_str(), S_IFCHR | 0666, makedev(1, 3)) != 0 ||
      mknod(path("full").c_str(), S_IFCHR | 0666, makedev(1, 7)) != 0) {
    GTEST_SKIP() << "mknod refused here (" << std::strerror(errno) << "); not run";
  }
  const int probe = open(path("full").c_str(), O_WRONLY);
  if (probe < 0) GTEST_SKIP() << "opening a device node made here is refused (" << std::strerror(errno) << ")";
  close(probe);
  const Result ok = run("trajectory --release 0.3 --out " + path("null"));
  EXPECT_EQ(ok.code, 0) << ok.output;
  const Result full = run("trajectory --release 0.3 --out " + path("full"));
  EXPECT_EQ(full.code, 1) << full.output;
  EXPECT_NE(full.output.find("cannot write '" + path("full") + "': No space left on device"), std::string::npos)
      << full.output;
  const Result sweep = run("sweep --theta 40 --samples 10 --out " + path("full"));
  EXPECT_EQ(sweep.code, 1) << sweep.output;
  // Standard output itself on the full device: the message goes to stderr, kept apart here.
  const std::string cmd = std::string(FUNNEL_BINARY) + " trajectory --release 0.3 > " + path("full") + " 2> " +
                          path("err.txt");
  const int status = std::system(cmd.c_str());
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 1) << status;
  EXPECT_NE(read("err.txt").find("cannot write to standard output: No space left on device"), std::string::npos)
      << read("err.txt");
  fs::remove(path("err.txt"));
  EXPECT_TRUE(is_char_device(path("null")));
  EXPECT_TRUE(is_char_device(path("full")));
  EXPECT_EQ(file_count(), 2u);
}

TEST_F(Cli, AReaderThatClosesThePipeEarlyIsAnOutputErrorNotASilentSignal) {
  // `funnel ... | head -c 10`: the next write fails; exit code 1 with a message (docs/cli.md), not
  // death by SIGPIPE (status 141 in the shell) with nothing said.
  const std::string cmd = "( " + std::string(FUNNEL_BINARY) + " ensemble --samples 20000 --per-sample --format csv 2> " +
                          path("err.txt") + "; echo $? > " + path("rc.txt") + " ) | head -c 10 > /dev/null";
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  EXPECT_EQ(read("rc.txt"), "1\n");
  EXPECT_NE(read("err.txt").find("cannot write to standard output: Broken pipe"), std::string::npos) << read("err.txt");
}

TEST_F(Cli, AnUnknownProgressSettingIsSaidOnceAndTheKnownOnesSilently) {
  const Result odd = run("sweep --theta 40,50 --samples 20 --out " + path("a.csv"), "FUNNEL_PROGRESS=nevr");
  ASSERT_EQ(odd.code, 0) << odd.output;
  expect_said_once(odd, "funnel: warning: FUNNEL_PROGRESS = 'nevr' is not always, never or auto; using auto");
  for (const char* known : {"never", "auto", "always"}) {
    const Result r = run("sweep --theta 40,50 --samples 20 --out " + path("b.csv"), std::string("FUNNEL_PROGRESS=") + known);
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_EQ(r.output.find("warning"), std::string::npos) << known << ": " << r.output;
  }
}

TEST_F(Cli, AnEnginePathTheCpuDoesNotRunIsSaidOnceAndTheWidestUsed) {
  // A misspelt FUNNEL_SIMD was ignored without a word: a user comparing paths timed one path twice.
  const Result odd = run("trajectory --release 0.3 --out " + path("a.json"), "FUNNEL_SIMD=avx1024");
  ASSERT_EQ(odd.code, 0) << odd.output;
  expect_said_once(odd, "funnel: warning: FUNNEL_SIMD = 'avx1024' is not a path this CPU runs (scalar");
  const Result known = run("trajectory --release 0.3 --out " + path("b.json"), "FUNNEL_SIMD=scalar");
  ASSERT_EQ(known.code, 0) << known.output;
  EXPECT_EQ(known.output.find("warning"), std::string::npos) << known.output;
}

TEST_F(Cli, MisspeltSubcommandsAndOptionsGetTheNearestNameAndTheirHelp) {
  const Result sub = run("trajectroy --release 0.3");
  EXPECT_EQ(sub.code, 2);
  EXPECT_NE(sub.output.find("unknown subcommand 'trajectroy'; did you mean 'trajectory'?"), std::string::npos) << sub.output;
  EXPECT_NE(sub.output.find("Run 'funnel trajectory --help' for its options."), std::string::npos) << sub.output;
  const Result opt = run("ensemble --sampels 10 --theta 40");
  EXPECT_EQ(opt.code, 2);
  EXPECT_NE(opt.output.find("unknown option '--sampels' for 'funnel ensemble'; did you mean '--samples'?"),
            std::string::npos) << opt.output;
  EXPECT_NE(opt.output.find("Run 'funnel ensemble --help' for its options."), std::string::npos) << opt.output;
  // A negative value is not taken for an option; the misspelt option after it is found.
  const Result neg = run("trajectory --release -0.5 --thta 40");
  EXPECT_NE(neg.output.find("unknown option '--thta' for 'funnel trajectory'; did you mean '--theta'?"),
            std::string::npos) << neg.output;
  // Nothing close: no guess, but the list of subcommands.
  const Result far = run("xyzzy");
  EXPECT_EQ(far.code, 2);
  EXPECT_EQ(far.output.find("did you mean"), std::string::npos) << far.output;
  EXPECT_NE(far.output.find("valid subcommands are trajectory, ensemble, sweep"), std::string::npos) << far.output;
  // Other parse errors keep their message and point to the subcommand's help.
  const Result missing = run("trajectory --theta 40");
  EXPECT_EQ(missing.code, 2);
  EXPECT_NE(missing.output.find("--release"), std::string::npos) << missing.output;
  EXPECT_NE(missing.output.find("Run 'funnel trajectory --help' for its options."), std::string::npos) << missing.output;
  // An option given twice says the rule and the way out (it was CLI11's "At Most 1 required").
  const Result twice = run("ensemble --theta 40 --theta 50 --out " + path("e.json"));
  EXPECT_EQ(twice.code, 2);
  EXPECT_NE(twice.output.find("invalid --theta: given 2 times; valid range is once (several values are a list in one "
                              "option of funnel sweep, e.g. --theta A,B)"),
            std::string::npos)
      << twice.output;
  EXPECT_EQ(file_count(), 0u);
}

TEST_F(Cli, ClosedDefaultsToElasticCollisionsAndHonoursItsCaps) {
  const std::string base = "closed --theta 70 --mu 1 --samples 20 ";
  ASSERT_EQ(run(base + "--out " + path("c.json")).code, 0);
  std::string json = read("c.json");
  EXPECT_NE(json.find("\"e\": 1.0"), std::string::npos) << json.substr(0, 400);
  EXPECT_NE(json.find("\"periodic_fraction\": 1.0"), std::string::npos) << json.substr(0, 800);
  ASSERT_EQ(run(base + "--t-max 0.5 --out " + path("c.json")).code, 0);
  json = read("c.json");
  EXPECT_NE(json.find("\"max_time\": 0.5"), std::string::npos) << json.substr(0, 800);
  EXPECT_NE(json.find("\"undecided\": 20"), std::string::npos) << json.substr(0, 800);
  ASSERT_EQ(run(base + "--max-collisions 3 --out " + path("c.json")).code, 0);
  json = read("c.json");
  EXPECT_NE(json.find("\"max_collisions\": 3"), std::string::npos) << json.substr(0, 800);
  EXPECT_NE(json.find("\"undecided\": 20"), std::string::npos) << json.substr(0, 800);
  const Result help = run("closed --help");
  EXPECT_NE(help.output.find("(default 1 here"), std::string::npos) << help.output;
  EXPECT_NE(help.output.find("0 here, a closed funnel"), std::string::npos) << help.output;
  EXPECT_NE(help.output.find("(default 1e4 here)"), std::string::npos) << help.output;
  // Its progress is drawn on request (as on a terminal) and ends at 100%.
  const Result shown = run("closed --samples 2000 --out " + path("p.json"), "FUNNEL_PROGRESS=always");
  ASSERT_EQ(shown.code, 0) << shown.output;
  EXPECT_NE(shown.output.find("funnel closed ["), std::string::npos) << shown.output;
  EXPECT_NE(shown.output.find("100%"), std::string::npos) << shown.output;
}

TEST_F(Cli, OrbitHelpListsOnlyTheOptionsItTakes) {
  const Result help = run("orbit --help");
  ASSERT_EQ(help.code, 0);
  for (const char* taken : {"--theta", "--beta0", "--inertia", "--radius", "--y-star", "--format", "--out"}) {
    EXPECT_NE(help.output.find(taken), std::string::npos) << taken;
  }
  for (const char* refused : {"--e ", "--mu ", "--gap ", "--t-max ", "--max-collisions "}) {
    EXPECT_EQ(help.output.find(refused), std::string::npos) << refused << help.output;
  }
  expect_rejected(run("orbit --mu 1 --out " + path("o.json")), "mu", "orbit");
}

TEST_F(Cli, SweepConfigErrorsSayWhatIsWrongAndHowToWriteIt) {
  const std::string out = " --out " + path("s.csv");
  fs::create_directories(path("dir.toml"));
  expect_rejected(run("sweep --config " + path("dir.toml") + out), "dir.toml", "is a directory");
  write("empty.toml", "");
  expect_rejected(run("sweep --config " + path("empty.toml") + out), "empty.toml", "empty");
  write("comments.toml", "# nothing yet\n");
  expect_rejected(run("sweep --config " + path("comments.toml") + out), "comments.toml", "no settings");
  write("syntax.toml", "mu = 1\ntheta = [40, \n");
  expect_rejected(run("sweep --config " + path("syntax.toml") + out), "syntax.toml", "line 2, column 15");
  write("grid.toml", "[grid]\nthta = 40\n");
  const Result typo = run("sweep --config " + path("grid.toml") + out);
  expect_rejected(typo, "thta", "did you mean 'theta'?");
  EXPECT_NE(typo.output.find("[grid] table"), std::string::npos) << typo.output;  // how to write it
  expect_rejected(run("sweep --config " + std::string(FUNNEL_SOURCE_DIR) + "/paper/fig03.toml" + out), "fig03.toml",
                  "funnel paper");
  write("twice.toml", "theta = 40\n[grid]\ntheta = 50\n");
  expect_rejected(run("sweep --config " + path("twice.toml") + out), "theta", "more than once");
  if (geteuid() != 0) {
    write("secret.toml", "theta = 40\n");
    chmod(path("secret.toml").c_str(), 0);
    expect_rejected(run("sweep --config " + path("secret.toml") + out), "secret.toml", "cannot be read");
  }
  EXPECT_FALSE(fs::exists(path("s.csv")));
}

TEST_F(Cli, SweepConfigReadsGridAndParamsTables) {
  write("grid.toml", "samples = 20\nrelease_dist = \"line\"\n[params]\ne = 0.9\n[grid]\ntheta = \"40:50:10\"\nmu = [0, 1]\n");
  const Result r = run("sweep --config " + path("grid.toml") + " --out " + path("s.csv"));
  ASSERT_EQ(r.code, 0) << r.output;
  const std::string csv = read("s.csv");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 5) << csv;
  EXPECT_NE(csv.find("\n50,0.9,1,0,0.01,0.04,0.4,1e+05,100000000,1,0,0,0,50,50,0,line,20,"), std::string::npos) << csv;
}

TEST_F(Cli, HugeSweepsNeedYes) {
  // The grids below have an invalid gap (d <= 2a) too: the size is checked first, and a funnel
  // without this check fails at once on the gap instead of running for hours.
  const std::string out = " --gap 0.01 --out " + path("s.csv");
  const Result many = run("sweep --theta 1:89:0.01 --mu 0:1.14:0.01 --samples 10" + out);
  EXPECT_EQ(many.code, 2);
  EXPECT_NE(many.output.find("needs --yes: 1012115 points (theta 8801 x mu 115)"), std::string::npos) << many.output;
  const Result slow = run("sweep --theta 40:50:1 --samples 100000000 --threads 1" + out);
  EXPECT_EQ(slow.code, 2);
  // 11 x 10^8 trajectories at 5 us each on one thread: 5500 s = 92 min.
  EXPECT_NE(slow.output.find("1100000000 trajectories, estimated 92 min on 1 thread"), std::string::npos) << slow.output;
  // --yes lifts the limit: the next check speaks.
  const Result yes = run("sweep --theta 40:50:1 --samples 100000000 --threads 1 --yes" + out);
  expect_rejected(yes, "gap", "0.01");
  EXPECT_EQ(yes.output.find("--yes"), std::string::npos) << yes.output;
  // Not past memory: 8.8e9 points ended in bad_alloc (exit 1), as did an orbit grid of 1.8e8.
  const Result absurd = run("sweep --samples 1 --theta 1:89:0.0001 --mu 0:1:0.0001 --yes" + out);
  expect_rejected(absurd, "grid", "theta 880001 x mu 10001: 8800890001 points");
  EXPECT_NE(absurd.output.find("at most 2000000 points"), std::string::npos) << absurd.output;
  // The cap comes first: --yes would not help, so it is not suggested.
  const Result capped = run("sweep --samples 1 --theta 1:89:0.001 --mu 0:0.3:0.01" + out);
  expect_rejected(capped, "grid", "at most 2000000 points");
  EXPECT_EQ(capped.output.find("--yes to run it"), std::string::npos) << capped.output;
  const Result orbit = run("orbit --theta 1:89:0.0001 --beta0 -1:1:0.01 --out " + path("o.json"));
  expect_rejected(orbit, "grid", "theta 880001 x beta0 201: 176880201 points");
  // Exact counts: one point over the cap reads as over it (rounded, "1e+06 points; valid range is
  // at most 1e+06 points").
  const Result over = run("orbit --theta 40:50:1e-5 --out " + path("o.json"));
  expect_rejected(over, "grid", "theta 1000001: 1000001 points; valid range is at most 1000000 points");
  EXPECT_EQ(file_count(), 0u);
}

TEST_F(Cli, PaperWithoutPythonWritesTheDataAndSaysWhyThereAreNoPictures) {
  // A Python that cannot start: the data are complete, the run succeeds and says what is missing.
  const Result r = run("paper --quick --only fig01,fig10 --out " + path("p"), "FUNNEL_PYTHON=/nonexistent/python3");
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("funnel paper: pictures not made: Python 3 with numpy and matplotlib is needed"), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("cannot start /nonexistent/python3"), std::string::npos) << r.output;
  for (const char* fig : {"fig01", "fig10"}) {
    EXPECT_TRUE(fs::exists(path("p/" + std::string(fig) + "/" + fig + ".csv"))) << fig;
    EXPECT_FALSE(fs::exists(path("p/" + std::string(fig) + "/" + fig + ".png"))) << fig;
  }
  EXPECT_NE(r.output.find("funnel paper: total wall time"), std::string::npos) << r.output;
}

TEST_F(Cli, ACopiedBinaryDrawsThePicturesWhereItsPrefixHasAnEmptySitePackages) {
  // funnel copied to PREFIX/bin, where PREFIX's site-packages directory exists without the
  // package (as /usr/local/lib/python3.X/dist-packages does on Debian): the pictures are drawn
  // with the build's package, not left out with a Python that finds no module 'funnel'.
  const std::string site = FUNNEL_INSTALL_PYTHON_DIR;
  if (site.empty()) GTEST_SKIP() << "built without Python";
  fs::create_directories(path("prefix/bin"));
  fs::create_directories(path("prefix/" + site));
  fs::copy_file(FUNNEL_BINARY, path("prefix/bin/funnel"));
  fs::permissions(path("prefix/bin/funnel"), fs::perms::owner_all, fs::perm_options::add);
  const Result r = run_binary(path("prefix/bin/funnel"), "paper --quick --only fig01 --out " + path("p"), "PYTHONPATH=");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_EQ(r.output.find("pictures not made"), std::string::npos) << r.output;
  EXPECT_TRUE(fs::exists(path("p/fig01/fig01.png"))) << r.output;
}

TEST_F(Cli, PaperShowsProgressOfClosedFunnelRunsAndSummarisesEachStage) {
  // Not a terminal: one line per stage. FUNNEL_PROGRESS=always: the bar of Fig. 12's runs.
  const std::string args = "paper --quick --only fig12 --out " + path("p");
  const Result log = run(args);
  ASSERT_EQ(log.code, 0) << log.output;
  EXPECT_NE(log.output.find("funnel paper: θ sweeps: 0 ensembles in "), std::string::npos) << log.output;
  EXPECT_NE(log.output.find("funnel paper: fig12 data written"), std::string::npos) << log.output;
  EXPECT_NE(log.output.find("funnel paper: plots: 1 of 1 figures drawn in "), std::string::npos) << log.output;
  EXPECT_TRUE(fs::exists(path("p/fig12/fig12.png")));
  EXPECT_EQ(log.output.find("["), std::string::npos) << log.output;  // no bar in a log
  const Result bar = run(args + " --no-plots", "FUNNEL_PROGRESS=always");
  ASSERT_EQ(bar.code, 0) << bar.output;
  EXPECT_NE(bar.output.find("funnel paper: fig12 [##############################] 100%"), std::string::npos)
      << bar.output;
}

}  // namespace

namespace {

using namespace funnel_test;

TEST_F(Cli, TheRecordedCommandRunsAsWritten) {
  // Arguments were joined with spaces: an --out "a b's.json" came back as two words, so the
  // provenance's command (and the --resume command a sweep prints) failed when pasted.
  ASSERT_EQ(run("ensemble --samples 10 --out \"" + path("a b's.json") + "\"").code, 0);
  const std::string text = read("a b's.json");
  const std::string quoted = "'" + path("a b") + "'\\\\''s.json'";  // as JSON writes the backslash
  EXPECT_NE(text.find(quoted), std::string::npos) << text;
  const std::size_t at = text.find("\"command\": \"") + 12;
  std::string command = text.substr(at, text.find("\"\n", at) - at);
  for (std::size_t i; (i = command.find("\\\\")) != std::string::npos;) command.erase(i, 1);
  std::remove(path("a b's.json").c_str());
  const Result again = run_binary(command, "");
  ASSERT_EQ(again.code, 0) << command << "\n" << again.output;
  EXPECT_NE(read("a b's.json").find("\"samples\": 10"), std::string::npos);
}

}  // namespace
