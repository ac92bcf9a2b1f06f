// qmaps: ensembles of orbits of the integrable maps of H = |p|²/2 + A q1² + B q2² + α q1⁴ + β q2⁴
// + δ q1² q2², advanced in SIMD across millions of initial conditions. See `qmaps --help`.
#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <new>
#include <string>

#include <CLI/CLI.hpp>
#ifdef QMAPS_MPI
#include <mpi.h>
#endif

#include "core/error.hpp"
#include "core/memory_limit.hpp"
#include "ensembles/io/ranks.hpp"
#include "core/version.hpp"
#include "ensembles/program/commands.hpp"
#include "ensembles/program/interrupt.hpp"

namespace {

#ifdef QMAPS_MPI
// qmaps-mpi: one rank of MPI_COMM_WORLD from start to end (ensembles/io/ranks_mpi.cpp).
struct MpiSession {
  MpiSession(int& argc, char**& argv) {
    int provided = 0;
    MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
  }
  ~MpiSession() { MPI_Finalize(); }
};
#else
// Started by mpirun (its environment says so), qmaps becomes qmaps-mpi, installed beside it: the
// serial program itself needs no MPI to install or to start.
void hand_over_to_mpi(char** argv) {
  const char* size = std::getenv("OMPI_COMM_WORLD_SIZE");
  if (!size) size = std::getenv("PMI_SIZE");
  if (!size) return;
  std::error_code error;
  const auto mpi = std::filesystem::read_symlink("/proc/self/exe", error).parent_path() / "qmaps-mpi";
  if (!error && access(mpi.c_str(), X_OK) == 0) {
    argv[0] = const_cast<char*>(mpi.c_str());
    execv(mpi.c_str(), argv);
  }
  if (std::atoi(size) > 1) {
    std::cerr << "qmaps: error: started by mpirun, but this qmaps was built without qmaps-mpi "
                 "(it needs OpenMPI and parallel HDF5: docs/scaling.md)\n";
    std::exit(static_cast<int>(qmaps::ExitCode::unsupported));
  }
}
#endif

}  // namespace

int main(int argc, char** argv) {
  // A file-size limit makes a write fail (an io error, exit 3) instead of killing the process.
  std::signal(SIGXFSZ, SIG_IGN);
#ifdef QMAPS_MPI
  const MpiSession mpi(argc, argv);
#else
  hand_over_to_mpi(argv);
#endif
  CLI::App app{"qmaps: ensembles of orbits of integrable maps of a quartic-potential Hamiltonian"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("qmaps ") + qmaps::build::version + " (" +
                                        qmaps::build::commit + ", " + qmaps::build::compiler + ")");

  qmaps::RunOptions run;
  auto* run_cmd = app.add_subcommand("run", "advance an ensemble as a TOML config says; write HDF5");
  run_cmd->add_option("config", run.source.config_path, "TOML configuration file");
  run_cmd->add_option("--resume", run.resume,
                      "continue the run of this checkpoint (<output>.ckpt) instead of a config");
  run_cmd->add_option("--set", run.source.sets, "override a config key: section.key=value (repeatable)");
  run_cmd->add_option("--out", run.source.out, "output HDF5 file (overrides [output] file)");
  run_cmd->add_option("--threads", run.source.threads, "OpenMP threads (default: all cores)")
      ->check(CLI::PositiveNumber);
  run_cmd->add_option("--simd", run.source.simd, "path: auto, scalar (the reference), sse2, avx2, avx512")
      ->capture_default_str();
  run_cmd->add_flag("--quiet", run.session.quiet, "no progress output");
  run_cmd->add_option("--shard", run.source.shard,
                      "k/K: run only orbit range k of K into a shard file (<output>.shard-k-of-K "
                      "unless --out), for qmaps merge");

  qmaps::MergeOptions merge;
  auto* merge_cmd = app.add_subcommand(
      "merge", "join the shard files of a run (qmaps run --shard k/K) into the run's file");
  merge_cmd->add_option("shards", merge.shards, "every shard file of the run, in any order")
      ->required();
  merge_cmd->add_option("--out", merge.out, "the merged file")->required();

  qmaps::OrbitOptions orbit;
  auto* orbit_cmd = app.add_subcommand("orbit", "one orbit as CSV on stdout (the scalar reference path)");
  orbit_cmd->add_option("--map", orbit.map,
                        "map name, or a configuration file (*.toml) whose [map] is written as "
                        "formulas (docs/formulas.md)")
      ->required();
  orbit_cmd->add_option("--set", orbit.sets, "a map parameter: name=value (repeatable)");
  orbit_cmd->add_option("--ic", orbit.ic, "initial condition q1,q2,p1,p2")->required();
  orbit_cmd->add_option("--steps", orbit.steps, "number of steps N")->required();
  orbit_cmd->add_option("--every", orbit.every, "print every K-th step")->capture_default_str();
  orbit_cmd->add_option("--start", orbit.start, "start rule: taylor or euler")->capture_default_str();
  orbit_cmd->add_option("--energy", orbit.energy,
                        "put the initial condition on H = E: p2 solved from the continuous H, "
                        "with the sign --ic gives it");
  orbit_cmd->add_flag("--chaos", orbit.chaos,
                      "also columns lyapunov, fli, megno, lyapunov_1 to lyapunov_4, gali_2, "
                      "gali_4: the orbit's chaos indicators so far, from the tangent map, the "
                      "spectrum orthonormalized every 10 steps (nan at n = 0 for the exponents "
                      "and megno; docs/chaos.md)");
  orbit_cmd->add_option("--tunes", orbit.tunes,
                        "also the orbit's tunes over steps 1..N and N+1..2N and its diffusion, on "
                        "stderr (N a power of two, 32 to 2^20; docs/tunes.md)");
  orbit_cmd->add_option("--escape-bound", orbit.escape_bound, "escape when |q| exceeds this")
      ->capture_default_str();

  std::vector<std::string> list_files;
  auto* list_cmd = app.add_subcommand(
      "list", "every map: parameters (meaning, default), invariants, equations; with files, the "
              "maps written as formulas there");
  list_cmd->add_option("files", list_files, "TOML files whose [map] is written as formulas");

  std::string info_path;
  auto* info_cmd =
      app.add_subcommand("info", "what a qmaps HDF5 file holds: map, orbits, drift, observers");
  info_cmd->add_option("file", info_path, "HDF5 file written by qmaps run")->required();

  qmaps::CheckOptions check;
  auto* check_cmd =
      app.add_subcommand("check", "invariant drift and reversibility over a random box");
  check_cmd->add_option("--map", check.map,
                        "map name, or a TOML file whose [map] is written as formulas")
      ->required();
  check_cmd->add_option("--set", check.sets,
                        "a map parameter: name=value (repeatable; defaults "
                        "A=0.7 B=0.3 alpha=0.9 h=0.1 ...)");
  check_cmd->add_option("--orbits", check.orbits, "orbits in the random box")
      ->capture_default_str();
  check_cmd->add_option("--steps", check.steps, "steps forward (and as many back)")
      ->capture_default_str();
  check_cmd->add_option("--seed", check.seed, "seed of the box")->capture_default_str();
  check_cmd->add_option("--box", check.box, "orbits uniform in [-box, box]^4")
      ->capture_default_str();
  check_cmd->add_option("--escape-bound", check.escape_bound, "escape when |q| exceeds this")
      ->capture_default_str();

  qmaps::DiscoverOptions discover;
  auto* discover_cmd = app.add_subcommand(
      "discover", "polynomial invariants of a map found from its orbits (SVD of the steps)");
  discover_cmd->add_option("config", discover.config_path,
                           "TOML configuration: its [map] and [ensemble]")
      ->required();
  discover_cmd->add_option("--degree", discover.degree, "monomials of degree 1 to D")->required();
  discover_cmd->add_option("--steps", discover.steps, "steps of each orbit")->required();
  discover_cmd->add_option("--orbits", discover.orbits,
                           "the first N orbits of the ensemble (all, if it has fewer)")
      ->capture_default_str();
  discover_cmd->add_option("--set", discover.sets,
                           "override a config key: section.key=value (repeatable)");
  discover_cmd->add_option("--threshold", discover.threshold,
                           "null space: sigma_i / sigma_1 at or below this (0: at the largest "
                           "gap below 1e-6)")
      ->capture_default_str();
  discover_cmd->add_option("--drop", discover.drop,
                           "leave out coefficients below this times the largest")
      ->capture_default_str();
  discover_cmd->add_flag("--csv", discover.csv,
                         "the invariants as CSV rows (invariant,monomial,coefficient)");

  qmaps::IntegrabilityCommandOptions integrability;
  auto& tests = integrability.tests;
  auto* integrability_cmd = app.add_subcommand(
      "integrability", "is a rational map integrable? degree growth, orbits over finite fields, "
                       "height growth (docs/integrability.md)");
  integrability_cmd->add_option("--map", integrability.map,
                                "map name, or a TOML file whose [map] is written as formulas")
      ->required();
  integrability_cmd->add_option("--set", integrability.sets, "a map parameter: name=value (repeatable)");
  integrability_cmd->add_option("--steps", tests.steps, "degree growth: steps")->capture_default_str();
  integrability_cmd->add_option("--degree-cap", tests.degree_cap,
                                "degree growth: stop where a degree passes this")
      ->capture_default_str();
  integrability_cmd->add_option("--degree-primes", tests.degree_primes,
                                "degree growth: the primes p of F_p(t) (default two near 2^61)")
      ->delimiter(',');
  integrability_cmd->add_option("--lines", tests.lines, "degree growth: random lines per prime")
      ->capture_default_str();
  integrability_cmd->add_option("--field-primes", tests.field_primes,
                                "finite fields: the primes (default 1009,4001,10007 for 2 "
                                "coordinates, 31,61,101 for 4)")
      ->delimiter(',');
  integrability_cmd->add_option("--orbits", tests.orbits, "finite fields: orbits per prime")
      ->capture_default_str();
  integrability_cmd->add_option("--max-period", tests.max_period,
                                "finite fields: an orbit not back by then is counted apart (default "
                                "64 p^(d/2))");
  integrability_cmd->add_option("--height-steps", tests.height_steps, "height growth: steps")
      ->capture_default_str();
  integrability_cmd->add_option("--height-bits", tests.height_bits,
                                "height growth: stop where a height passes this many bits")
      ->capture_default_str();
  integrability_cmd->add_option("--seed", tests.seed, "the lines, points and bootstrap")
      ->capture_default_str();
  integrability_cmd->add_option("--out", integrability.output,
                                "also write the evidence to this HDF5 file");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : static_cast<int>(qmaps::ExitCode::usage);
  }

  // Over several ranks every rank reports an error alike (ensembles/program/run_command.cpp):
  // rank 0 prints it.
  std::ostream silent(nullptr);
  std::ostream& errors = qmaps::ranks::root() ? std::cerr : silent;
  try {
    if (qmaps::ranks::count() > 1 && !*run_cmd)
      throw qmaps::usage_error("under mpirun, qmaps runs `qmaps run` alone");
    // An option given empty is no option left out: `--out ""` names no file.
    for (auto* out : {run_cmd->get_option("--out"), merge_cmd->get_option("--out"),
                      integrability_cmd->get_option("--out")})
      if (out->count() > 0 && out->as<std::string>().empty())
        throw qmaps::usage_error("--out: the output's name is empty");
    // A run's outcome is its files: a summary written to a closed pipe (qmaps run | head) fails
    // as a write, never ends the process with the run's lock left behind.
    if (*run_cmd || *merge_cmd) std::signal(SIGPIPE, SIG_IGN);
    if (*run_cmd) {
      for (int i = 0; i < argc; ++i) run.session.command_line += (i ? " " : "") + std::string(argv[i]);
      return qmaps::run_command(run, errors);
    }
    if (*merge_cmd) return qmaps::merge_command(merge, std::cerr);
    if (*orbit_cmd) return qmaps::orbit_command(orbit, std::cout, std::cerr);
    if (*info_cmd) return qmaps::info_command(info_path, std::cout);
    if (*check_cmd) return qmaps::check_command(check, std::cout);
    if (*discover_cmd) return qmaps::discover_command(discover, std::cout);
    if (*integrability_cmd) return qmaps::integrability_command(integrability, std::cout);
    return qmaps::list_command(list_files, std::cout);
  } catch (const qmaps::Interrupted& e) {
    errors << "qmaps: " << e.what() << '\n';
    std::signal(e.signal(), SIG_DFL);  // ended by the signal, as the caller asked
    std::raise(e.signal());
    return 128 + e.signal();
  } catch (const qmaps::Error& e) {
    errors << "qmaps: error: " + std::string(e.what()) + '\n' << std::flush;  // one write
    if (dynamic_cast<const qmaps::ranks::FailedOnEveryRank*>(&e)) qmaps::ranks::barrier();
    if (e.code() == qmaps::ExitCode::io) {
      // A shared file (MPI-IO) whose close failed (a full disk) stays open inside HDF5, whose
      // exit handler would then fail on it (ensembles/io/h5_writing_driver.hpp spares the files of
      // one process): the outputs are settled by now (no temporary is left), so end here.
      std::cout.flush();
      std::fflush(nullptr);
      std::_Exit(static_cast<int>(e.code()));
    }
    return static_cast<int>(e.code());
  } catch (const std::bad_alloc&) {
    // The estimates checked before the work leave out what no estimate knows (a library's
    // buffers): an allocation refused then is still the memory limit, not a fault of qmaps.
    const qmaps::MemoryLimit have = qmaps::memory_limit();
    errors << "qmaps: error: out of memory: " << have.what << " is "
           << have.bytes / (1 << 30) << " GiB now; the work needs more than qmaps estimated: "
           << "give it more memory, or fewer orbits, bins or threads\n";
    return static_cast<int>(qmaps::ExitCode::usage);
  } catch (const std::exception& e) {
    errors << "qmaps: error: " << e.what() << '\n';
    return static_cast<int>(qmaps::ExitCode::failure);
  }
}
