#include "ensembles/io/files.hpp"

#include <fcntl.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>

#include "core/error.hpp"

namespace qmaps::files {
namespace {

Error io_error(const std::string& message) { return Error(ExitCode::io, message); }

const char* kind_of(mode_t mode) {
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  if (S_ISLNK(mode)) return "a symbolic link";
  return "not a regular file";
}

std::string folder_of(const std::string& path) {
  const auto slash = path.rfind('/');
  return slash == std::string::npos ? "." : slash == 0 ? "/" : path.substr(0, slash);
}

std::string name_of(const std::string& path) { return path.substr(path.rfind('/') + 1); }

// An open descriptor of the regular file `path`, or an io error; O_NONBLOCK: a FIFO without a
// writer would block the open itself.
int open_regular(const std::string& path, const std::string& what) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  const std::string named = what.empty() ? std::string() : what + " ";
  if (fd < 0) throw io_error("cannot read " + named + open_failure(path, errno));
  struct stat info {};
  if (::fstat(fd, &info) != 0 || !S_ISREG(info.st_mode)) {
    const std::string kind = kind_of(info.st_mode);
    ::close(fd);
    throw io_error(named + "'" + path + "' is " + kind + ", not a regular file");
  }
  return fd;
}

}  // namespace

std::string reason(int error) {
  std::string text = std::strerror(error);
  rlimit limit{};
  if (error == EMFILE && ::getrlimit(RLIMIT_NOFILE, &limit) == 0)
    text += " (the open-file limit, ulimit -n, is " + std::to_string(limit.rlim_cur) + ")";
  return text;
}

std::string open_failure(const std::string& path, int error) {
  return "'" + path + "': " + reason(error);
}

void check_regular_input(const std::string& path, const std::string& what) {
  ::close(open_regular(path, what));
}

std::string read_regular_file(const std::string& path, std::size_t max_bytes,
                              const std::string& what) {
  const int fd = open_regular(path, what);
  std::string text(max_bytes + 1, '\0');
  std::size_t have = 0;
  while (have < text.size()) {
    const ssize_t n = ::read(fd, text.data() + have, text.size() - have);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      const int error = errno;
      ::close(fd);
      throw io_error("cannot read " + what + " " + open_failure(path, error));
    }
    if (n == 0) break;
    have += static_cast<std::size_t>(n);
  }
  ::close(fd);
  if (have > max_bytes)
    throw usage_error(path + ": more than " + std::to_string(max_bytes) + " bytes; a " + what +
                      " may have at most " + std::to_string(max_bytes) + " bytes");
  text.resize(have);
  return text;
}

void check_output_target(const std::string& path) {
  const std::string folder = folder_of(path);
  struct stat info {};
  if (::lstat(path.c_str(), &info) == 0) {
    if (!S_ISREG(info.st_mode))
      throw io_error("output '" + path + "' is " + kind_of(info.st_mode) +
                     "; qmaps replaces only a regular file: name another output");
    struct stat dir {};
    const uid_t me = ::geteuid();
    if (::stat(folder.c_str(), &dir) == 0 && (dir.st_mode & S_ISVTX) && me != 0 &&
        info.st_uid != me && dir.st_uid != me)
      throw io_error("output '" + path + "' belongs to another user (uid " +
                     std::to_string(info.st_uid) + ") in the sticky folder '" + folder +
                     "', where it cannot be replaced: name another output");
  } else if (errno != ENOENT) {
    throw io_error("cannot write output " + open_failure(path, errno));
  }
  if (::access(folder.c_str(), W_OK | X_OK) != 0)
    throw io_error("cannot write '" + path + "': its folder " + open_failure(folder, errno));
}

void remove_stale_temporaries(const std::string& path) {
  const std::string prefix = name_of(path) + ".tmp-";
  const std::string mine = std::to_string(::getpid());
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator(folder_of(path), error)) {
    const std::string name = entry.path().filename().string();
    if (name.size() <= prefix.size() || name.compare(0, prefix.size(), prefix) != 0) continue;
    const std::string digits = name.substr(prefix.size());
    if (digits == mine || !std::all_of(digits.begin(), digits.end(), [](unsigned char c) {
          return std::isdigit(c) != 0;
        }))
      continue;
    std::filesystem::remove(entry.path(), error);  // a link is removed, never what it names
  }
}

}  // namespace qmaps::files
