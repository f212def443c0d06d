// Small helpers shared by the figure computations of `funnel paper`: number formatting, the
// check's verdict, and reading a figure's [check] and [settings] tables.
#pragma once

#include <nlohmann/json.hpp>

#include <cstdio>
#include <string>
#include <vector>

#include "funnel/paper/cases.hpp"
#include "funnel/paper/records.hpp"

namespace funnel::paper {

/// A number with `digits` significant digits, for the checks' sentences.
inline std::string fmt(double x, int digits = 4) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", digits, x);
  return buf;
}

/// {"claim", "measured", "holds"}: what the paper (or the extension) claims and what was found.
inline nlohmann::ordered_json verdict(const std::string& claim, const std::string& measured, bool holds) {
  return {{"claim", claim}, {"measured", measured}, {"holds", holds}};
}

/// The claim text of a figure's [check] table.
inline std::string claim_of(const FigureSpec& fig) { return fig.check["claim"].value_or(std::string()); }

/// A number of a figure's table `table` ("check" or "settings"), or `fallback` when the key is
/// absent; InputError when it is there but not a number (it fell back to the default silently,
/// and a check then "held" against a tolerance nobody gave).
inline double table_number(const FigureSpec& fig, const toml::table& t, const char* table, const char* key,
                           double fallback) {
  const toml::node* node = t.get(key);
  if (node == nullptr) return fallback;
  if (const auto v = node->value<double>()) return *v;
  throw InputError("invalid figure definition '" + fig.source + "': [" + table + "] " + key +
                   " is not a number; valid values are numbers (e.g. " + key + " = " + fmt(fallback) + ")");
}

/// A number of a figure's [check] table, or `fallback`.
inline double check_number(const FigureSpec& fig, const char* key, double fallback) {
  return table_number(fig, fig.check, "check", key, fallback);
}

/// A number of a figure's [settings] table, or `fallback`.
inline double setting(const FigureSpec& fig, const char* key, double fallback) {
  return table_number(fig, fig.settings, "settings", key, fallback);
}

/// One panel per value, labelled "<symbol> = <value><unit>": ids a, b, c, ...
inline nlohmann::ordered_json value_panels(const std::vector<double>& values, const std::string& symbol,
                                           const std::string& unit) {
  nlohmann::ordered_json panels = nlohmann::ordered_json::array();
  for (std::size_t i = 0; i < values.size(); ++i) {
    panels.push_back({{"id", std::string(1, static_cast<char>('a' + i))}, {"label", symbol + " = " + fmt(values[i]) + unit}});
  }
  return panels;
}

}  // namespace funnel::paper
