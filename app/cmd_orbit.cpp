// `funnel orbit`: eigenvalues and stability of the period-2 orbit (paper Sec. IV, Fig. 10).
#include <memory>

#include "cli_common.hpp"
#include "commands.hpp"
#include "funnel/orbit.hpp"
#include "funnel/paper/records.hpp"

namespace funnel::cli {

namespace {

/// The parameters the period-2 orbit depends on (e = 1, sticking collisions, infinite walls).
bool orbit_parameter(std::string_view name) {
  return name == "theta" || name == "beta0" || name == "inertia" || name == "radius";
}

/// One grid point of the orbit analysis.
struct OrbitPoint {
  orbit::OrbitParams params;
  orbit::OrbitAnalysis analysis;
};

struct OrbitCommand {
  ModelOptions model;
  std::string y_star = "0.5";
  std::string format = "json";
  std::string out = "-";
  std::string command_line;

  void run() const {
    for (const auto& [name, text] : model.given) {
      if (!orbit_parameter(name)) {
        throw UsageError("invalid option --" + name + " = '" + text + "' for funnel orbit: the orbit depends on theta, beta0, inertia, radius only (e = 1, sticking)");
      }
    }
    const auto ys = parse_number(y_star);
    if (!ys || !(*ys > 0.0)) throw UsageError("invalid y-star = '" + y_star + "': valid range is y-star > 0");
    const std::vector<Axis> axes =
        to_axes(model, 1e6, "the output holds each point's four eigenvalues, about 500 bytes of JSON");
    const std::vector<Params> points = expand_grid(default_params(), axes);
    // The orbit's own parameters only: the funnel's gap and release line play no part in it.
    for (const Params& p : points) {
      if (const auto err = validate_orbit(p)) throw UsageError(err->message());
    }
    const Format fmt = to_format(format);
    check_writable(out);

    std::vector<OrbitPoint> results;
    for (const Params& p : points) {
      const orbit::OrbitParams op{p.theta, p.beta0, p.inertia, p.radius};
      results.push_back({op, orbit::analyse(op, *ys)});
    }

    std::string text;
    if (fmt == Format::Json) {
      nlohmann::ordered_json j;
      j["y_star"] = *ys;
      j["points"] = nlohmann::ordered_json::array();
      for (const OrbitPoint& r : results) {
        nlohmann::ordered_json pj;
        pj["theta"] = r.params.theta_deg;
        pj["beta0"] = r.params.beta0;
        pj["inertia"] = r.params.kappa;
        pj["radius"] = r.params.radius;
        pj["eigenvalues"] = nlohmann::ordered_json::array();
        for (int i = 0; i < 4; ++i) {
          const auto z = r.analysis.eigenvalues[i];
          pj["eigenvalues"].push_back({{"real", z.real()}, {"imag", z.imag()}, {"modulus", std::abs(z)}});
        }
        pj["stable"] = r.analysis.stable;
        pj["jacobian_max_rel_diff"] = r.analysis.jacobian_max_rel_diff;
        j["points"].push_back(pj);
      }
      j["provenance"] = provenance_json(command_line);
      text = j.dump(2) + "\n";
    } else {
      std::vector<std::string> cols{"theta", "beta0", "inertia", "radius"};
      for (int i = 1; i <= 4; ++i) {
        for (const char* part : {"re", "im", "mod"}) cols.push_back(std::string(part) + std::to_string(i));
      }
      cols.emplace_back("stable");
      cols.emplace_back("jacobian_max_rel_diff");
      text = csv_line(cols);
      for (const OrbitPoint& r : results) {
        std::vector<std::string> row{number(r.params.theta_deg), number(r.params.beta0), number(r.params.kappa),
                                     number(r.params.radius)};
        for (int i = 0; i < 4; ++i) {
          const auto z = r.analysis.eigenvalues[i];
          row.push_back(number(z.real()));
          row.push_back(number(z.imag()));
          row.push_back(number(std::abs(z)));
        }
        row.emplace_back(r.analysis.stable ? "1" : "0");
        row.push_back(number(r.analysis.jacobian_max_rel_diff));
        text += csv_line(row);
      }
    }
    write_output(out, text);
  }
};

}  // namespace

void add_orbit_command(CLI::App& app, const std::string& command_line) {
  auto cmd = std::make_shared<OrbitCommand>();
  cmd->command_line = command_line;
  CLI::App* sub = app.add_subcommand(
      "orbit", "Eigenvalues and stability of the period-2 orbit (e = 1, sticking collisions) per grid point (Fig. 10).");
  add_model_options(*sub, cmd->model, true);
  // The orbit is for e = 1 and sticking collisions: the other model options are refused in
  // run() with that reason, and not listed by --help.
  for (const ParameterInfo& p : parameters()) {
    if (p.option && !orbit_parameter(p.name)) sub->get_option("--" + std::string(p.name))->group("");
  }
  // Its theta range is its own (validate_orbit): below 1e-3 degrees the eigenvalues are not resolved.
  sub->get_option("--theta")->description("wall angle to the horizontal [degrees]; " + std::string(orbit_theta_range) +
                                          " (default 60); a list a,b,c or a range start:stop:step sweeps it");
  sub->add_option("--y-star", cmd->y_star,
                  "orbit height y* for the Jacobians (the eigenvalues do not depend on it); > 0 (default 0.5)")
      ->type_name("Y");
  add_output_options(*sub, cmd->format, cmd->out);
  sub->callback([cmd] { cmd->run(); });
}

}  // namespace funnel::cli
