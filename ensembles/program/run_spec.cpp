#include "ensembles/program/run_spec.hpp"

#include <string>
#include <utility>

#include "core/error.hpp"
#include "core/memory_limit.hpp"
#include "core/thread_limit.hpp"
#include "ensembles/config/map_config.hpp"
#include "ensembles/io/h5.hpp"
#include "ensembles/io/output.hpp"
#include "ensembles/io/ranks.hpp"
#include "ensembles/program/every_rank.hpp"

namespace qmaps {
namespace {

// The configuration as its source gives it: its file or text, then --set and --out.
Config config_of(const SpecSource& source) {
  Config config = source.config_path.empty()
                      ? Config::parse(source.config_text, source.config_source)
                      : Config::load(source.config_path);
  for (const auto& s : source.sets) config.set(s);
  // A shard's --out names its own file: the configuration keeps the whole run's output, which
  // every shard of the run must share.
  if (!source.out.empty() && source.shard.empty()) config.set("output.file=" + source.out);
  return config;
}

// The run of `config` from these initial conditions, with what it records of them.
RunPoint point_of(const Config& config, std::unique_ptr<Model> model, InitialConditions initial,
                  const SpecSource& source, const std::string& started) {
  Run r = run_of(config, std::move(model), initial.orbits(), source);
  r.kind = initial.kind();
  r.rejects_points = initial.generator().rejects_points();
  r.description = initial.description();
  r.seed = initial.seed();
  r.started = started;
  return {std::move(initial), std::move(r)};
}

InitialConditions initial_of(const Config& config, const Model& model, const SpecSource& source) {
  return source.points ? InitialConditions::of_points(config, source.points)
                        : InitialConditions::from_config(config, model, stop_on_signal);
}

// Refuses, before any point but the first has its observers, a sweep whose points cannot all
// fit in memory: each point's run is the first's (the same keys and map) with its own orbits.
void check_memory(const RunSpec& spec, const Run& first,
                  const std::vector<std::size_t>& orbits_of_points) {
  double bytes = (first.x.threads - 1) * bytes_per_thread();  // the threads serve every point
  std::size_t orbits = 0;
  for (const std::size_t n : orbits_of_points) {
    bytes += memory_of(first, n);
    orbits += n;
  }
  check_fits(bytes, spec.config.where("sweep[0]"),
             std::to_string(orbits_of_points.size()) + " points, " + std::to_string(orbits) +
                 " orbits in all, with their observers,");
}

// A sweep's points: first every point's map and initial conditions (which fix its orbits), then
// the first point's run, from which the whole sweep's memory is known before the others are made.
// A map that degenerates at a point is refused here, naming the point.
void read_points(RunSpec& spec, const SpecSource& source) {
  const Sweep& sweep = *spec.sweep;
  std::vector<std::unique_ptr<Model>> models;
  std::vector<InitialConditions> starts;
  std::optional<Config> first_point;  // kept: the keys its readers used, for reject_unknown()
  for (std::size_t k = 0; k < sweep.points(); ++k) {
    Config point = sweep.config_of(spec.config, k);
    try {  // the point's own map and, for a shell, its own energy surface
      models.push_back(map_of(point, chaos_options_of(point)));
      starts.push_back(initial_of(point, *models.back(), source));
    } catch (const Error& e) {
      throw Error(e.code(), "[[sweep]] " + sweep.label(k) + ": " + e.what());
    }
    if (k == 0) first_point = std::move(point);
  }
  std::vector<std::size_t> orbits;
  for (const auto& s : starts) orbits.push_back(s.orbits());
  for (std::size_t k = 0; k < sweep.points(); ++k) {
    Config point = k == 0 ? std::move(*first_point) : sweep.config_of(spec.config, k);
    RunPoint p = point_of(point, std::move(models[k]), std::move(starts[k]), source, spec.started);
    if (p.run.checkpoint_every > 0)
      throw usage_error(point.where("run", "checkpoint_every") +
                        ": a sweep keeps no checkpoint (it runs to the end or stops with nothing "
                        "written)");
    if (k == 0) {
      point.reject_unknown();
      check_memory(spec, p.run, orbits);
    }
    spec.points.push_back(std::move(p));
  }
}

}  // namespace

RunSpec read_spec(const SpecSource& source) {
  if (source.config_path.empty() && source.config_source.empty())
    throw usage_error("qmaps run needs a config file, or --resume <output>.ckpt");
  RunSpec spec;
  spec.started = ranks::from_root(utc_now());
  on_every_rank([&] {
    spec.config = config_of(source);
    if (!source.shard.empty() && ranks::count() > 1)
      throw usage_error("--shard splits a run into processes of their own; under mpirun the "
                        "ranks split it");
    auto model = map_of(spec.config, chaos_options_of(spec.config));
    spec.sweep = Sweep::from_config(spec.config, *model);
    if (spec.sweep) {
      if (!source.shard.empty())
        throw usage_error("--shard splits a run's orbits, not a sweep's points");
      if (ranks::count() > 1)
        throw usage_error("a sweep runs in one process: run it with qmaps, not under mpirun");
      return read_points(spec, source);
    }
    InitialConditions initial = initial_of(spec.config, *model, source);
    spec.points.push_back(
        point_of(spec.config, std::move(model), std::move(initial), source, spec.started));
    spec.config.reject_unknown();
    if (ranks::count() > 1) h5::AtomicFile::check_writable(spec.points.front().run.path);
  });
  return spec;
}

RunSpec read_recorded_spec(const std::string& config_resolved, const std::string& where,
                           std::size_t orbits, const SpecSource& source) {
  RunSpec spec;
  spec.config = Config::parse(config_resolved, where);
  spec.points.push_back(
      {std::nullopt, run_of(spec.config, map_of(spec.config, chaos_options_of(spec.config)),
                            orbits, source)});
  return spec;
}

}  // namespace qmaps
