#include "ensembles/program/sweep_run.hpp"


#include <optional>
#include <ostream>
#include <vector>

#include "core/error.hpp"
#include "ensembles/io/h5.hpp"
#include "core/memory_limit.hpp"
#include "core/thread_limit.hpp"
#include "ensembles/config/map_config.hpp"
#include "ensembles/io/output_lock.hpp"
#include "ensembles/io/sweep_output.hpp"
#include "ensembles/kinds/initial_conditions.hpp"
#include "ensembles/program/interrupt.hpp"
#include "ensembles/program/run_setup.hpp"
#include "ensembles/program/session.hpp"

namespace qmaps {

int run_sweep(RunSpec& spec, const SessionOptions& session, const InterruptGuard& interrupt,
              std::ostream& log) {
  const Sweep& sweep = *spec.sweep;
  const std::string& started = spec.started;
  const std::size_t points = spec.points.size();
  const auto runs = [&](std::size_t k) -> Run& { return spec.points[k].run; };
  const Run& first = runs(0);

  const OutputLock lock(first.path);  // first: a second run to this output is refused
  h5::AtomicFile output(first.path);
  auto file = output.create_hdf5(first.deflate);
  const auto groups = create_sweep_runs(file.root(), points);
  std::vector<Ensemble> ensembles;
  std::uint64_t rejected = 0;
  std::size_t orbits = 0;
  for (std::size_t k = 0; k < points; ++k) {
    Run& r = runs(k);
    ensembles.push_back(r.model->ensemble(r.orbits, r.measured));
    Ensemble& e = ensembles.back();
    const auto initial =
        r.per_orbit ? std::optional(groups[k].create_group("initial")) : std::nullopt;
    if (initial) create_phase(*initial, r.orbits);
    r.rejected = spec.points[k].initial->start(
        *r.model, e, r.start, r.plan.escape_bound,
        [&](std::size_t from, std::span<const Phase> at) {
          if (initial) write_phase_part(*initial, from, at);
        },
        orbits_per_part);
    for (auto& t : r.trajectories) record(t, *r.model, e, r.plan);
    rejected += r.rejected;
    orbits += r.orbits;
  }

  // All points step together in one session (ensembles/program/session.hpp).
  const RunPlan plan = first.plan;
  std::vector<SessionPart> parts;
  for (std::size_t k = 0; k < points; ++k) parts.push_back({runs(k), ensembles[k]});
  const auto [signal, seconds] =
      step_session(parts, SegmentLoop::sweep_aim, 0, orbits, session, interrupt, log);
  if (signal != 0) {
    log << "qmaps: " << signal_name(signal) << " at step " << ensembles.front().step << " of "
        << plan.total << ": a sweep keeps no checkpoint; stopped, nothing was written\n";
    return static_cast<int>(ExitCode::interrupted);
  }
  const std::string finished = utc_now();
  std::vector<RunRecord> records;
  for (std::size_t k = 0; k < points; ++k) {
    runs(k).observers.finish();
    records.push_back(record_of(runs(k), ensembles[k], 0, started, finished, session.command_line));
  }
  naming_failures(first.path, [&] {
    write_sweep(file.root(), sweep, records);
    file.close();
  });
  output.commit();

  long long escaped = 0;
  for (const auto& e : ensembles) escaped += static_cast<long long>(e.escaped());
  log << summary_line(first, points, orbits, plan.total, seconds, escaped,
                      static_cast<long long>(rejected));
  return 0;
}

}  // namespace qmaps
