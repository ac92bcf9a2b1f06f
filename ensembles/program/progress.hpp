#pragma once
// The progress line of a run on a terminal: percent done, particle-steps/s, elapsed time and the
// time left, redrawn at most a few times per second.
#include <chrono>
#include <cstddef>
#include <iosfwd>

namespace qmaps {

class Progress {
 public:
  // Steps first..last of `orbits` orbits; shown on `log` only when `show`.
  Progress(bool show, std::ostream& log, std::size_t orbits, long long first, long long last);
  void update(long long step);  // the ensemble is at `step`
  void end();                   // ends the line (when one was drawn)
  double seconds() const;       // since construction

 private:
  using Clock = std::chrono::steady_clock;
  bool show_;
  std::ostream& log_;
  double orbits_;
  long long first_, last_;
  Clock::time_point t0_;
  double drawn_ = -1;  // when the line was last drawn (seconds), < 0: never
};

}  // namespace qmaps
