// Version and build identification of the funnel library.
#pragma once

#include <string_view>

namespace funnel {

/// Semantic version of the library, e.g. "0.1.0".
std::string_view version();
/// Short git commit hash of the source tree at configure time, or "unknown".
std::string_view git_commit();

}  // namespace funnel
