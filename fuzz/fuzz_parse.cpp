// libFuzzer target: number/list/range parsing, parameter validation and the sweep's TOML config.
//
// The input is used three ways: as the text of an option (parse_number, parse_values), as raw
// doubles for a Params (validate, make_geometry) and as a TOML config read the way
// `funnel sweep --config` reads it (app/cmd_sweep.cpp; mirrored here since the app is not a
// library). Invariants (a violation aborts, which libFuzzer reports as a crash):
//  - nothing crashes, throws (other than toml::parse_error) or trips a sanitizer;
//  - an accepted number or value is finite; a range has 1 to 10^7 values within
//    [start, stop + step 1e-9], a list one value per comma; a rejection gives a reason;
//  - set_parameter/get_parameter round-trip; every point of a grid carries its axes' values;
//  - validate rejects with a known parameter name and range text, and accepts only values in
//    the documented ranges whose geometry is finite and consistent;
//  - a geometry file (app/geometry_file.cpp) is rejected naming the file, or validated into a
//    finite funnel without overhangs, or rejected by validate with a reason.
#include <toml++/toml.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "funnel/funnel.hpp"
#include "funnel/geometry.hpp"
#include "funnel/grid.hpp"
#include "funnel/params.hpp"
#include "geometry_file.hpp"
#include "cli_common.hpp"

namespace {

[[noreturn]] void fail(const char* what, std::string_view detail = {}) {
  std::fprintf(stderr, "fuzz_parse: invariant violated: %s [%.*s]\n", what, static_cast<int>(detail.size()),
               detail.data());
  std::abort();
}

void require(bool ok, const char* what, std::string_view detail = {}) {
  if (!ok) fail(what, detail);
}

void check_number(std::string_view text) {
  const auto v = funnel::parse_number(text);
  if (v) require(std::isfinite(*v), "parse_number accepted a non-finite value", text);
}

/// parse_values and its invariants; the values, or nullopt.
std::optional<std::vector<double>> check_values(std::string_view text) {
  std::string error;
  auto values = funnel::parse_values(text, error);
  if (!values) {
    require(!error.empty(), "parse_values rejected without a reason", text);
    return values;
  }
  require(!values->empty(), "parse_values accepted no value", text);
  require(values->size() <= 10'000'000, "a range gave more than 10^7 values", text);
  for (const double v : *values) require(std::isfinite(v), "parse_values accepted a non-finite value", text);
  if (text.find(':') != std::string_view::npos) {
    // An accepted range is "start:stop:step": values start + i step, the last within 1e-9 step of stop.
    const std::size_t c1 = text.find(':');
    const std::size_t c2 = text.find(':', c1 + 1);
    const auto trimmed = [](std::string_view s) {
      while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
      while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
      return s;
    };
    const auto start = funnel::parse_number(trimmed(text.substr(0, c1)));
    const auto stop = funnel::parse_number(trimmed(text.substr(c1 + 1, c2 - c1 - 1)));
    const auto step = funnel::parse_number(trimmed(text.substr(c2 + 1)));
    require(start && stop && step && *step > 0 && *stop >= *start, "accepted a malformed range", text);
    require(values->front() == *start, "range does not begin at start", text);
    require(std::is_sorted(values->begin(), values->end()), "range values not increasing", text);
    const double rounding = 4.0 * std::numeric_limits<double>::epsilon() *
                            std::fmax(std::fabs(*start), std::fabs(values->back()));
    require(values->back() <= *stop + 1e-9 * *step + rounding, "range goes beyond stop", text);
    require(values->back() + *step * (1.0 + 1e-9) >= *stop - rounding, "range stops short of stop", text);
  } else {
    require(values->size() == static_cast<std::size_t>(std::count(text.begin(), text.end(), ',')) + 1,
            "list gave a value count other than commas + 1", text);
  }
  return values;
}

/// Each accepted value of an axis must be stored as given (max-collisions: if integral).
void check_axis(const std::string& name, const std::vector<double>& values) {
  const funnel::Params base = funnel::default_params();
  std::vector<double> accepted;
  for (const double v : values) {
    funnel::Params p = base;
    if (!funnel::set_parameter(p, name, v)) {
      require(name == "max-collisions", "set_parameter refused a finite value", name);
      continue;
    }
    require(funnel::get_parameter(p, name) == v, "get_parameter does not return the value set", name);
    accepted.push_back(v);
    if (const auto err = funnel::validate(p)) {
      require(!err->message().empty() && !err->range.empty(), "validate error without a message", name);
    }
  }
  // The grid must carry exactly the values of its axis, in order. (The sweep command rejects a
  // value that set_parameter refuses before it builds the grid; app/cli_common.cpp to_axes.)
  if (accepted.size() != values.size() || values.size() > 4096) return;
  const std::vector<funnel::Params> grid = funnel::expand_grid(base, {{name, values}});
  require(grid.size() == values.size(), "grid size differs from the axis", name);
  for (std::size_t i = 0; i < grid.size(); ++i) {
    require(funnel::get_parameter(grid[i], name) == values[i], "grid point does not carry its axis value", name);
  }
}

double raw_double(const std::uint8_t* data, std::size_t size, std::size_t i) {
  std::uint8_t bytes[8] = {};
  for (std::size_t k = 0; k < 8; ++k) bytes[k] = size > 0 ? data[(8 * i + k) % size] : 0;
  double v = 0.0;
  std::memcpy(&v, bytes, sizeof v);
  return v;
}

/// validate() on a Params of raw doubles (NaN, infinities and subnormals included).
void check_validate(const std::uint8_t* data, std::size_t size) {
  funnel::Params p = funnel::default_params();
  // Each field is either left at its default or taken from the bytes, so that valid sets occur.
  const std::uint8_t mask = size > 0 ? data[0] : 0;
  double* fields[] = {&p.theta, &p.e, &p.mu, &p.beta0, &p.radius, &p.gap, &p.inertia, &p.t_max};
  for (std::size_t i = 0; i < 8; ++i) {
    if (mask & (1u << i)) *fields[i] = raw_double(data, size, i + 1);
  }
  if (size > 1 && (data[1] & 1)) {
    const double c = raw_double(data, size, 9);
    std::memcpy(&p.max_collisions, &c, sizeof c);
  }

  const auto err = funnel::validate(p);
  if (err) {
    static const char* const known[] = {"theta", "e",     "mu",    "beta0",          "radius", "gap",
                                        "inertia", "t-max", "max-collisions", "p-c",   "eps-rest"};
    const bool named = std::any_of(std::begin(known), std::end(known), [&](const char* k) { return err->name == k; });
    require(named, "validate named an unknown parameter", err->name);
    require(!err->range.empty() && !err->value.empty(), "validate error without value or range", err->name);
    require(err->message().find(err->name) != std::string::npos, "message does not name the parameter", err->name);
    return;
  }
  require(p.theta > 0 && p.theta < 90 && p.e >= 0 && p.e <= 1 && p.mu >= 0 && std::isfinite(p.mu) &&
              p.beta0 >= -1 && p.beta0 <= 1 && p.radius > 0 && p.radius < 1 &&
              (p.gap == 0 || (p.gap > 2 * p.radius && std::isfinite(p.gap))) && p.inertia > 0 &&
              std::isfinite(p.inertia) && p.t_max > 0 && std::isfinite(p.t_max) && p.max_collisions >= 1,
          "validate accepted a value outside its documented range");
  const funnel::Geometry g = funnel::make_geometry(p);
  const double values[] = {g.sin_t, g.cos_t, g.tan_t, g.y_bottom, g.y_release, g.half_width, g.y_face_end,
                           g.x_face_end};
  for (const double v : values) require(std::isfinite(v), "validate accepted parameters with a non-finite geometry");
  require(g.y_release > 0 && g.half_width > 0, "release point not above the vertex");
  // <=, not <: a radius far below the gap's rounding puts C* on the edges' level in doubles.
  require(g.closed || (g.y_bottom <= g.y_face_end && g.y_face_end <= g.y_release), "face end outside the walls");
}

/// A TOML number as text: integers exactly (toml++ gives no value<double>() for |i| > 2^53),
/// floats in their shortest round-trip form (inf and nan included, which parse_values rejects).
std::string toml_number_text(const toml::node& node) {
  if (const auto* i = node.as_integer()) return std::to_string(i->get());
  char buf[32];
  const auto [ptr, ec] = std::to_chars(buf, buf + sizeof buf, node.as_floating_point()->get());
  return std::string(buf, ptr);
}

/// Text of a TOML value as `funnel sweep --config` passes it on (app/cmd_sweep.cpp), or nullopt
/// where the app reports an error.
std::optional<std::string> toml_value_text(const toml::node& node) {
  if (node.is_string()) return *node.value<std::string>();
  if (node.is_integer() || node.is_floating_point()) return toml_number_text(node);
  if (const toml::array* arr = node.as_array()) {
    std::string text;
    for (const toml::node& item : *arr) {
      if (!(item.is_integer() || item.is_floating_point())) return std::nullopt;
      text += (text.empty() ? "" : ",") + toml_number_text(item);
    }
    if (text.empty()) return std::nullopt;
    return text;
  }
  return std::nullopt;
}

/// toml++ 3.3.0 (Debian bookworm) reaches __builtin_unreachable on some non-ASCII code points
/// where it expects whitespace (upstream marzer/tomlplusplus#295, fixed by PR #305), e.g. the
/// input "\xef\xb8\xbf0". The shipped library (gcc) reports a parse error for it; the fuzzer
/// gives toml++ ASCII only, so that this known upstream bug does not mask our own.
bool ascii(std::string_view text) {
  return std::none_of(text.begin(), text.end(), [](char c) { return static_cast<unsigned char>(c) >= 0x80; });
}

void check_toml(std::string_view text) {
  if (!ascii(text)) return;
  toml::table tbl;
  try {
    tbl = toml::parse(text);
  } catch (const toml::parse_error&) {
    return;
  }
  const auto& names = funnel::sweep_parameter_names();
  for (auto&& [k, node] : tbl) {
    std::string key(k.str());
    std::replace(key.begin(), key.end(), '_', '-');
    const auto value = toml_value_text(node);
    if (!value) continue;
    if (std::find(names.begin(), names.end(), key) == names.end()) continue;
    if (const auto values = check_values(*value)) check_axis(key, *values);
  }
}

}  // namespace

/// The text as a geometry file (`--geometry FILE.toml`, app/geometry_file.cpp, compiled into
/// this target): it is rejected with a UsageError naming the file, or gives a profile that
/// validate() either rejects with a reason or turns into a funnel with finite numbers.
void check_geometry(std::string_view text) {
  if (!ascii(text)) return;
  std::shared_ptr<const funnel::ProfileSpec> spec;
  try {
    spec = funnel::cli::parse_geometry(std::string(text), "fuzz.toml");
  } catch (const funnel::cli::UsageError& err) {
    require(std::string_view(err.what()).starts_with("invalid geometry = 'fuzz.toml': "), "geometry error without the file",
            err.what());
    return;
  }
  funnel::Params p = funnel::default_params();
  p.profile = spec;
  if (const auto error = funnel::validate(p)) {
    require(!error->name.empty() && !error->range.empty(), "geometry rejected without a reason", error->value);
    return;
  }
  const funnel::Funnel f = funnel::make_funnel(p);
  require(std::isfinite(f.y_exit) && std::isfinite(f.y_release) && std::isfinite(f.half_width) && f.half_width > 0.0 &&
              std::isfinite(f.x_release_mid),
          "accepted geometry with a non-finite funnel");
  for (const funnel::Side& side : f.sides) {
    require(!side.faces.empty() && !side.corners.empty(), "accepted geometry without faces");
    for (const funnel::Face& face : side.faces) require(face.n.y >= 0.0, "accepted geometry with an overhang");
  }
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size > 4096) return 0;  // long inputs add nothing but time
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  check_number(text);
  if (const auto values = check_values(text); values && values->size() <= 4096) {
    // The same text as each parameter's option value.
    for (const std::string& name : funnel::sweep_parameter_names()) check_axis(name, *values);
  }
  check_validate(data, size);
  check_toml(text);
  check_geometry(text);
  return 0;
}
