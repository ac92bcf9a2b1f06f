#pragma once
// What one call of the runner does: advance an ensemble from step `first` to step `last` of a run
// of `total` steps, sampling at every multiple of `stride` and at step `total`
// (core/sample_schedule.hpp).
#include <cmath>

namespace qmaps {

// The tunes' two windows of `window` steps from step 0 (core/observers/tunes/tunes.hpp; 0: no
// tunes) and their Hann order: a call of the runner never starts or ends strictly inside them.
struct TuneWindows {
  long long window = 0;
  int order = 2;
  long long end() const { return 2 * window; }
  bool inside(long long step) const { return step > 0 && step < end(); }
};

struct RunPlan {
  long long first = 0;
  long long last = 0;
  long long total = 0;
  long long stride = 1;
  double escape_bound = 1e8;      // an orbit escapes when |q| > escape_bound or it is non-finite
  bool measure_orbits = true;
  TuneWindows tunes;

  double escape_bound2() const { return escape_bound * escape_bound; }
};

}  // namespace qmaps
