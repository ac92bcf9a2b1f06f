#include <omp.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <ostream>

#include "core/config.hpp"
#include "core/error.hpp"
#include "core/h5.hpp"
#include "ensembles/catalogue.hpp"
#include "ensembles/commands.hpp"
#include "ensembles/initial_conditions.hpp"
#include "ensembles/output.hpp"

namespace qmaps {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// The map of [map]; its errors say where in the config the map is.
std::unique_ptr<Model> map_of(const Config& config) {
  const std::string name = config.string("map", "name");
  ParamValues params;
  for (const auto& key : config.keys("map"))
    if (key != "name") params[key] = config.number("map", key);
  try {
    return make_model(name, params);
  } catch (const Error& e) {
    throw Error(e.code(), config.where("map") + ": " + e.what());
  }
}

// Refuses, before allocating, an ensemble that cannot fit in this machine's memory.
void check_memory(const Config& config, const Model& model, std::size_t orbits) {
  const double doubles_per_orbit = static_cast<double>(
      model.state_names().size() + 3 * model.invariant_names().size() + 8);  // + phase in, out
  const double need = static_cast<double>(orbits) * (8 * doubles_per_orbit + 9);
  const double have = static_cast<double>(sysconf(_SC_PHYS_PAGES)) *
                      static_cast<double>(sysconf(_SC_PAGE_SIZE));
  if (need > have) {
    char text[160];
    std::snprintf(text, sizeof text, ": %zu orbits need about %.3g GiB; this machine has %.3g GiB",
                  orbits, need / (1 << 30), have / (1 << 30));
    throw usage_error(config.where("ensemble", "orbits") + text);
  }
}

// Advances in segments when progress is shown (the result is the same: segments are exact).
void advance_with_progress(const Model& model, Ensemble& e, const RunPlan& plan,
                           const Execution& x, Observers* observers, bool show, std::ostream& log) {
  if (!show) {
    model.advance(e, plan, x, observers);
    return;
  }
  const auto t0 = Clock::now();
  const long long segment = std::max(1LL, plan.total / 100);
  for (long long n = plan.first; n < plan.last;) {
    RunPlan part = plan;
    part.first = n;
    part.last = n = std::min(plan.last, n + segment);
    model.advance(e, part, x, observers);
    const double t = seconds_since(t0), done = double(n - plan.first) / double(plan.last - plan.first);
    char line[160];
    std::snprintf(line, sizeof line, "\rqmaps: %5.1f%%  %.3g particle-steps/s  %.1f s elapsed  ETA %.1f s ",
                  100 * done, double(e.orbits) * double(n - plan.first) / t, t, t / done - t);
    log << line << std::flush;
  }
  log << '\n';
}

// ", 12 rejected" for a shell ensemble, which rejects points off its energy surface.
std::string rejected_text(const std::string& kind, std::uint64_t rejected) {
  if (kind != "shell") return "";
  return ", " + std::to_string(rejected) + " rejected";
}

}  // namespace

int run_command(const RunOptions& options, std::ostream& log) {
  const std::string started = utc_now();
  Config config = Config::load(options.config_path);
  for (const auto& s : options.sets) config.set(s);
  if (!options.out.empty()) config.set("output.file=" + options.out);

  const auto model = map_of(config);
  const auto initial_conditions = InitialConditions::from_config(config, *model);
  check_memory(config, *model, initial_conditions.orbits());
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

  Observers observers = observers_from_config(config, *model, initial_conditions.orbits());
  const auto image = invariant_image_from_config(config, *model);

  const std::string path = config.string("output", "file");
  if (path.empty()) throw usage_error(config.where("output", "file") + " must not be empty");
  config.reject_unknown();

  h5::AtomicFile output(path);
  auto file = output.create_hdf5();  // fails now, not after the run

  auto [ensemble, initial, rejected] = initial_conditions.start(*model, start, plan.escape_bound);
  const auto t0 = Clock::now();
  advance_with_progress(*model, ensemble, plan, x, observers.empty() ? nullptr : &observers,
                        !options.quiet && isatty(STDERR_FILENO), log);
  const double seconds = seconds_since(t0);

  RunRecord record{*model, ensemble, initial, plan, x, initial_conditions.kind(),
                   initial_conditions.seed(), start, config.text(), config.resolved(),
                   options.command_line, started, utc_now(), &observers,
                   image ? &*image : nullptr, initial_conditions.description(), rejected};
  write_run(file.root(), record);
  file.close();
  output.commit();

  const double rate = static_cast<double>(ensemble.orbits) * static_cast<double>(plan.total) /
                      (seconds > 0 ? seconds : 1e-300);
  char line[512];
  std::snprintf(line, sizeof line,
                "qmaps: %s, %zu orbits x %lld steps in %.3f s (%.3g particle-steps/s, %s, %d "
                "thread%s), %zu escaped%s -> %s\n",
                std::string(model->name()).c_str(), ensemble.orbits, plan.total, seconds, rate,
                std::string(isa_name(x.isa)).c_str(), x.threads, x.threads == 1 ? "" : "s",
                ensemble.escaped(), rejected_text(initial_conditions.kind(), rejected).c_str(),
                path.c_str());
  log << line;
  return 0;
}

}  // namespace qmaps
