#pragma once
// SIGINT and SIGTERM during a run: the handler only sets a flag, which the run reads between
// segments (where it writes a checkpoint and stops). A second signal ends the process at once.
namespace qmaps {

class InterruptGuard {
 public:
  InterruptGuard();   // installs the handlers
  ~InterruptGuard();  // restores the previous ones
  InterruptGuard(const InterruptGuard&) = delete;
  InterruptGuard& operator=(const InterruptGuard&) = delete;
  bool requested() const;  // a signal arrived since construction
  int signal() const;      // which one (0: none)
};

}  // namespace qmaps
