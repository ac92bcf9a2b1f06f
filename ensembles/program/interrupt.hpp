#pragma once
// SIGINT, SIGTERM and SIGHUP during a run: the handler only records the first, which the run
// reads between segments (where it writes a checkpoint and stops), and the start-up's long loops
// read through stop_if_interrupted (where there is nothing to keep yet). A second signal ends the
// process at once. Guards may overlap (runs in several threads): a signal under any of them
// stops every one, and the last to end restores the handlers found before the first.
#include <string>

#include "core/error.hpp"

namespace qmaps {

class InterruptGuard {
 public:
  InterruptGuard();   // installs the handlers
  ~InterruptGuard();  // restores the previous ones
  InterruptGuard(const InterruptGuard&) = delete;
  InterruptGuard& operator=(const InterruptGuard&) = delete;
  bool requested() const;  // a signal arrived since construction
  int signal() const;      // which one (0: none)
  // `sig` as a message names it: signal_name(sig), except a SIGTERM that this process, started by
  // mpirun, had from its parent (mpirun, or its daemon on another node). mpirun sends every rank
  // SIGTERM for a SIGINT and a SIGTERM alike, so the message says that it came from mpirun.
  std::string named(int sig) const;
};

const char* signal_name(int sig);  // "SIGINT", "SIGTERM", "SIGHUP"

// A signal during the start-up (drawing or enumerating the initial conditions): nothing is
// written; main reports it and ends the process by that signal.
class Interrupted : public Error {
 public:
  Interrupted(int sig, const std::string& doing,
              const std::string& outcome = "stopped before the run began; nothing was written");
  int signal() const { return signal_; }

 private:
  int signal_;
};

// Throws Interrupted if a signal arrived under an InterruptGuard; cheap enough for every draw.
void stop_if_interrupted(
    const char* doing,
    const char* outcome = "stopped before the run began; nothing was written");

// The start-up's stop check (ensembles/kinds' StopCheck): stop_if_interrupted.
inline void stop_on_signal(const char* doing) { stop_if_interrupted(doing); }

// A signal the run sends itself on reaching a step, so that an interruption can be reproduced
// exactly: QMAPS_SIGNAL_AT_STEP="STEP:NAME" (NAME: INT, TERM, HUP or KILL), see docs/cli.md.
class SelfSignal {
 public:
  static SelfSignal from_environment();  // none when unset; a malformed value is a usage error
  // The end of a segment from `first` to at most `last` that stops at the step, if it lies between.
  long long segment_end(long long first, long long last) const;
  void deliver_if_due(long long step);  // raises the signal once the run is at the step

 private:
  long long step_ = -1;  // -1: none
  int signal_ = 0;
};

}  // namespace qmaps
