#pragma once
// One session of a run or a sweep (a run is a sweep of one part), as qmaps run, qmaps-mpi and
// the Python module go through it: the parts stepped together in segments (segments.hpp), each
// segment's samples into empty observers merged into the part's run (the points so far neither
// copied nor sorted per segment), the progress line, signals and the caller's callback; then the
// summary line.
#include <cstddef>
#include <functional>
#include <iosfwd>
#include <span>
#include <string>

#include "core/ensemble.hpp"
#include "ensembles/program/commands.hpp"
#include "ensembles/program/interrupt.hpp"
#include "ensembles/program/run_setup.hpp"
#include "ensembles/program/segments.hpp"

namespace qmaps {

struct SessionPart {
  Run& run;
  Ensemble& ensemble;
};

struct Stepped {
  int signal = 0;  // the signal that stopped the session; 0: it reached the last step
  double seconds = 0;  // stepping and observing
};

// Steps every part from its ensemble's step to the last, on the first part's plan and path.
// After each segment that ends short of the last step and unstopped, between(step) (a run's
// checkpoint, at multiples of checkpoint_every). `orbits` is what the progress line counts.
Stepped step_session(std::span<const SessionPart> parts, SegmentLoop::Aim aim,
                     long long checkpoint_every, std::size_t orbits, const SessionOptions& session,
                     const InterruptGuard& interrupt, std::ostream& log,
                     const std::function<void(long long step)>& between = [](long long) {});

// "qmaps: <map>, [sweep of <points> points, ]<orbits> orbits x <steps> steps in <s> s (<rate>
// particle-steps/s, <path>, [<ranks> ranks x ]<threads> threads[ each]), <escaped>
// escaped[, <rejected> rejected] -> <file>": points 0 for a run.
std::string summary_line(const Run& first, std::size_t points, std::size_t orbits, long long steps,
                         double seconds, long long escaped, long long rejected);

}  // namespace qmaps
