#include "ensembles/program/run_setup.hpp"

#include <omp.h>

#include <climits>
#include <cstring>
#include <cstdio>

#include "core/error.hpp"
#include "core/memory_limit.hpp"
#include "core/observers/tunes/naff_tables.hpp"
#include "ensembles/io/ranks.hpp"
#include "core/thread_limit.hpp"
#include "core/tangent_map.hpp"
#include "ensembles/io/checkpoint.hpp"

namespace qmaps {
namespace {

// How the output classifies and histograms the indicators.
ChaosReport chaos_report_of(const Config& config) {
  ChaosReport report;
  report.megno_threshold = config.number_or("chaos", "megno_threshold", report.megno_threshold);
  if (!(report.megno_threshold > 0 && report.megno_threshold < 1e300))
    throw usage_error(config.where("chaos", "megno_threshold") + " must be a positive number");
  report.bins = config.integer_or("chaos", "bins", report.bins);
  if (report.bins < 1 || report.bins > (1 << 20))
    throw usage_error(config.where("chaos", "bins") + " must be 1 to 1048576");
  return report;
}


// Refuses, before allocating, a run that cannot fit in this machine's memory: its orbits, its
// observers (Observers::bytes: the histograms in every thread, the sections' point slots) and its
// threads (their stacks, which count against an address-space limit).
void check_memory(const Config& config, const Model& model, std::span<const std::string> measured,
                  std::size_t orbits, double for_observers, int threads) {
  const double padded = static_cast<double>((orbits + Ensemble::padding - 1) /
                                            Ensemble::padding * Ensemble::padding);
  const double for_orbits = padded * bytes_per_orbit(model, measured);
  const double for_threads = threads * bytes_per_thread();
  char text[300];
  std::string parts;  // how the bytes divide, where more than the orbits need them
  if (for_observers > 0 || for_threads > 0) {
    std::snprintf(text, sizeof text,
                  " (the orbits %.3g GiB, their histograms (a copy per thread), section points "
                  "and trajectories %.3g GiB, %d threads' stacks %.3g GiB)",
                  for_orbits / (1 << 30), for_observers / (1 << 30), threads,
                  for_threads / (1 << 30));
    parts = text;
  }
  // The key that sets the ensemble's size: a grid's points, else its orbits.
  const char* key = config.has("ensemble", "points") ? "points" : "orbits";
  check_fits(for_orbits + for_observers + for_threads, config.where("ensemble", key),
             std::to_string(orbits) + " orbits", parts);
}

}  // namespace

// [chaos], if the run records chaos indicators (docs/chaos.md).
std::optional<ChaosOptions> chaos_options_of(const Config& config) {
  if (!config.has_section("chaos")) return std::nullopt;
  ChaosOptions o;
  o.spectrum = config.boolean_or("chaos", "spectrum", false);
  o.every = config.integer_or("chaos", "orthonormalize_every", o.every);
  if (o.every < 1 || o.every > max_orthonormalize_every)
    throw usage_error(config.where("chaos", "orthonormalize_every") + " must be 1 to " +
                      std::to_string(max_orthonormalize_every) + " (got " +
                      std::to_string(o.every) + ")");
  return o;
}

// The memory a run holds per orbit: the state (with its chaos record), the escape record (step,
// reason), the invariant tracking (initial value, max drift), the chaos indicators computed for
// the output; the observers count theirs (Observers::bytes).
std::vector<std::string> measured_of(const Config& config, const Model& model) {
  std::vector<std::string> measured;
  for (const auto key : model.lane_keys())
    if (config.has_section(key)) measured.emplace_back(key);
  return measured;
}

double bytes_per_orbit(const Model& model, std::span<const std::string> measured) {
  std::size_t columns = 0;
  for (const auto& specs : model.lane_columns(measured)) columns += specs.size();
  return static_cast<double>(8 * (model.state_names().size() + columns) + 9 +
                             8 * model.indicator_names().size());
}

Run run_of(const Config& config, std::unique_ptr<Model> model, std::size_t orbits,
           const SpecSource& source) {
  Run r;
  r.model = std::move(model);
  r.orbits = r.total = orbits;
  if (!source.shard.empty()) {
    r.shard = Shard::parse(source.shard);
    r.first = r.shard->first(orbits);
    r.orbits = r.shard->size(orbits);
    if (r.orbits == 0)
      throw usage_error("--shard " + source.shard + ": the ensemble's " + std::to_string(orbits) +
                        " orbits leave this shard none");
  } else if (ranks::count() > 1) {  // qmaps-mpi: rank r runs the orbits of shard r + 1
    const Shard part{static_cast<std::size_t>(ranks::rank()) + 1,
                     static_cast<std::size_t>(ranks::count())};
    r.first = part.first(orbits);
    r.orbits = part.size(orbits);
    if (r.orbits == 0)
      throw usage_error("the ensemble's " + std::to_string(orbits) + " orbits leave rank " +
                        std::to_string(ranks::rank()) + " of " + std::to_string(ranks::count()) +
                        " none: run it on fewer ranks");
  }
  r.measured = measured_of(config, *r.model);
  check_memory(config, *r.model, r.measured, r.orbits, 0, 0);  // before the observers are made
  try {
    r.start = parse_start(config.string_or("ensemble", "start", "taylor"));
  } catch (const Error& e) {
    throw usage_error(config.where("ensemble", "start") + ": " + e.what());
  }

  r.plan.total = r.plan.last = config.integer("run", "steps");
  if (r.plan.total < 0) throw usage_error(config.where("run", "steps") + " must be >= 0");
  r.plan.stride = config.integer_or("run", "stride", 1);
  if (r.plan.stride < 1) throw usage_error(config.where("run", "stride") + " must be >= 1");
  r.plan.escape_bound = config.number_or("run", "escape_bound", r.plan.escape_bound);
  if (!(r.plan.escape_bound > 0))
    throw usage_error(config.where("run", "escape_bound") + " must be > 0");
  r.checkpoint_every = config.integer_or("run", "checkpoint_every", 0);
  if (r.checkpoint_every < 0)
    throw usage_error(config.where("run", "checkpoint_every") + " must be >= 0 (0: never)");

  r.x.isa = resolve_isa(source.simd);
  // Checked even where the scalar path runs on one thread: the request is the same mistake.
  const int team =
      checked_threads(r.x.isa == Isa::scalar && source.threads == 0 ? 1 : source.threads,
                      source.threads_given_as + std::to_string(source.threads));
  r.x.threads = r.x.isa == Isa::scalar ? 1 : team;
  r.x.chains = static_cast<int>(config.integer_or("run", "chains", Execution{}.chains));
  if (r.x.chains != 1 && r.x.chains != 2 && r.x.chains != 4 && r.x.chains != 8)
    throw usage_error(config.where("run", "chains") + " must be 1, 2, 4 or 8");

  const TuneSettings tunes = tunes_from_config(config, r.plan.total);
  r.plan.tunes = tunes.windows;
  r.tunes = tunes.report;
  r.observers = observers_from_config(config, *r.model, r.orbits, r.plan.total);
  r.trajectories = trajectories_from_config(config, *r.model, orbits, r.plan.total);
  if (r.shard) keep_orbits_in(r.trajectories, r.first, r.orbits);
  // Over several ranks, rank 0 records every trajectory (run_command.cpp); the others none.
  if (!r.shard && !ranks::root()) keep_orbits_in(r.trajectories, 0, 0);
  double for_trajectories = 0;
  for (const auto& t : r.trajectories) for_trajectories += t.bytes(r.plan.total);
  // The tunes' scratch on each thread: a window of every chain's lanes, and the FFT's.
  const double for_tunes = static_cast<double>(r.x.threads) * static_cast<double>(fft_slot + 1) *
                           2 * static_cast<double>(r.plan.tunes.window) * 8 * sizeof(double);
  // The threads started: OpenMP's beside this one, and the writer's, one per invariant
  // (ensembles/io/output.cpp).
  check_memory(config, *r.model, r.measured, r.orbits,
               r.observers.bytes(r.x.threads) + for_trajectories + for_tunes,
               r.x.threads - 1 + static_cast<int>(r.model->invariant_names().size()));
  r.image = invariant_image_from_config(config, *r.model);
  r.chaos = chaos_report_of(config);

  // The caller's file (qmaps.run) makes [output] file a name the configuration may keep.
  r.path = source.write_to.empty() ? config.string("output", "file")
                                    : config.string_or("output", "file", "");
  // A shard's file: --out, or the output's name with ".shard-k-of-K".
  if (r.shard)
    r.path = !source.out.empty() ? source.out
                                  : r.path + ".shard-" + std::to_string(r.shard->index) + "-of-" +
                                        std::to_string(r.shard->count);
  if (!source.write_to.empty()) r.path = source.write_to;
  check_output_name(r.path, source.write_to.empty() ? config.where("output", "file") : "the output");
  // Every name the run derives from the output's must be legal before the run starts: the
  // longest is the checkpoint's temporary, "<name>.ckpt.tmp-<pid>".
  const auto slash = r.path.rfind('/');
  const std::string name = slash == std::string::npos ? r.path : r.path.substr(slash + 1);
  const std::size_t longest = name.size() + std::strlen(checkpoint_suffix) + std::strlen(".tmp-") + 10;
  if (name.empty() || longest > NAME_MAX)
    throw usage_error(config.where("output", "file") + ": the name '" + name + "' has " +
                      std::to_string(name.size()) + " bytes; its checkpoint's temporary needs " +
                      std::to_string(longest - name.size()) + " more and a name may have at most " +
                      std::to_string(NAME_MAX));
  if (r.path.empty()) throw usage_error(config.where("output", "file") + " must not be empty");
  r.per_orbit = config.boolean_or("output", "per_orbit", true);
  r.per_orbit = r.per_orbit || r.shard.has_value();  // the merge needs every orbit's record
  const std::string compression = config.string_or("output", "compression", "none");
  if (compression != "none" && compression != "gzip")
    throw usage_error(config.where("output", "compression") + ": '" + compression +
                      "' is not a compression (expected \"none\" or \"gzip\")");
  if (compression == "gzip") {
    const long long level = config.integer_or("output", "compression_level", 4);
    if (level < 1 || level > 9)
      throw usage_error(config.where("output", "compression_level") + " must be 1 to 9 (got " +
                        std::to_string(level) + ")");
    r.deflate = static_cast<int>(level);
  } else if (config.has("output", "compression_level")) {
    throw usage_error(config.where("output", "compression_level") +
                      " needs compression = \"gzip\"");
  }
  r.config_text = config.text();
  r.config_resolved = config.resolved();
  return r;
}

void read_provenance(const h5::Group& root, Run& r) {
  r.kind = root.attr_string("ensemble");
  r.seed = static_cast<std::uint64_t>(root.attr_int64("seed"));
  r.description = root.attr_string("ensemble_description");
  r.config_text = root.attr_string("config");
  r.command_line = root.attr_string("command_line");
  r.started = root.attr_string("started");
}

void check_record_of(const h5::Group& root, const Run& r) {
  const auto differ = [&](const std::string& attr, const std::string& has, const std::string& run) {
    throw Error(ExitCode::io, "attribute " + attr + " is " + has +
                                  ", but the run its configuration describes has " + run +
                                  ": the file was altered, or is another run's");
  };
  const auto text = [&](const std::string& attr, const std::string& run) {
    if (const std::string has = root.attr_string(attr); has != run) differ(attr, "'" + has + "'", "'" + run + "'");
  };
  const auto integer = [&](const std::string& attr, std::int64_t run) {
    if (const auto has = root.attr_int64(attr); has != run)
      differ(attr, std::to_string(has), std::to_string(run));
  };
  const auto number = [&](const std::string& attr, double run) {
    const double has = root.attr_double(attr);  // the same bits: both come from one text
    if (std::memcmp(&has, &run, sizeof has) != 0) differ(attr, number_text(has), number_text(run));
  };
  integer("schema_version", schema_version);
  text("map", std::string(r.model->name()));
  const auto specs = r.model->param_specs();
  const auto values = r.model->param_values();
  for (std::size_t k = 0; k < specs.size(); ++k)
    number("param." + std::string(specs[k].name), values[k]);
  integer("steps", r.plan.total);
  integer("stride", r.plan.stride);
  text("start", std::string(start_name(r.start)));
  number("escape_bound", r.plan.escape_bound);
  text("ensemble", r.kind);
  integer("seed", static_cast<std::int64_t>(r.seed));
}

void check_output_name(const std::string& path, const std::string& where) {
  if (path.empty()) throw usage_error(where + ": the output's name is empty");
  if (const auto nul = path.find('\0'); nul != std::string::npos)
    throw usage_error(where + ": the output's name has a NUL byte at position " +
                      std::to_string(nul) + "; a file name cannot hold one");
  const auto slash = path.rfind('/');
  const std::string name = slash == std::string::npos ? path : path.substr(slash + 1);
  if (name.empty() || name == "." || name == "..")
    throw usage_error(where + ": '" + path + "' names a folder; the output is a file in it (" +
                      (name.empty() ? path : path + "/") + "run.h5, say)");
}

double memory_of(const Run& r) { return memory_of(r, r.orbits); }

double memory_of(const Run& r, std::size_t orbits) {
  const std::size_t padded =
      (orbits + Ensemble::padding - 1) / Ensemble::padding * Ensemble::padding;
  double slots_per_orbit = 0;  // SectionPoints::bytes() is the orbits times an orbit's share
  for (const auto& s : r.observers.sections)
    slots_per_orbit += static_cast<double>(s.points->bytes() / r.orbits);
  double bytes = static_cast<double>(padded) * bytes_per_orbit(*r.model, r.measured) +
                 r.observers.bytes(r.x.threads) +
                 (static_cast<double>(orbits) - static_cast<double>(r.orbits)) * slots_per_orbit;
  for (const auto& t : r.trajectories) bytes += t.bytes(r.plan.total);
  return bytes;
}

RunRecord record_of(Run& r, const Ensemble& e, long long session_first,
                    const std::string& session_started, const std::string& now,
                    const std::string& session_command) {
  return RunRecord{
      .model = *r.model,
      .ensemble = e,
      .plan = r.plan,
      .execution = r.x,
      .ensemble_kind = r.kind,
      .seed = r.seed,
      .start = r.start,
      .per_orbit = r.per_orbit,
      .config_text = r.config_text,
      .config_resolved = r.config_resolved,
      .command_line = r.command_line,
      .started = r.started,
      .finished = now,
      .sessions = r.sessions + session_line(session_first, e.step, r.x, session_started, now,
                                            session_command),
      .observers = &r.observers,
      .image = r.image ? &*r.image : nullptr,
      .ensemble_description = r.description,
      .rejected = r.rejected,
      .chaos = r.chaos,
      .tunes = r.tunes,
      .trajectories = &r.trajectories,
      .shard = r.shard ? r.shard->name() : "",
      .shard_first = static_cast<std::int64_t>(r.first),
      .orbits_total = static_cast<std::int64_t>(r.total),
      .rows = r.shard ? Rows{} : Rows{r.first, r.orbits, r.total}};
}

}  // namespace qmaps
