// funnel: command-line entry point. Bad input exits with code 2 and writes no file; a failed write exits 1.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <cctype>
#include <csignal>
#include <cstdlib>
#include <iostream>
#include <string>
#include <string_view>

#include "cli_common.hpp"
#include "commands.hpp"
#include "mpi_run.hpp"
#include "suggest.hpp"
#include "funnel/simd.hpp"
#include "funnel/version.hpp"

namespace {

/// FUNNEL_SIMD naming no path this CPU runs is said once on stderr (the widest path is used):
/// a misspelt path was ignored silently, so a user comparing paths compared the same one.
void warn_unknown_simd_path() {
  const char* env = std::getenv("FUNNEL_SIMD");
  if (env == nullptr || *env == '\0') return;
  const std::vector<std::string> paths = funnel::simd_paths();
  if (std::find(paths.begin(), paths.end(), env) != paths.end()) return;
  std::string valid;
  for (const std::string& p : paths) valid += (valid.empty() ? "" : ", ") + p;
  std::cerr << "funnel: warning: FUNNEL_SIMD = '" << env << "' is not a path this CPU runs (" << valid
            << "); using " << funnel::simd_path() << "\n";
}

/// An argument as a POSIX shell reads it back: as is when it holds only characters the shell
/// takes literally, else in single quotes (a ' inside as '\''). The provenance's command and the
/// printed --resume command are then runnable as written (an --out "a b.csv" was not).
std::string shell_word(std::string_view arg) {
  const bool plain = !arg.empty() && std::all_of(arg.begin(), arg.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || std::string_view("_@%+=:,./-").find(c) != std::string_view::npos;
  });
  if (plain) return std::string(arg);
  std::string out = "'";
  for (const char c : arg) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

/// Parses the command line and runs the subcommand; returns the exit code.
int run_command_line(int argc, char** argv) {
  std::string command_line;
  for (int i = 0; i < argc; ++i) {
    if (i > 0) command_line += ' ';
    command_line += shell_word(argv[i]);
  }

  CLI::App app{"funnel: exact event-driven simulation of a frictional, inelastic sphere falling\n"
               "through a 2D funnel (Walton's collision law). Units: H = g = m = 1.",
               "funnel"};
  app.set_version_flag("--version", std::string(funnel::version()) + " (" + std::string(funnel::git_commit()) + ")");
  app.require_subcommand(1);
  funnel::cli::add_trajectory_command(app, command_line);
  funnel::cli::add_ensemble_command(app, command_line);
  funnel::cli::add_sweep_command(app, command_line);
  funnel::cli::add_closed_command(app, command_line);
  funnel::cli::add_orbit_command(app, command_line);
  funnel::cli::add_retrace_command(app, command_line);
  funnel::cli::add_paper_command(app, command_line);
  funnel::cli::add_bench_command(app, command_line);
  for (const char* name : {"sweep", "ensemble", "paper"}) app.get_subcommand(name)->footer(funnel::cli::mpi_help());

  warn_unknown_simd_path();
  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {
    return app.exit(e);  // --help, --version
  } catch (const CLI::ParseError& e) {
    // An unknown word gets its nearest valid one; other parse errors keep CLI11's message.
    const std::string what = e.what();
    const std::string repeated = ": At Most 1 required but received ";
    if (const auto why = funnel::cli::explain_unknown(app, argc, argv)) {
      std::cerr << "funnel: error: " << *why << "\n";
    } else if (const auto at = what.find(repeated); at != std::string::npos && what.rfind("--", 0) == 0) {
      // An option given twice: CLI11's words named neither the rule nor a way out.
      const std::string option = what.substr(0, at);
      std::cerr << "funnel: error: invalid " << option << ": given " << what.substr(at + repeated.size())
                << " times; valid range is once (several values are a list in one option of funnel sweep, e.g. "
                << option << " A,B)\n"
                << funnel::cli::help_hint(app, argc, argv) << "\n";
    } else {
      std::cerr << "funnel: error: " << e.what() << "\n" << funnel::cli::help_hint(app, argc, argv) << "\n";
    }
    return 2;
  } catch (const funnel::cli::UsageError& e) {
    std::cerr << "funnel: error: " << e.what() << "\n";
    return 2;
  } catch (const funnel::cli::OutputError& e) {
    std::cerr << "funnel: error: " << e.what() << "\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "funnel: internal error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  // A reader that closes the pipe early (`funnel ... | head`) makes the next write fail with
  // EPIPE, reported as an output error (exit code 1, docs/cli.md), instead of killing the process
  // silently with SIGPIPE (exit status 141 in the shell).
  std::signal(SIGPIPE, SIG_IGN);
  // Under mpirun only rank 0 runs the command; the others compute what it deals them and exit
  // with its exit code (docs/cluster.md).
  funnel::cli::MpiSession mpi(argc, argv);
  if (funnel::cli::mpi_rank() != 0) return mpi.serve();
  const int code = run_command_line(argc, argv);
  mpi.finish(code);
  return code;
}
