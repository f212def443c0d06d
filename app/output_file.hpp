// Writing --out safely: regular files are replaced atomically, anything else is written through.
#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

namespace funnel::cli {

/// A failure to write an output (a full disk, a closed pipe, a device that refuses the data):
/// reported as "funnel: error: <message>" with exit code 1 (bad input is exit code 2).
class OutputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// What an --out path names once its symbolic links are followed.
struct OutputTarget {
  /// How the data reaches the target.
  enum class Kind {
    Replace,  ///< a regular file, or none yet: written to a temporary file beside it, then renamed onto it
    Stream,   ///< a device, FIFO or socket: opened and written through, never replaced
    Fd,       ///< standard output ("-", "/dev/stdout") or another open descriptor (/dev/fd/N)
  };
  Kind kind = Kind::Replace;
  std::string path;  ///< the final target (symbolic links followed); empty for Fd
  int fd = 1;        ///< the descriptor, for Fd
  /// True for a regular file (or a new one): the only kind that can hold side files (.partial, .json).
  bool regular() const { return kind == Kind::Replace; }
};

/// Follows the symbolic links of `path` ("-" is standard output); throws UsageError for an empty
/// path, a directory, a missing or unwritable directory, a link loop, an unwritable target, or a
/// file name too long for its temporary file (".tmp.XXXXXX" added), or for a side file of
/// `side_suffix` characters more (a sweep's ".partial") and that side file's temporary file.
OutputTarget resolve_output(const std::string& path, std::size_t side_suffix = 0);

/// A file the run reads, which --out must not replace: the option that names it and its path
/// (empty: none given).
struct InputFile {
  std::string option;
  std::string path;
};

/// Throws UsageError when --out `out`, resolved to `t`, is one of `inputs` (the same file under
/// any name): the output would silently replace the run's own input.
void check_not_input(const std::string& out, const OutputTarget& t, const std::vector<InputFile>& inputs);

/// Checks before any work that `path` can be written (see resolve_output) and is none of
/// `inputs`; throws UsageError.
void check_writable(const std::string& path, const std::vector<InputFile>& inputs = {});

/// Writes `content` to `path`: a regular file (or a new one, also through a symbolic link) via a
/// temporary file in the target's directory and a rename, so that no partial file is ever left
/// and its permissions are kept; a device, FIFO or standard output ("-", "/dev/stdout") is
/// written through. Throws UsageError for a bad path, OutputError if writing fails.
void write_output(const std::string& path, const std::string& content);

}  // namespace funnel::cli
