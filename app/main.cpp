// funnel: command-line entry point. Bad input exits with code 2 and writes no file.
#include <CLI/CLI.hpp>

#include <iostream>
#include <string>

#include "cli_common.hpp"
#include "commands.hpp"
#include "funnel/version.hpp"

int main(int argc, char** argv) {
  std::string command_line;
  for (int i = 0; i < argc; ++i) {
    if (i > 0) command_line += ' ';
    command_line += argv[i];
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

  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {
    return app.exit(e);  // --help, --version
  } catch (const CLI::ParseError& e) {
    std::cerr << "funnel: error: " << e.what() << "\nRun 'funnel --help' for the options.\n";
    return 2;
  } catch (const funnel::cli::UsageError& e) {
    std::cerr << "funnel: error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "funnel: internal error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
