#include "ensembles/program/progress.hpp"

#include <cstdio>
#include <ostream>

namespace qmaps {
namespace {
constexpr double redraw_interval = 0.25;  // seconds
}

Progress::Progress(bool show, std::ostream& log, std::size_t orbits, long long first,
                   long long last)
    : show_(show), log_(log), orbits_(static_cast<double>(orbits)), first_(first), last_(last),
      t0_(Clock::now()) {}

double Progress::seconds() const {
  return std::chrono::duration<double>(Clock::now() - t0_).count();
}

void Progress::update(long long step) {
  if (!show_) return;
  const double t = seconds();
  if (drawn_ >= 0 && t - drawn_ < redraw_interval && step < last_) return;
  drawn_ = t;
  const double done = static_cast<double>(step - first_);
  const double todo = static_cast<double>(last_ - first_);
  const double fraction = todo > 0 ? done / todo : 1.0;
  char line[200];
  if (done > 0 && t > 0)
    std::snprintf(line, sizeof line,
                  "\rqmaps: step %lld of %lld  %5.1f%%  %.3g particle-steps/s  %.1f s elapsed  "
                  "ETA %.1f s ",
                  step, last_, 100 * fraction, orbits_ * done / t, t, t * (todo - done) / done);
  else
    std::snprintf(line, sizeof line, "\rqmaps: step %lld of %lld  %5.1f%%  %.1f s elapsed ", step,
                  last_, 100 * fraction, t);
  log_ << line << std::flush;
}

void Progress::end() {
  if (show_ && drawn_ >= 0) log_ << '\n';
}

}  // namespace qmaps
