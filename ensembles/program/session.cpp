#include "ensembles/program/session.hpp"

#include <unistd.h>

#include <cstdio>
#include <vector>

#include "core/runner.hpp"
#include "ensembles/io/ranks.hpp"
#include "ensembles/program/progress.hpp"

namespace qmaps {

Stepped step_session(std::span<const SessionPart> parts, SegmentLoop::Aim aim,
                     long long checkpoint_every, std::size_t orbits, const SessionOptions& session,
                     const InterruptGuard& interrupt, std::ostream& log,
                     const std::function<void(long long step)>& between) {
  const Run& first = parts.front().run;
  const long long from = parts.front().ensemble.step;
  Progress progress(!session.quiet && ranks::root() && isatty(STDERR_FILENO), log, orbits, from,
                    first.plan.total);
  std::vector<Observers> blanks;
  for (const SessionPart& p : parts) blanks.push_back(p.run.observers.empty_copy());
  const SegmentLoop segments{first.plan, aim,       checkpoint_every,
                             progress,   interrupt, session.on_segment};
  const int signal = segments.run(
      from,
      [&](const RunPlan& segment) {
        std::vector<Observers> samples;
        std::vector<RunPart> work;
        for (const Observers& blank : blanks) samples.push_back(blank.empty_copy());
        for (std::size_t k = 0; k < parts.size(); ++k)
          work.push_back({parts[k].run.model.get(), &parts[k].ensemble,
                          parts[k].run.observers.empty() ? nullptr : &samples[k]});
        advance_parts(work, segment, first.x);
        for (std::size_t k = 0; k < parts.size(); ++k)
          if (!parts[k].run.observers.empty()) parts[k].run.observers.merge(std::move(samples[k]));
      },
      between);
  progress.end();
  return {signal, progress.seconds()};
}

std::string summary_line(const Run& first, std::size_t points, std::size_t orbits, long long steps,
                         double seconds, long long escaped, long long rejected) {
  const double rate = static_cast<double>(orbits) * static_cast<double>(steps) /
                      (seconds > 0 ? seconds : 1e-300);
  const int n = ranks::count();
  const Execution& x = first.x;
  const std::string workers = (n > 1 ? std::to_string(n) + " ranks x " : std::string()) +
                              std::to_string(x.threads) + " thread" + (x.threads == 1 ? "" : "s") +
                              (n > 1 ? " each" : "");
  const std::string sweep = points > 0 ? "sweep of " + std::to_string(points) + " points, " : "";
  char line[512];
  std::snprintf(line, sizeof line,
                "qmaps: %s, %s%zu orbits x %lld steps in %.3f s (%.3g particle-steps/s, %s, %s), "
                "%lld escaped%s -> %s\n",
                std::string(first.model->name()).c_str(), sweep.c_str(), orbits, steps, seconds,
                rate, std::string(isa_name(x.isa)).c_str(), workers.c_str(), escaped,
                first.rejects_points ? (", " + std::to_string(rejected) + " rejected").c_str() : "",
                first.path.c_str());
  std::string out = line;
  if (const auto wider = missing_wider_isa(); wider && x.isa == best_isa())
    out += "qmaps: this CPU has " + std::string(isa_name(*wider)) +
           ", which this binary was built without: it ran " + std::string(isa_name(x.isa)) +
           " (bash tools/setup on this machine builds it)\n";
  return out;
}

}  // namespace qmaps
