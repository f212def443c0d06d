// Edit distances and the messages for misspelt subcommands and options.
#include "suggest.hpp"

#include <algorithm>
#include <cctype>
#include <climits>

namespace funnel::cli {

namespace {

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string strip_dashes(const std::string& s) { return s.substr(std::min(s.find_first_not_of('-'), s.size())); }

const CLI::App* find_subcommand(const CLI::App& app, const std::string& name) {
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; })) {
    if (sub->get_name() == name) return sub;
  }
  return nullptr;
}

std::vector<std::string> subcommand_names(const CLI::App& app) {
  std::vector<std::string> names;
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; })) names.push_back(sub->get_name());
  return names;
}

/// The names of the options --help lists (hidden ones are accepted but not suggested).
std::vector<std::string> visible_option_names(const CLI::App& app) {
  std::vector<std::string> names;
  for (const CLI::Option* opt : app.get_options()) {
    if (opt->get_group().empty()) continue;
    for (const std::string& n : opt->get_lnames()) names.push_back("--" + n);
    for (const std::string& n : opt->get_snames()) names.push_back("-" + n);
  }
  return names;
}

/// An option-like word: "-x" or "--xyz", but not a negative number or range ("-5", "-0.5:0.5:0.1").
bool looks_like_option(const std::string& t) {
  if (t.size() < 2 || t[0] != '-') return false;
  const char c = t[1];
  return !(std::isdigit(static_cast<unsigned char>(c)) || c == '.');
}

std::string join(const std::vector<std::string>& words) {
  std::string s;
  for (const std::string& w : words) s += (s.empty() ? "" : ", ") + w;
  return s;
}

}  // namespace

int edit_distance(const std::string& a, const std::string& b) {
  const std::size_t n = a.size(), m = b.size();
  std::vector<std::vector<int>> d(n + 1, std::vector<int>(m + 1, 0));
  for (std::size_t i = 0; i <= n; ++i) d[i][0] = static_cast<int>(i);
  for (std::size_t j = 0; j <= m; ++j) d[0][j] = static_cast<int>(j);
  for (std::size_t i = 1; i <= n; ++i) {
    for (std::size_t j = 1; j <= m; ++j) {
      const int cost = a[i - 1] == b[j - 1] ? 0 : 1;
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  }
  return d[n][m];
}

std::optional<std::string> nearest(const std::string& word, const std::vector<std::string>& candidates) {
  const std::string w = lower(strip_dashes(word));
  if (w.empty()) return std::nullopt;
  const int threshold = std::max(1, static_cast<int>(w.size()) / 3);
  std::optional<std::string> best;
  int best_d = INT_MAX;
  for (const std::string& c : candidates) {
    const std::string lc = lower(strip_dashes(c));
    int d = edit_distance(w, lc);
    if (w.size() >= 3 && lc.size() > w.size() && lc.compare(0, w.size(), w) == 0) d = std::min(d, 1);  // a prefix
    if (d < best_d) {
      best_d = d;
      best = c;
    }
  }
  if (best_d > threshold) return std::nullopt;
  return best;
}

std::optional<std::string> explain_unknown(const CLI::App& app, int argc, const char* const* argv) {
  if (argc < 2) return std::nullopt;
  const std::string first = argv[1];
  if (looks_like_option(first)) {
    const std::string name = first.substr(0, first.find('='));
    if (app.get_option_no_throw(name) != nullptr) return std::nullopt;
    return "unknown option '" + name + "' for 'funnel': the options follow a subcommand, as in 'funnel ensemble " +
           name + " ...'\nRun 'funnel --help' for the subcommands.";
  }
  const CLI::App* sub = find_subcommand(app, first);
  if (sub == nullptr) {
    const std::vector<std::string> names = subcommand_names(app);
    if (const auto s = nearest(first, names)) {
      return "unknown subcommand '" + first + "'; did you mean '" + *s + "'?\nRun 'funnel " + *s +
             " --help' for its options.";
    }
    return "unknown subcommand '" + first + "'; valid subcommands are " + join(names) +
           "\nRun 'funnel --help' for what each does.";
  }
  for (int j = 2; j < argc; ++j) {
    const std::string token = argv[j];
    if (token == "--") break;
    if (!looks_like_option(token)) continue;
    const std::string name = token.substr(0, token.find('='));
    if (sub->get_option_no_throw(name) != nullptr) continue;
    const auto s = nearest(name, visible_option_names(*sub));
    return "unknown option '" + name + "' for 'funnel " + sub->get_name() + "'" +
           (s ? "; did you mean '" + *s + "'?" : "") + "\nRun 'funnel " + sub->get_name() + " --help' for its options.";
  }
  return std::nullopt;
}

std::string help_hint(const CLI::App& app, int argc, const char* const* argv) {
  if (argc >= 2) {
    if (const CLI::App* sub = find_subcommand(app, argv[1])) {
      return "Run 'funnel " + sub->get_name() + " --help' for its options.";
    }
  }
  return "Run 'funnel --help' for the subcommands.";
}

}  // namespace funnel::cli
