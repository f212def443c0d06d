// The TOML file of `--geometry FILE.toml`: a funnel's two walls as vertex lists (docs/cli.md).
#pragma once

#include <memory>
#include <string>

#include "funnel/funnel.hpp"

namespace funnel::cli {

/// How a geometry file is written, for error messages and --help.
extern const char* const geometry_layout;

/// Reads a geometry file into a profile (not yet checked against the particle: validate() does
/// that with the other parameters). Throws UsageError for a missing or unreadable file, a TOML
/// syntax error (line and column), an unknown key (with the nearest valid one), or a value of
/// the wrong type, naming the key.
std::shared_ptr<const ProfileSpec> read_geometry(const std::string& file);

/// The same for the text of a geometry file; `file` names it in messages.
std::shared_ptr<const ProfileSpec> parse_geometry(const std::string& text, const std::string& file);

}  // namespace funnel::cli
