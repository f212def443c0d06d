// Reading `--geometry FILE.toml` (docs/cli.md, "Geometry files").
#include "geometry_file.hpp"

#include <toml++/toml.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <vector>

#include "cli_common.hpp"
#include "suggest.hpp"

namespace funnel::cli {

const char* const geometry_layout =
    "a geometry file holds [left] and [right] tables, each with vertices = [[x, y], ...] (the wall's surface "
    "from its top down to its lower end, units of H, x to the right, y up) and optional e, mu, beta0; or "
    "mirror = true and [left] only (the right wall is its mirror image x -> -x); optional bottom = Y (the "
    "height release-height is measured from; default the higher lower end)";

namespace {

[[noreturn]] void fail(const std::string& file, const std::string& what) {
  throw UsageError("invalid geometry = '" + file + "': " + what + "; " + geometry_layout);
}

std::string read_file(const std::string& file) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status st = fs::status(file, ec);
  if (!fs::exists(st)) throw UsageError("invalid geometry = '" + file + "': no such file");
  if (fs::is_directory(st)) fail(file, "is a directory, not a TOML file");
  std::ifstream in(file, std::ios::binary);
  if (!in) throw UsageError("invalid geometry = '" + file + "': cannot be read: " + std::strerror(errno));
  std::stringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

std::optional<double> number_of(const toml::node& node) {
  if (const auto v = node.value<double>()) return *v;  // floating point, or an integer converted
  return std::nullopt;
}

std::vector<Vec2> vertices_of(const std::string& file, const std::string& key, const toml::node& node) {
  const toml::array* list = node.as_array();
  if (list == nullptr) fail(file, key + " is not an array of [x, y] pairs");
  std::vector<Vec2> out;
  for (std::size_t k = 0; k < list->size(); ++k) {
    const toml::array* pair = (*list)[k].as_array();
    std::optional<double> x, y;
    if (pair != nullptr && pair->size() == 2) {
      x = number_of((*pair)[0]);
      y = number_of((*pair)[1]);
    }
    if (!x || !y) fail(file, key + "[" + std::to_string(k) + "] is not a pair of numbers [x, y]");
    out.push_back({*x, *y});
  }
  return out;
}

WallSpec side_of(const std::string& file, const std::string& name, const toml::node& node) {
  const toml::table* tbl = node.as_table();
  if (tbl == nullptr) fail(file, name + " is not a table [" + name + "]");
  WallSpec side;
  const std::vector<std::string> keys{"vertices", "e", "mu", "beta0"};
  for (auto&& [k, value] : *tbl) {
    const std::string key(k.str());
    if (key == "vertices") {
      side.vertices = vertices_of(file, name + ".vertices", value);
      continue;
    }
    std::optional<double>* slot = key == "e" ? &side.e : key == "mu" ? &side.mu : key == "beta0" ? &side.beta0 : nullptr;
    if (slot == nullptr) {
      const auto s = nearest(key, keys);
      fail(file, "unknown key '" + key + "' in [" + name + "]" + (s ? " (did you mean '" + *s + "'?)" : ""));
    }
    *slot = number_of(value);
    if (!*slot) fail(file, name + "." + key + " is not a number");
  }
  return side;
}

}  // namespace

std::shared_ptr<const ProfileSpec> read_geometry(const std::string& file) {
  return parse_geometry(read_file(file), file);
}

std::shared_ptr<const ProfileSpec> parse_geometry(const std::string& text, const std::string& file) {
  toml::table tbl;
  try {
    tbl = toml::parse(text, file);
  } catch (const toml::parse_error& err) {
    const auto& at = err.source().begin;
    throw UsageError("invalid geometry = '" + file + "': line " + std::to_string(at.line) + ", column " +
                     std::to_string(at.column) + ": " + std::string(err.description()));
  }
  std::optional<WallSpec> left, right;
  bool mirror = false;
  std::optional<double> bottom;
  const std::vector<std::string> keys{"left", "right", "mirror", "bottom"};
  for (auto&& [k, node] : tbl) {
    const std::string key(k.str());
    if (key == "left") {
      left = side_of(file, "left", node);
    } else if (key == "right") {
      right = side_of(file, "right", node);
    } else if (key == "mirror") {
      const auto b = node.value<bool>();
      if (!b) fail(file, "mirror is not true or false");
      mirror = *b;
    } else if (key == "bottom") {
      bottom = number_of(node);
      if (!bottom) fail(file, "bottom is not a number");
    } else {
      const auto s = nearest(key, keys);
      fail(file, "unknown key '" + key + "'" + (s ? " (did you mean '" + *s + "'?)" : ""));
    }
  }
  auto spec = std::make_shared<ProfileSpec>();
  try {
    *spec = assemble_profile(left, right, mirror);
  } catch (const std::invalid_argument& err) {
    fail(file, err.what());
  }
  spec->bottom = bottom;
  spec->source = file;
  return spec;
}

}  // namespace funnel::cli
