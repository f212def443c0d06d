// "Did you mean ...?": the nearest valid word for a misspelt subcommand, option or key.
#pragma once

#include <CLI/CLI.hpp>

#include <optional>
#include <string>
#include <vector>

namespace funnel::cli {

/// Optimal string alignment distance: insertions, deletions, substitutions and transpositions
/// of adjacent characters each cost 1 ("trajectroy" is 1 from "trajectory").
int edit_distance(const std::string& a, const std::string& b);

/// The candidate nearest to `word` (case-insensitive) if it is close enough to be a likely typo
/// (at most a third of the word's letters, at least 1, or `word` is its prefix); nullopt otherwise.
std::optional<std::string> nearest(const std::string& word, const std::vector<std::string>& candidates);

/// Explains a command line that `app` refused because of an unknown subcommand or option: names
/// the bad word, suggests the nearest valid one and points to the right --help. nullopt if the
/// command line has no unknown word (the parser's own message is then the right one).
std::optional<std::string> explain_unknown(const CLI::App& app, int argc, const char* const* argv);

/// "Run 'funnel SUB --help' for its options." for the subcommand named in argv, or the same
/// for 'funnel --help' when there is none.
std::string help_hint(const CLI::App& app, int argc, const char* const* argv);

}  // namespace funnel::cli
