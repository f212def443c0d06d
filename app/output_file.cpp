// Output files: atomic replacement of regular files, write-through for devices, FIFOs and stdout.
#include "output_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <optional>

#include "cli_common.hpp"

namespace funnel::cli {

namespace {

/// Symbolic links followed before giving up, as the kernel does (MAXSYMLINKS).
constexpr int max_links = 40;

std::string error_text(int err) { return std::strerror(err); }

/// The descriptor a path names without being a file: "-", /dev/stdout, /dev/fd/N, /proc/self/fd/N.
/// Writing to the descriptor itself keeps the shell's redirection (its offset, its append mode).
std::optional<int> descriptor_alias(const std::string& path) {
  if (path.empty() || path == "-" || path == "/dev/stdout") return 1;
  if (path == "/dev/stderr") return 2;
  const std::string prefixes[] = {"/dev/fd/", "/proc/self/fd/", "/proc/" + std::to_string(getpid()) + "/fd/"};
  for (const std::string& prefix : prefixes) {
    if (path.size() > prefix.size() && path.compare(0, prefix.size(), prefix) == 0 && path.size() - prefix.size() <= 6 &&
        path.find_first_not_of("0123456789", prefix.size()) == std::string::npos) {
      return std::stoi(path.substr(prefix.size()));
    }
  }
  return std::nullopt;
}

std::string parent_of(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  if (slash == std::string::npos) return ".";
  if (slash == 0) return "/";
  return path.substr(0, slash);
}

/// What `--out` accepts, said after each refusal of a path.
constexpr const char* valid_out = "; valid values are a file path in an existing, writable directory, or - for standard output";

/// "'out.csv'", or "'link.csv' (a link to 'data/out.csv')" when the target differs.
std::string describe(const std::string& path, const std::string& target) {
  std::string s = "'" + path + "'";
  if (!target.empty() && target != path) s += " (a link to '" + target + "')";
  return s;
}

void check_directory(const std::string& path, const std::string& target) {
  const std::string dir = parent_of(target);
  struct stat st {};
  if (stat(dir.c_str(), &st) != 0 || !S_ISDIR(st.st_mode)) {
    throw UsageError("invalid out = " + describe(path, target) + ": directory '" + dir + "' does not exist" + valid_out);
  }
  if (access(dir.c_str(), W_OK) != 0) {
    throw UsageError("invalid out = " + describe(path, target) + ": directory '" + dir + "' is not writable" + valid_out);
  }
}

/// Writes all of `content` to `fd`; returns 0 or the errno of the failure.
int write_all(int fd, const std::string& content) {
  std::size_t done = 0;
  while (done < content.size()) {
    const ssize_t n = ::write(fd, content.data() + done, content.size() - done);
    if (n < 0) {
      if (errno == EINTR) continue;
      return errno;
    }
    done += static_cast<std::size_t>(n);
  }
  return 0;
}

/// A regular file: a temporary file in the same directory (so the rename is atomic), flushed to
/// disk, with the permissions of the file it replaces (or the umask's for a new one).
void replace_file(const std::string& path, const std::string& target, const std::string& content) {
  mode_t mode = 0;
  struct stat st {};
  if (stat(target.c_str(), &st) == 0) {
    mode = st.st_mode & 07777;
  } else {
    const mode_t mask = umask(0);
    umask(mask);
    mode = 0666 & ~mask;
  }
  std::string tmp = target + ".tmp.XXXXXX";
  const int fd = mkostemp(tmp.data(), O_CLOEXEC);
  if (fd < 0) {
    throw OutputError("cannot create a temporary file beside " + describe(path, target) + ": " + error_text(errno));
  }
  int err = fchmod(fd, mode) != 0 ? errno : 0;
  if (err == 0) err = write_all(fd, content);
  if (err == 0 && fsync(fd) != 0) err = errno;
  if (close(fd) != 0 && err == 0) err = errno;
  if (err == 0 && std::rename(tmp.c_str(), target.c_str()) != 0) err = errno;
  if (err != 0) {
    unlink(tmp.c_str());
    throw OutputError("cannot write " + describe(path, target) + ": " + error_text(err));
  }
}

/// The temporary file's suffix (replace_file).
constexpr std::size_t temporary_suffix = sizeof(".tmp.XXXXXX") - 1;

/// Refuses, before any work, a file name that fits but whose temporary file's name (or a side
/// file's) would not: the run would otherwise end in "File name too long" after its work.
void check_name_length(const std::string& path, const std::string& target, std::size_t side_suffix) {
  const std::string dir = parent_of(target);
  const std::size_t slash = target.find_last_of('/');
  const std::size_t name = target.size() - (slash == std::string::npos ? 0 : slash + 1);
  const long limit = pathconf(dir.c_str(), _PC_NAME_MAX);
  const std::size_t max_name = limit > 0 ? static_cast<std::size_t>(limit) : 255;
  const std::size_t room = temporary_suffix + side_suffix;
  if (name + room > max_name) {
    throw UsageError("invalid out = " + describe(path, target) + ": a file name of " + std::to_string(name) +
                     " characters; valid range is at most " + std::to_string(max_name > room ? max_name - room : 0) +
                     " characters (" + std::to_string(max_name) + " in this directory, less " + std::to_string(room) +
                     " for the " + (side_suffix > 0 ? "side and temporary files" : "temporary file") + " written beside it)");
  }
}

}  // namespace

OutputTarget resolve_output(const std::string& path, std::size_t side_suffix) {
  // `--out ""` is not "no --out": it names no file (standard output is `-`).
  if (path.empty()) throw UsageError("invalid out = '': an empty path; valid values are a file path, or - for standard output");
  OutputTarget t;
  std::string cur = path;
  for (int links = 0;; ++links) {
    if (const auto fd = descriptor_alias(cur)) {
      // Checked before any work: a closed descriptor was found only when the result was written.
      const int flags = fcntl(*fd, F_GETFL);
      const std::string name = *fd == 1 ? "standard output" : "descriptor " + std::to_string(*fd);
      if (flags < 0) {
        throw UsageError("invalid out = '" + path + "': " + name + " is not open; valid values are a file path, or - "
                         "for an open standard output");
      }
      if ((flags & O_ACCMODE) == O_RDONLY) {
        throw UsageError("invalid out = '" + path + "': " + name + " is open for reading only");
      }
      t.kind = OutputTarget::Kind::Fd;
      t.fd = *fd;
      return t;
    }
    struct stat st {};
    if (lstat(cur.c_str(), &st) != 0) {
      if (errno != ENOENT) throw UsageError("invalid out = " + describe(path, cur) + ": " + error_text(errno));
      check_directory(path, cur);  // a new file
      check_name_length(path, cur, side_suffix);
      t.path = cur;
      return t;
    }
    if (S_ISLNK(st.st_mode)) {
      if (links == max_links) throw UsageError("invalid out = '" + path + "': too many levels of symbolic links");
      std::string link(static_cast<std::size_t>(st.st_size > 0 ? st.st_size : 4096) + 1, '\0');
      const ssize_t n = readlink(cur.c_str(), link.data(), link.size());
      if (n < 0) throw UsageError("invalid out = " + describe(path, cur) + ": " + error_text(errno));
      link.resize(static_cast<std::size_t>(n));
      cur = (link.front() == '/' || parent_of(cur) == ".") ? link : parent_of(cur) + "/" + link;
      continue;
    }
    if (S_ISDIR(st.st_mode)) throw UsageError("invalid out = " + describe(path, cur) + ": is a directory" + valid_out);
    if (S_ISREG(st.st_mode)) {
      check_directory(path, cur);
      if (access(cur.c_str(), W_OK) != 0) throw UsageError("invalid out = " + describe(path, cur) + ": is not writable" + valid_out);
      check_name_length(path, cur, side_suffix);
      t.path = cur;
      return t;
    }
    // A device, FIFO or socket: written through, never replaced.
    if (access(cur.c_str(), W_OK) != 0) throw UsageError("invalid out = " + describe(path, cur) + ": is not writable" + valid_out);
    t.kind = OutputTarget::Kind::Stream;
    t.path = cur;
    return t;
  }
}

void check_not_input(const std::string& out, const OutputTarget& t, const std::vector<InputFile>& inputs) {
  if (!t.regular()) return;
  for (const InputFile& in : inputs) {
    std::error_code ec;
    if (!in.path.empty() && std::filesystem::equivalent(t.path, in.path, ec) && !ec) {
      throw UsageError("invalid out = '" + out + "': it is the --" + in.option + " file '" + in.path +
                       "', which the output would replace; valid values are a file other than the run's inputs");
    }
  }
}

void check_writable(const std::string& path, const std::vector<InputFile>& inputs) {
  check_not_input(path, resolve_output(path), inputs);
}

void write_output(const std::string& path, const std::string& content) {
  const OutputTarget t = resolve_output(path);
  switch (t.kind) {
    case OutputTarget::Kind::Replace:
      replace_file(path, t.path, content);
      return;
    case OutputTarget::Kind::Stream: {
      // Blocks until a FIFO has a reader, as a shell redirection does.
      const int fd = open(t.path.c_str(), O_WRONLY | O_NOCTTY | O_CLOEXEC);
      if (fd < 0) throw OutputError("cannot open " + describe(path, t.path) + ": " + error_text(errno));
      int err = write_all(fd, content);
      if (close(fd) != 0 && err == 0) err = errno;
      if (err != 0) throw OutputError("cannot write " + describe(path, t.path) + ": " + error_text(err));
      return;
    }
    case OutputTarget::Kind::Fd: {
      std::cout.flush();
      std::fflush(stdout);
      if (const int err = write_all(t.fd, content); err != 0) {
        const std::string name = t.fd == 1 ? "standard output" : "descriptor " + std::to_string(t.fd);
        throw OutputError("cannot write to " + name + (path.empty() || path == "-" ? "" : " ('" + path + "')") +
                          ": " + error_text(err));
      }
      return;
    }
  }
}

}  // namespace funnel::cli
