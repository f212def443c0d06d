// Value lists, ranges and Cartesian grids of parameters.
#include "funnel/grid.hpp"

#include <algorithm>
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

/// Decimal places of a number as written ("0.25" 2, "1e-5" 5, "2.5e1" 0, "40" 0), or -1 when
/// the text is not a plain decimal (hexadecimal, "inf", ...).
int decimal_places(std::string_view text) {
  std::size_t i = 0;
  if (i < text.size() && (text[i] == '+' || text[i] == '-')) ++i;
  int digits = 0, fraction = 0;
  for (; i < text.size() && text[i] >= '0' && text[i] <= '9'; ++i) ++digits;
  if (i < text.size() && text[i] == '.') {
    for (++i; i < text.size() && text[i] >= '0' && text[i] <= '9'; ++i) ++fraction;
  }
  if (digits + fraction == 0) return -1;
  int exponent = 0;
  if (i < text.size() && (text[i] == 'e' || text[i] == 'E')) {
    const auto [ptr, ec] = std::from_chars(text.data() + i + 1 + (i + 1 < text.size() && text[i + 1] == '+'),
                                           text.data() + text.size(), exponent);
    if (ec != std::errc()) return -1;
    i = static_cast<std::size_t>(ptr - text.data());
  }
  if (i != text.size() || exponent > 400 || exponent < -400) return -1;
  return std::max(fraction - exponent, 0);
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
    // Each value the nearest double of its decimal when start and step are decimals of p <= 22
    // places: 0.7:0.9:0.1 gives 0.8, not 0.7 + 0.1 = 0.7999999999999999 (a user who looks for
    // e = 0.8 finds it, and the point is the one `--e 0.8` runs). With S = start 10^p and K =
    // step 10^p (integers), (S + i K) / 10^p is that decimal correctly rounded, as long as every
    // numerator is below 2^53 (each then exact) and 10^p is exact (p <= 22).
    const int start_places = decimal_places(parts[0]), step_places = decimal_places(parts[2]);
    const int places = std::max(start_places, step_places);
    double scale = 1.0;
    for (int k = 0; k < places && k < 23; ++k) scale *= 10.0;
    const double s0 = std::round(*start * scale), k0 = std::round(*step * scale);
    const bool decimal = start_places >= 0 && step_places >= 0 && places <= 22 &&
                         std::fabs(s0) + count * std::fabs(k0) < 0x1p53;
    for (int i = 0; i < static_cast<int>(count); ++i) {
      values.push_back(decimal ? (s0 + i * k0) / scale : *start + i * *step);
    }
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
