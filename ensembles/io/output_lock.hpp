#pragma once
// An advisory lock on a run's output, and so on its checkpoint: "<output>.lock", held (flock)
// from before the output's temporary is created until the run ends, and then removed. A second
// run or resume to the same output is refused at once, naming the process that holds it, so that
// it can neither replace the first run's file nor remove its temporary or its checkpoint. Held,
// it removes the temporaries that dead writers left of the output and of its checkpoint: on a
// shared file system their pids say nothing, the lock does. The kernel releases the lock of a
// killed process; the file it leaves is taken over by the next run.
//
// Before it locks, it checks that the output can be replaced (ensembles/io/files.hpp), so that a
// doomed run makes no lock. The lock file is never written through a link: it is opened without
// following one, and one that is not a regular file of this user with a single name is refused.
#include <string>

namespace qmaps {

class OutputLock {
 public:
  explicit OutputLock(const std::string& output);  // throws Error(io) if another run holds it
  ~OutputLock();
  OutputLock(const OutputLock&) = delete;
  OutputLock& operator=(const OutputLock&) = delete;

 private:
  std::string path_;
  int fd_ = -1;
};

}  // namespace qmaps
