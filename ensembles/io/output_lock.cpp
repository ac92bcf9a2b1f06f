#include "ensembles/io/output_lock.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <string>

#include "core/error.hpp"
#include "ensembles/io/files.hpp"
#include "ensembles/io/checkpoint.hpp"

namespace qmaps {

OutputLock::OutputLock(const std::string& output) : path_(output + ".lock") {
  const auto fail = [&](const std::string& what) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
    throw Error(ExitCode::io, "output '" + output + "': " + what);
  };
  files::check_output_target(output);  // a doomed run makes no lock
  // A lock file removed by its holder between our open and our flock is a stale inode: retry
  // until the file locked is the one under the name.
  for (;;) {
    fd_ = ::open(path_.c_str(), O_RDWR | O_CREAT | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC, 0644);
    if (fd_ < 0 && errno == ELOOP)
      fail("its lock '" + path_ + "' is a symbolic link; qmaps writes no lock through a link: "
           "remove it");
    if (fd_ < 0) fail("cannot create its lock " + files::open_failure(path_, errno));
    struct stat held {};
    if (::fstat(fd_, &held) != 0 || !S_ISREG(held.st_mode) || held.st_uid != ::geteuid() ||
        held.st_nlink != 1)
      fail("its lock '" + path_ + "' is not a regular file of this user with one name; qmaps "
           "writes no lock it does not own: remove it");
    if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
      const int error = errno;
      char pid[32] = {};
      const auto n = ::pread(fd_, pid, sizeof pid - 1, 0);
      if (error == EWOULDBLOCK)
        fail("another qmaps run (process " + std::string(n > 0 ? pid : "?") +
             ") is writing it; its lock is '" + path_ + "'");
      fail("cannot lock '" + path_ + "': " + std::strerror(error));
    }
    struct stat named {};
    if (::lstat(path_.c_str(), &named) == 0 && held.st_dev == named.st_dev &&
        held.st_ino == named.st_ino)
      break;
    ::close(fd_);
  }
  const std::string pid = std::to_string(::getpid());
  if (::ftruncate(fd_, 0) != 0 || ::pwrite(fd_, pid.data(), pid.size(), 0) < 0) {
    // The pid only helps the message of a second run; the lock holds without it.
  }
  files::remove_stale_temporaries(output);
  files::remove_stale_temporaries(output + checkpoint_suffix);
}

OutputLock::~OutputLock() {
  if (fd_ < 0) return;
  ::unlink(path_.c_str());  // while held: a waiting run then locks a stale inode and retries
  ::close(fd_);
}

}  // namespace qmaps
