#include <omp.h>

#include <chrono>
#include <cstdio>
#include <ostream>

#include "core/config.hpp"
#include "core/error.hpp"
#include "core/h5.hpp"
#include "ensembles/box.hpp"
#include "ensembles/catalogue.hpp"
#include "ensembles/commands.hpp"
#include "ensembles/output.hpp"

namespace qmaps {
namespace {

ParamValues map_params(const Config& config) {
  ParamValues params;
  for (const auto& key : config.keys("map"))
    if (key != "name") params[key] = config.number("map", key);
  return params;
}

}  // namespace

int run_command(const RunOptions& options, std::ostream& log) {
  const std::string started = utc_now();
  Config config = Config::load(options.config_path);
  for (const auto& s : options.sets) config.set(s);
  if (!options.out.empty()) config.set("output.file=" + options.out);

  const auto model = make_model(config.string("map", "name"), map_params(config));
  const std::string kind = config.string_or("ensemble", "kind", "box");
  if (kind != "box")
    throw usage_error(config.where("ensemble", "kind") + ": unknown ensemble kind '" + kind +
                      "' (known: box)");
  const Box box = Box::from_config(config);
  const Start start = parse_start(config.string_or("ensemble", "start", "taylor"));

  RunPlan plan;
  plan.total = plan.last = config.integer("run", "steps");
  if (plan.total < 0) throw usage_error(config.where("run", "steps") + " must be >= 0");
  plan.stride = config.integer_or("run", "stride", 1);
  if (plan.stride < 1) throw usage_error(config.where("run", "stride") + " must be >= 1");
  plan.escape_bound = config.number_or("run", "escape_bound", plan.escape_bound);
  if (!(plan.escape_bound > 0))
    throw usage_error(config.where("run", "escape_bound") + " must be > 0");

  Execution x;
  x.isa = resolve_isa(options.simd);
  x.threads = x.isa == Isa::scalar ? 1 : options.threads > 0 ? options.threads : omp_get_max_threads();
  x.chains = static_cast<int>(config.integer_or("run", "chains", 4));
  if (x.chains != 1 && x.chains != 2 && x.chains != 4 && x.chains != 8)
    throw usage_error(config.where("run", "chains") + " must be 1, 2, 4 or 8");

  const std::string path = config.string("output", "file");
  if (path.empty()) throw usage_error(config.where("output", "file") + " must not be empty");
  config.reject_unknown();

  h5::AtomicFile output(path);
  auto file = h5::File::create(output.temporary());  // fails now, not after the run

  const auto initial = box.points();
  Ensemble ensemble = model->start(initial, start, plan.escape_bound);
  const auto t0 = std::chrono::steady_clock::now();
  model->advance(ensemble, plan, x);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  RunRecord record{*model, ensemble, initial, plan, x, kind, box.seed, start,
                   config.text(), config.resolved(), options.command_line, started, utc_now()};
  write_run(file.root(), record);
  file.close();
  output.commit();

  const double rate = static_cast<double>(box.orbits) * static_cast<double>(plan.total) /
                      (seconds > 0 ? seconds : 1e-300);
  char line[512];
  std::snprintf(line, sizeof line,
                "qmaps: %s, %zu orbits x %lld steps in %.3f s (%.3g particle-steps/s, %s, %d "
                "thread%s), %zu escaped -> %s\n",
                std::string(model->name()).c_str(), box.orbits, plan.total, seconds, rate,
                std::string(isa_name(x.isa)).c_str(), x.threads, x.threads == 1 ? "" : "s",
                ensemble.escaped(), path.c_str());
  log << line;
  return 0;
}

}  // namespace qmaps
