#include "ensembles/program/segments.hpp"

#include <algorithm>
#include <cstdint>

#include "ensembles/io/ranks.hpp"

namespace qmaps {

int SegmentLoop::run(long long from, const std::function<void(const RunPlan&)>& advance,
                     const std::function<void(long long)>& between) const {
  SelfSignal self_signal = SelfSignal::from_environment();
  long long length = 1;
  for (long long step = from; step < plan.total;) {
    RunPlan segment = plan;
    segment.first = step;
    segment.last = std::min(plan.total, step + length);
    if (checkpoint_every > 0)
      segment.last = std::min(segment.last, (step / checkpoint_every + 1) * checkpoint_every);
    segment.last = self_signal.segment_end(segment.first, segment.last);
    // the tunes' windows are analysed whole: a segment ends before them or at their end
    if (plan.measure_orbits && plan.tunes.inside(segment.last))
      segment.last = std::min(plan.total, plan.tunes.end());
    const double t = progress.seconds();
    advance(segment);
    const double took = ranks::max(progress.seconds() - t);
    step = segment.last;
    progress.update(step);
    if (on_segment) on_segment(step, plan.total);
    if (step == plan.total) break;
    self_signal.deliver_if_due(step);
    const int signal = static_cast<int>(ranks::max(std::int64_t{interrupt.signal()}));
    if (signal != 0) return signal;
    between(step);
    const bool few = length < aim.least_steps;
    if (took < aim.shortest || (few && took < 2)) length = std::min(2 * length, plan.total);
    else if ((took > aim.longest && length > aim.least_steps) || (took > 8 && length > 1))
      length /= 2;
  }
  return 0;
}

}  // namespace qmaps
