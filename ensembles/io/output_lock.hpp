#pragma once
// An advisory lock on a run's output, and so on its checkpoint: "<output>.lock", held (flock)
// from the creation of the output's temporary until the run ends, and then removed. A second run
// or resume to the same output is refused at once, naming the process that holds it, so that it
// can neither replace the first run's file nor remove its checkpoint. The kernel releases the
// lock of a killed process; the file it leaves is taken over by the next run.
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
