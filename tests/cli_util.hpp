// Helpers of the command-line tests: run the funnel binary, a scratch directory per test.
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace funnel_test {

namespace fs = std::filesystem;

/// Exit code (-1 if killed) and output of one run.
struct Result {
  int code = -1;
  std::string output;  ///< stdout and stderr together
};

/// Runs `BINARY ARGS` through the shell (so ARGS may hold redirections and variables).
inline Result run_binary(const std::string& binary, const std::string& args, const std::string& env = "") {
  const std::string cmd = env + (env.empty() ? "" : " ") + binary + " " + args + " 2>&1";
  Result r;
  FILE* pipe = popen(cmd.c_str(), "r");
  if (pipe == nullptr) return r;
  char buf[4096];
  std::size_t n;
  while ((n = fread(buf, 1, sizeof buf, pipe)) > 0) r.output.append(buf, n);
  const int status = pclose(pipe);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

/// Runs `funnel ARGS` (the build's binary) through the shell.
inline Result run(const std::string& args, const std::string& env = "") { return run_binary(FUNNEL_BINARY, args, env); }

inline std::string read_source(const std::string& file) {
  std::ifstream in(file);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// A fresh scratch directory per test, removed afterwards.
class Cli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("funnel_cli_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  void write(const std::string& name, const std::string& text) const { std::ofstream(path(name)) << text; }
  std::string read(const std::string& name) const { return read_source(path(name)); }
  /// Only the files the test itself created are in the directory.
  std::size_t file_count() const { return static_cast<std::size_t>(std::distance(fs::directory_iterator(dir_), {})); }

  fs::path dir_;
};

/// The first two lines of a sweep's partial file, as an interrupted run leaves them: the spec
/// (FILE.csv.json's "spec", dumped), then the columns: the grid index, the counts of runs that the
/// collision cap and a guard ended, and the CSV's (`header`, its first line without the newline).
/// Each finished point follows as "INDEX,CAPPED,STALLED,ROW".
inline std::string partial_start(const std::string& spec, const std::string& header) {
  return "# funnel sweep spec: " + spec + "\npoint,capped,stalled," + header + "\n";
}

/// `warning` appears in the output exactly once.
inline void expect_said_once(const Result& r, const std::string& warning) {
  const auto at = r.output.find(warning);
  EXPECT_NE(at, std::string::npos) << r.output;
  EXPECT_EQ(r.output.find(warning, at + 1), std::string::npos) << r.output;  // (at npos: from 0, still npos)
}

/// Exit code 2, and the message names the parameter and the value.
inline void expect_rejected(const Result& r, const std::string& name, const std::string& value) {
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find(name), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(value), std::string::npos) << r.output;
}

}  // namespace funnel_test
