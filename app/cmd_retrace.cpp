// `funnel retrace`: self-retracing orbits of the elastic frictionless particle, with their stability.
#include <charconv>
#include <memory>

#include "cli_common.hpp"
#include "commands.hpp"
#include "progress.hpp"
#include "funnel/geometry.hpp"
#include "funnel/retrace.hpp"
#include "funnel/paper/records.hpp"
#include "funnel/paper/retrace_records.hpp"

namespace funnel::cli {

namespace {

int integer_in(const std::string& name, const std::string& text, int lo, int hi) {
  int n = 0;
  const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), n);
  if (ec != std::errc() || ptr != text.data() + text.size() || n < lo || n > hi) {
    throw UsageError("invalid " + name + " = '" + text + "': valid range is an integer " + std::to_string(lo) +
                     " <= " + name + " <= " + std::to_string(hi));
  }
  return n;
}

struct RetraceCommand {
  std::string theta = "60";
  std::string radius = "0.01";
  std::string gap = "0";
  std::string e = "1";
  std::string mu = "0";
  std::string max_bounces = "6";
  std::string scan_points = "1000";
  std::string turns = "wall";
  std::string threads = "0";
  bool windows_csv = false;
  std::string format = "json";
  std::string out = "-";
  std::string command_line;

  void run() const {
    // The orbits are those of the elastic frictionless particle: e and mu are fixed.
    if (const auto v = parse_number(e); !v || *v != 1.0) {
      throw UsageError("invalid e = '" + e + "': funnel retrace needs e = 1 (elastic; the default here)");
    }
    if (const auto v = parse_number(mu); !v || *v != 0.0) {
      throw UsageError("invalid mu = '" + mu + "': funnel retrace needs mu = 0 (frictionless; the default here)");
    }
    ModelOptions model;
    model.given["radius"] = radius;
    model.given["gap"] = gap;
    const Params base = retrace::frictionless(to_params(model));
    std::string reason;
    const auto thetas = parse_values(theta, reason);
    if (!thetas) {
      throw UsageError("invalid theta = '" + theta + "': " + reason + "; valid range is " +
                       std::string(valid_range("theta")));
    }
    // About 0.5 ms of one core per angle at the defaults, and every angle's orbits are held in
    // memory: a finer grid than this is refused at once (it ran, silent, for hours).
    check_grid_cap({{"theta", *thetas}}, 1e5, "each angle is a scan of --scan-points releases, and its orbits are "
                                              "held in memory");
    for (const double t : *thetas) {
      Params p = base;
      p.theta = t;
      if (const auto err = validate(p)) throw UsageError(err->message());
    }
    retrace::Options opt;
    opt.max_bounces = integer_in("max-bounces", max_bounces, 1, 20);
    opt.scan_points = integer_in("scan-points", scan_points, 16, 1'000'000);
    opt.rest_turns = parse_turns(turns);
    opt.threads = to_threads(threads);
    const Format fmt = to_format(format);
    if (windows_csv && fmt != Format::Csv) throw UsageError("invalid windows: --windows needs --format csv");
    check_writable(out);

    std::vector<retrace::Orbit> orbits;
    {
      ProgressBar bar("funnel retrace");  // a bar on a terminal; no summary line (the JSON may go to stdout)
      opt.progress = [&bar](std::int64_t done, std::int64_t total) { bar.update(done, total); };
      orbits = retrace::scan(base, *thetas, opt);
      bar.finish(std::to_string(thetas->size()) + " angles scanned");
    }
    const std::vector<retrace::Window> wins = retrace::windows(orbits, *thetas);
    std::string text;
    if (fmt == Format::Json) {
      nlohmann::ordered_json j;
      j["params"] = {{"radius", base.radius}, {"gap", base.gap}, {"e", base.e}, {"mu", base.mu}};
      j["theta"] = {{"first", thetas->front()}, {"last", thetas->back()}, {"count", thetas->size()}};
      j["options"] = {{"max_bounces", opt.max_bounces}, {"scan_points", opt.scan_points},
                      {"turns", opt.rest_turns ? "wall,rest" : "wall"}};
      j["orbits"] = nlohmann::ordered_json::array();
      for (const CheckedOrbit& c : check_orbits(base, orbits)) j["orbits"].push_back(orbit_json(c));
      j["windows"] = nlohmann::ordered_json::array();
      for (const retrace::Window& w : wins) j["windows"].push_back(window_json(w));
      j["provenance"] = provenance_json(command_line);
      text = j.dump(2) + "\n";
    } else if (windows_csv) {
      text = csv_line(window_columns());
      for (const retrace::Window& w : wins) text += csv_line(window_row(w));
    } else {
      text = csv_line(orbit_columns());
      for (const CheckedOrbit& c : check_orbits(base, orbits)) text += csv_line(orbit_row(c));
    }
    write_output(out, text);
  }
};

}  // namespace

void add_retrace_command(CLI::App& app, const std::string& command_line) {
  auto cmd = std::make_shared<RetraceCommand>();
  cmd->command_line = command_line;
  CLI::App* sub = app.add_subcommand(
      "retrace",
      "Self-retracing orbits of the elastic frictionless particle (e = 1, mu = 0): releases x0/L whose path turns "
      "back after k collisions (a perpendicular wall hit, or a vertical rise to rest), their period and stability.");
  sub->add_option("--theta", cmd->theta,
                  "wall angle(s), degrees; a number, a list a,b,c or a range start:stop:step; 0 < theta < 90 (default 60)")
      ->type_name("LIST");
  sub->add_option("--radius", cmd->radius, "particle radius a / H; 1e-100 <= a < 1 (default 0.01)")->type_name("NUM");
  sub->add_option("--gap", cmd->gap,
                  "gap d / H: 0 = closed funnel (default); d > 2a keeps the orbits that stay above the faces' ends")
      ->type_name("NUM");
  sub->add_option("--e", cmd->e, "normal restitution: must be 1 (default 1)")->type_name("NUM");
  sub->add_option("--mu", cmd->mu, "friction coefficient: must be 0 (default 0)")->type_name("NUM");
  sub->add_option("--max-bounces", cmd->max_bounces, "K: largest number of collisions up to the turn; 1 <= K <= 20 (default 6)")
      ->type_name("K");
  sub->add_option("--scan-points", cmd->scan_points,
                  "release grid points on x0/L in (-1, 0) before refinement; 16 <= N <= 10^6 (default 1000)")
      ->type_name("N");
  sub->add_option("--turns", cmd->turns,
                  "which turns: wall (a perpendicular hit, default), or wall,rest (also a vertical rise to a second rest point; all "
                  "is the same)")
      ->type_name("TURNS");
  sub->add_option("--threads", cmd->threads, "worker threads over the angles; integer 1 to 1024, or 0 = all cores (default 0)")
      ->type_name("T");
  sub->add_flag("--windows", cmd->windows_csv, "with --format csv: the existence and stability windows instead of the orbits");
  add_output_options(*sub, cmd->format, cmd->out);
  sub->callback([cmd] { cmd->run(); });
}

}  // namespace funnel::cli
