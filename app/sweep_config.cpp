// Reading a sweep's TOML file, with messages that say how to write it.
#include "sweep_config.hpp"

#include <toml++/toml.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "cli_common.hpp"
#include "funnel/grid.hpp"
#include "suggest.hpp"

namespace funnel::cli {

const char* const sweep_config_layout =
    "a sweep config sets model parameters (theta, e, mu, beta0, radius, gap, inertia, t-max, max-collisions, ...; "
    "in 3d also release-w, release-spin-x, release-spin-y, max-ode-steps) "
    "at the top level or in a [grid] table, each a number, an array such as [0, 0.1, 1] or a string such as "
    "\"40:50:0.5\" or \"0,1,5\"; samples and release-dist go at the top level";

namespace {

/// A TOML number as text. Integers are written exactly: toml++ gives no value<double>() for
/// |i| > 2^53, and dereferencing that empty optional ran the sweep with a garbage value
/// (theta = 9007199254740993 ran at theta = 6.9e-310; found writing fuzz/fuzz_parse).
std::string toml_number_text(const toml::node& node) {
  if (const auto* i = node.as_integer()) return std::to_string(i->get());
  return number(node.as_floating_point()->get());
}

/// Text of a TOML value as the command line would give it: a number, a list or a range.
std::string toml_value_text(const std::string& key, const toml::node& node, const std::string& file) {
  if (node.is_string()) return *node.value<std::string>();
  if (node.is_integer() || node.is_floating_point()) return toml_number_text(node);
  if (const toml::array* arr = node.as_array()) {
    std::string text;
    for (const toml::node& item : *arr) {
      if (!(item.is_integer() || item.is_floating_point())) {
        throw UsageError("invalid " + key + " in config '" + file + "': arrays must hold numbers only");
      }
      text += (text.empty() ? "" : ",") + toml_number_text(item);
    }
    if (text.empty()) throw UsageError("invalid " + key + " in config '" + file + "': empty array");
    return text;
  }
  throw UsageError("invalid " + key + " in config '" + file + "': expected a number, an array or a string");
}

std::string canonical_key(std::string key) {
  std::replace(key.begin(), key.end(), '_', '-');
  // The command line's other name of the spin about z (--release-spin-z): the nearest key was
  // release-spin-x, the spin about another axis.
  if (key == "release-spin-z") return "release-spin";
  return key;
}

/// The model parameters a config may set: those of either space (a 3D one in a 2D sweep is then
/// refused by the sweep's validation, naming it and --space 3d).
const std::vector<std::string>& config_parameter_names() { return sweep_parameter_names(Space::ThreeD); }

bool is_parameter(const std::string& key) {
  const auto& names = config_parameter_names();
  return std::find(names.begin(), names.end(), key) != names.end();
}

std::string read_text(const std::string& file) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status st = fs::status(file, ec);
  if (!fs::exists(st)) throw UsageError("invalid config = '" + file + "': no such file");
  if (fs::is_directory(st)) {
    throw UsageError("invalid config = '" + file + "': is a directory, not a TOML file; " + sweep_config_layout);
  }
  std::ifstream in(file, std::ios::binary);
  if (!in) throw UsageError("invalid config = '" + file + "': cannot be read: " + std::strerror(errno));
  std::stringstream buffer;
  buffer << in.rdbuf();
  if (in.bad()) throw UsageError("invalid config = '" + file + "': cannot be read: " + std::strerror(errno));
  return buffer.str();
}

}  // namespace

SweepConfig read_sweep_config(const std::string& file) {
  const std::string text = read_text(file);
  if (text.find_first_not_of(" \t\r\n") == std::string::npos) {
    throw UsageError("invalid config = '" + file + "': the file is empty; " + sweep_config_layout);
  }
  toml::table tbl;
  try {
    tbl = toml::parse(text, file);
  } catch (const toml::parse_error& err) {
    const auto& at = err.source().begin;
    throw UsageError("invalid config = '" + file + "': line " + std::to_string(at.line) + ", column " +
                     std::to_string(at.column) + ": " + std::string(err.description()));
  }
  if (tbl.empty()) throw UsageError("invalid config = '" + file + "': holds no settings; " + sweep_config_layout);
  if (tbl.contains("figure") || tbl.contains("panels")) {
    const std::string fig = tbl["figure"].value_or(std::string("FIG"));
    throw UsageError("invalid config = '" + file + "': this is a figure definition of 'funnel paper' (run it with "
                     "'funnel paper --only " + fig + "'), not a sweep config; " + sweep_config_layout);
  }

  SweepConfig config;
  const auto set_parameter_text = [&](const std::string& key, const toml::node& node) {
    if (!config.params.emplace(key, toml_value_text(key, node, file)).second) {
      throw UsageError("invalid config = '" + file + "': " + key + " is given more than once");
    }
  };
  std::vector<std::string> valid = config_parameter_names();
  for (const char* k : {"samples", "release-dist", "grid"}) valid.emplace_back(k);
  for (auto&& [k, node] : tbl) {
    const std::string key = canonical_key(std::string(k.str()));
    if (key == "grid" || key == "params") {
      const toml::table* inner = node.as_table();
      if (inner == nullptr) {
        throw UsageError("invalid " + key + " in config '" + file + "': expected a table [" + key + "]; " +
                         sweep_config_layout);
      }
      for (auto&& [ik, inode] : *inner) {
        const std::string ikey = canonical_key(std::string(ik.str()));
        if (!is_parameter(ikey)) {
          const auto s = nearest(ikey, config_parameter_names());
          throw UsageError("invalid key '" + std::string(ik.str()) + "' in [" + key + "] of config '" + file + "'" +
                           (s ? " (did you mean '" + *s + "'?)" : "") + ": [" + key +
                           "] holds model parameters only; " + sweep_config_layout);
        }
        set_parameter_text(ikey, inode);
      }
    } else if (key == "samples") {
      config.samples = toml_value_text(key, node, file);
    } else if (key == "release-dist") {
      config.release_dist = toml_value_text(key, node, file);
    } else if (is_parameter(key)) {
      set_parameter_text(key, node);
    } else {
      const auto s = nearest(key, valid);
      throw UsageError("invalid key '" + std::string(k.str()) + "' in config '" + file + "'" +
                       (s ? " (did you mean '" + *s + "'?)" : "") + ": " + sweep_config_layout);
    }
  }
  return config;
}

}  // namespace funnel::cli
