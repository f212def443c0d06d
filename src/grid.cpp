// Value lists, ranges and Cartesian grids of parameters.
#include "funnel/grid.hpp"

#include <charconv>
#include <cmath>

namespace funnel {

std::optional<double> parse_number(std::string_view text) {
  if (text.empty()) return std::nullopt;
  if (text.front() == '+') text.remove_prefix(1);
  double value = 0.0;
  const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || ptr != text.data() + text.size() || !std::isfinite(value)) return std::nullopt;
  return value;
}

namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

}  // namespace

std::optional<std::vector<double>> parse_values(std::string_view text, std::string& error) {
  text = trim(text);
  std::vector<double> values;
  if (text.find(':') != std::string_view::npos) {
    std::vector<std::string_view> parts;
    std::size_t pos = 0;
    for (;;) {
      const std::size_t colon = text.find(':', pos);
      parts.push_back(trim(text.substr(pos, colon == std::string_view::npos ? colon : colon - pos)));
      if (colon == std::string_view::npos) break;
      pos = colon + 1;
    }
    if (parts.size() != 3) {
      error = "a range is start:stop:step";
      return std::nullopt;
    }
    const auto start = parse_number(parts[0]);
    const auto stop = parse_number(parts[1]);
    const auto step = parse_number(parts[2]);
    if (!start || !stop || !step) {
      error = "a range is start:stop:step with three finite numbers";
      return std::nullopt;
    }
    if (!(*step > 0.0) || *stop < *start) {
      error = "a range start:stop:step needs step > 0 and stop >= start";
      return std::nullopt;
    }
    // Count with a tolerance so that 5:85:0.5 includes 85; values as start + i*step (no drift).
    const double span = (*stop - *start) / *step;
    const double count = std::floor(span + 1e-9) + 1.0;
    if (count > 1e7) {
      error = "a range may have at most 10^7 values";
      return std::nullopt;
    }
    for (int i = 0; i < static_cast<int>(count); ++i) values.push_back(*start + i * *step);
    return values;
  }
  std::size_t pos = 0;
  for (;;) {
    const std::size_t comma = text.find(',', pos);
    const std::string_view item = trim(text.substr(pos, comma == std::string_view::npos ? comma : comma - pos));
    const auto v = parse_number(item);
    if (!v) {
      error = item.empty() ? "empty value in the list" : "'" + std::string(item) + "' is not a finite number";
      return std::nullopt;
    }
    values.push_back(*v);
    if (comma == std::string_view::npos) break;
    pos = comma + 1;
  }
  return values;
}

const std::vector<std::string>& sweep_parameter_names(Space space) {
  const auto names_of = [](Space sp) {
    std::vector<std::string> out;
    for (const ParameterInfo& p : parameters(sp)) {
      if (p.option) out.emplace_back(p.name);
    }
    return out;
  };
  static const std::vector<std::string> two_d = names_of(Space::TwoD), three_d = names_of(Space::ThreeD);
  return space == Space::TwoD ? two_d : three_d;
}

bool set_parameter(Params& params, std::string_view name, double value) {
  const ParameterInfo* p = find_parameter(name);
  if (p == nullptr || !p->option) return false;
  return !set_parameter_checked(params, p->name, value).has_value();
}

double get_parameter(const Params& params, std::string_view name) {
  const ParameterInfo* p = find_parameter(name);
  return p != nullptr ? p->get(params) : std::nan("");
}

double grid_points(const std::vector<Axis>& axes) {
  double points = 1.0;
  for (const Axis& a : axes) points *= static_cast<double>(a.values.size());
  return points;
}

std::vector<Params> expand_grid(const Params& base, const std::vector<Axis>& axes) {
  std::vector<Params> points{base};
  for (const Axis& axis : axes) {
    std::vector<Params> next;
    next.reserve(points.size() * axis.values.size());
    for (const Params& p : points) {
      for (const double v : axis.values) {
        Params q = p;
        set_parameter(q, axis.name, v);
        next.push_back(q);
      }
    }
    points = std::move(next);
  }
  return points;
}

}  // namespace funnel
