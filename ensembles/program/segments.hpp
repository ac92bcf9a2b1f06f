#pragma once
// The segment loop of every run and sweep. The steps are advanced in segments (exact: a segmented
// run equals one call), and a signal is answered at a segment's end. A segment's length is doubled
// or halved to take `shortest` to `longest` seconds: for a run about 0.1 to 0.4 s, since a signal
// waits for the segment's end and mpirun SIGKILLs the ranks 1 s after it passes a SIGTERM on
// (docs/cli.md). But each segment is one more pass over the ensembles' memory (about 10 steps'
// cost for the Suris preset, whatever the orbit count): a segment also takes at least
// `least_steps` steps where that lasts under 2 s (a large ensemble's), and never over 8 s. A sweep,
// which keeps no checkpoint and makes every point's observers afresh each segment, aims at 2 to
// 8 s. A segment also ends at every multiple of `checkpoint_every` (> 0) and where the run signals
// itself (SelfSignal), but never inside the tunes' windows (core/run_plan.hpp: the first segment
// then lasts to their end, and a signal waits for it). Over several ranks, each decision is taken alike on every rank: the longest
// segment sets the next length, a signal on any rank stops them all.
#include <functional>

#include "core/run_plan.hpp"
#include "ensembles/program/interrupt.hpp"
#include "ensembles/program/progress.hpp"

namespace qmaps {

struct SegmentLoop {
  struct Aim {
    double shortest, longest;  // seconds
    long long least_steps;
  };
  static constexpr Aim run_aim{0.1, 0.4, 256}, sweep_aim{2, 8, 1};

  const RunPlan& plan;
  Aim aim;
  long long checkpoint_every;  // 0: none
  Progress& progress;
  const InterruptGuard& interrupt;
  const std::function<void(long long step, long long total)>& on_segment;  // may be empty

  // Advances from step `from` to plan.total, advance(segment) stepping each segment; after each
  // segment that ends short of the last step and unstopped, between(step) (a checkpoint). Returns
  // the signal that stopped it, 0 when it reached the last step.
  int run(long long from, const std::function<void(const RunPlan& segment)>& advance,
          const std::function<void(long long step)>& between) const;
};

}  // namespace qmaps
