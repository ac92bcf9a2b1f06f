// The qmaps command line, run as a process: a valid run, every kind of bad input (a clear message,
// the right exit code, no file left behind), `qmaps orbit` output, --help and --simd; every
// ensemble kind and its bad input; list, info and check.
#include <gtest/gtest.h>
#include <pty.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include "ensembles/io/h5.hpp"
#include "core/isa.hpp"
#include "kernels/catalogue.hpp"
#include "run_process.hpp"

namespace qmaps::testing {
namespace {

class Cli : public ::testing::Test {
 protected:
  TempDir dir;
  const std::string output = dir / "run.h5";
  const std::string config = preset_config(output);

  // `qmaps run cfg.toml <extra>` with `text` as cfg.toml.
  Result run_config(const std::string& text, std::vector<std::string> extra = {}) {
    write_text(dir / "cfg.toml", text);
    extra.insert(extra.begin(), {"run", "cfg.toml"});
    return run(extra, dir);
  }

  // A failed run: exit `code`, a message with each of `parts`, and no output or temporary file.
  void expect_rejected(const Result& r, int code, const std::vector<std::string>& parts) {
    EXPECT_EQ(r.status, code) << r.err;
    EXPECT_TRUE(Contains(r.err, "qmaps: error: "));
    for (const auto& part : parts) EXPECT_TRUE(Contains(r.err, part));
    EXPECT_FALSE(fs::exists(output));
    EXPECT_FALSE(dir.has_entry_containing(".tmp-"));
  }
};

TEST_F(Cli, SmallRunWritesFileAndASummaryWithItsTimeByPhase) {
  const Result r = run_config(config);
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out, "");
  EXPECT_TRUE(Contains(r.err, "qmaps: suris, 100 orbits x 50 steps in "));
  const auto first_end = r.err.find("0 escaped -> " + output + "\n");
  ASSERT_NE(first_end, std::string::npos) << r.err;
  std::string phases = r.err.substr(r.err.find('\n') + 1);
  // A binary built without the widest ISA of this CPU says so after the summary (the sanitized
  // build, avx2 alone, on an AVX-512 machine).
  const auto wider = missing_wider_isa();
  if (wider) {
    const std::string note = "qmaps: this CPU has " + std::string(isa_name(*wider)) +
                             ", which this binary was built without: it ran " +
                             std::string(isa_name(best_isa())) + " (bash tools/setup";
    EXPECT_TRUE(phases.starts_with(note)) << r.err;
    phases = phases.substr(phases.find('\n') + 1);
  }
  EXPECT_TRUE(phases.starts_with("qmaps: time by phase: starting ")) << r.err;
  for (const char* part : {" s, stepping and observing ", " s, writing "})
    EXPECT_TRUE(Contains(phases, part)) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), wider ? 3 : 2) << r.err;
  EXPECT_TRUE(fs::is_regular_file(output));
  EXPECT_FALSE(dir.has_entry_containing(".tmp-"));
}

// What `qmaps run cfg.toml <extra>` prints on a terminal (a pseudo-terminal as stdout and stderr).
std::string run_on_terminal(const TempDir& dir, std::vector<std::string> extra) {
  extra.insert(extra.begin(), {QMAPS_BINARY, "run", "cfg.toml"});
  int terminal = -1;
  const pid_t pid = forkpty(&terminal, nullptr, nullptr, nullptr);
  if (pid < 0) throw std::runtime_error("forkpty failed");
  if (pid == 0) {
    std::vector<char*> argv;
    for (auto& a : extra) argv.push_back(a.data());
    argv.push_back(nullptr);
    if (chdir(dir.path().c_str()) == 0) execv(QMAPS_BINARY, argv.data());
    _exit(127);
  }
  std::string text;
  char buffer[4096];
  for (ssize_t n; (n = read(terminal, buffer, sizeof buffer)) > 0;) text.append(buffer, n);
  close(terminal);
  int status = 0;
  waitpid(pid, &status, 0);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << text;
  return text;
}

TEST_F(Cli, TerminalShowsProgressUnlessQuietAndAlwaysTheSummary) {
  write_text(dir / "cfg.toml", config);
  const std::string shown = run_on_terminal(dir, {});
  for (const char* part : {"\rqmaps: step 50 of 50  100.0%", "particle-steps/s", "s elapsed", "ETA",
                           "qmaps: suris, 100 orbits x 50 steps in "})
    EXPECT_TRUE(Contains(shown, part));
  const std::string quiet = run_on_terminal(dir, {"--quiet"});
  EXPECT_FALSE(Contains(quiet, "qmaps: step "));
  EXPECT_TRUE(Contains(quiet, "qmaps: suris, 100 orbits x 50 steps in "));
}

TEST_F(Cli, OutOptionOverridesConfigFile) {
  const Result r = run_config(config, {"--out", "other.h5"});
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(fs::is_regular_file(dir / "other.h5"));
  EXPECT_FALSE(fs::exists(output));
}

TEST_F(Cli, UnknownMapIsRejected) {
  expect_rejected(run_config(with_line(config, "name = ", "name = \"nosuch\"")), 2,
                  {"unknown map 'nosuch'", "suris"});
}

TEST_F(Cli, MissingMapParameterIsRejected) {
  expect_rejected(run_config(with_line(config, "h = ", "")), 2, {"parameter 'h' is missing"});
}

TEST_F(Cli, UnknownMapParameterIsRejected) {
  expect_rejected(run_config(config, {"--set", "map.beta=1"}), 2, {"no parameter 'beta'"});
}

TEST_F(Cli, NonFiniteParameterIsRejected) {
  const std::string text = with_line(config, "alpha = ", "alpha = nan");
  expect_rejected(
      run_config(text), 2,
      {"cfg.toml:" + std::to_string(line_of(text, "alpha = ")) + ": [map] alpha", "finite"});
  expect_rejected(run_config(config, {"--set", "map.A=inf"}), 2, {"--set map.A must be finite"});
}

TEST_F(Cli, NonPositiveStepIsRejected) {
  expect_rejected(run_config(with_line(config, "h = ", "h = 0.0")), 2, {"h must be > 0"});
  expect_rejected(run_config(config, {"--set", "map.h=-0.1"}), 2, {"h must be > 0"});
}

TEST_F(Cli, DegenerateStepIsRejected) {
  expect_rejected(run_config(config, {"--set", "map.A=1", "--set", "map.h=1"}), 2,
                  {"1 - A h^2 = 0"});
  expect_rejected(run_config(config, {"--set", "map.B=4", "--set", "map.h=0.5"}), 2,
                  {"1 - B h^2 = 0"});
}

TEST_F(Cli, NonPositiveOrbitsAreRejected) {
  for (const char* orbits : {"0", "-3"}) {
    const std::string text = with_line(config, "orbits = ", std::string("orbits = ") + orbits);
    expect_rejected(run_config(text), 2,
                    {"cfg.toml:" + std::to_string(line_of(text, "orbits = ")) +
                     ": [ensemble] orbits must be > 0 (got " + orbits + ")"});
  }
}

TEST_F(Cli, BadRunSettingsAreRejected) {
  expect_rejected(run_config(config, {"--set", "run.steps=-1"}), 2,
                  {"--set run.steps must be >= 0"});
  expect_rejected(run_config(config, {"--set", "run.stride=0"}), 2,
                  {"--set run.stride must be >= 1"});
  expect_rejected(run_config(config, {"--set", "run.chains=3"}), 2,
                  {"run.chains must be 1, 2, 4 or 8"});
  expect_rejected(run_config(config, {"--set", "ensemble.q1=[1, 0]"}), 2, {"empty range"});
  expect_rejected(run_config(config, {"--set", "ensemble.start=leapfrog"}), 2,
                  {"--set ensemble.start: unknown start rule 'leapfrog'"});
}

TEST_F(Cli, UnknownConfigKeyNamesItsLine) {
  const std::string text = with_line(config, "steps = ", "steps = 50\nstepz = 5");
  expect_rejected(
      run_config(text), 2,
      {"cfg.toml:" + std::to_string(line_of(text, "stepz")) + ": [run] stepz: unknown key"});
}

// A misspelt required key is named as the unknown key it is, with its line, before the key it
// stands for is reported missing.
TEST_F(Cli, MisspeltRequiredKeyIsNamedBeforeTheMissingOne) {
  const std::string text = with_line(config, "steps = ", "stpes = 50");
  expect_rejected(run_config(text), 2,
                  {"cfg.toml:" + std::to_string(line_of(text, "stpes")) +
                   ": [run] unknown key 'stpes' (did you mean 'steps'?)"});
}

TEST_F(Cli, SetTakesBlanksAroundNameAndValue) {
  const Result r = run_config(config, {"--set", " run.steps = 20 "});
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(Contains(r.err, "x 20 steps")) << r.err;
}

TEST_F(Cli, CheckRejectsABadEscapeBoundAndTooManyOrbits) {
  const Result bound = run({"check", "--map", "suris", "--escape-bound", "-1"}, dir);
  EXPECT_EQ(bound.status, 2);
  EXPECT_TRUE(Contains(bound.err, "--escape-bound must be a finite number > 0 (got -1)"));
  const Result many = run({"check", "--map", "suris", "--orbits", "100000000000"}, dir);
  EXPECT_EQ(many.status, 2);
  EXPECT_TRUE(Contains(many.err, "--orbits must be at most 10000000")) << many.err;
}

TEST_F(Cli, MalformedTomlNamesItsLine) {
  const std::string text = with_line(config, "B = ", "B = = 0.3");
  expect_rejected(run_config(text), 2,
                  {"cfg.toml:" + std::to_string(line_of(text, "B = ")) + ":", "malformed TOML"});
}

TEST_F(Cli, UnwritableOutputIsAnIoError) {
  expect_rejected(run_config(config, {"--out", "/nonexistent-dir/x.h5"}), 3,
                  {"cannot write '/nonexistent-dir/x.h5': its folder '/nonexistent-dir'",
                   "No such file or directory"});
}

TEST_F(Cli, OutputPathThatIsADirectoryIsRefusedBeforeTheRun) {
  fs::create_directory(dir / "sub");
  const Result r = run_config(config, {"--out", "sub"});
  EXPECT_EQ(r.status, 3);
  EXPECT_TRUE(Contains(r.err, "output 'sub' is a directory"));
  EXPECT_FALSE(Contains(r.err, "particle-steps/s")) << "it must fail before running";
}

TEST_F(Cli, MapErrorsNameTheConfigSectionAndNumbersExactly) {
  const Result r = run_config(config, {"--set", "map.h=-1e-9"});
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(Contains(r.err, "cfg.toml:" + std::to_string(line_of(config, "[map]")) + ": [map]"));
  EXPECT_TRUE(Contains(r.err, "(got -1e-09)"));
}

TEST_F(Cli, EnsembleLargerThanMemoryIsAUsageErrorNotACrash) {
  expect_rejected(run_config(config, {"--set", "ensemble.orbits=10000000000000"}), 2,
                  {"10000000000000 orbits need about", "GiB; ", " is "});
  // Suris: 89 bytes per orbit (state 32, escape 9, invariant tracking 3 × 16), 8.9e14 bytes.
  expect_rejected(run_config(config, {"--set", "ensemble.orbits=10000000000000"}), 2,
                  {"need about 8.29e+05 GiB"});
}

TEST_F(Cli, BadObserverConfigurationIsRejectedNamingTheKey) {
  const std::string histogram = "\n[[histogram]]\nname = \"h\"\nx = \"q1\"\ny = \"q2\"\n"
                                "x_range = [-1.0, 1.0]\ny_range = [-1.0, 1.0]\n";
  expect_rejected(run_config(config + histogram + "bins = [0, 4]\n"), 2, {"[histogram[0]] bins must be > 0"});
  expect_rejected(run_config(config + histogram + "bins = [4, -1]\n"), 2, {"bins must be > 0"});
  expect_rejected(run_config(with_line(config + histogram, "x_range = ", "x_range = [1.0, 1.0]")), 2,
                  {"x_range is an empty range"});
  expect_rejected(run_config(with_line(config + histogram, "x = ", "x = \"q3\"")), 2,
                  {"unknown coordinate 'q3'"});
  expect_rejected(run_config(config + histogram + "colour = 1\n"), 2, {"colour: unknown key"});
  // Bins whose product overflows, and ranges whose width or bins per unit are not finite.
  expect_rejected(run_config(config + histogram + "bins = [4294967296, 4294967296]\n"), 2,
                  {"[histogram[0]] bins asks for more than 67108864 cells"});
  // The histograms together: each thread keeps a copy of every one.
  expect_rejected(run_config(config + histogram + "bins = [8192, 8192]\n" +
                             with_line(histogram, "name = ", "name = \"other\"") + "bins = 2\n"),
                  2, {"[histogram[1]] bins: 4 cells, with the 67108864 of the histograms and "
                      "sections before, exceed 67108864 cells in all"});
  expect_rejected(run_config(with_line(config + histogram, "x_range = ", "x_range = [0.0, 1e-320]")),
                  2, {"[histogram[0]] x_range must be finite"});
  expect_rejected(run_config(with_line(config + histogram, "x_range = ", "x_range = [-1e308, 1e308]")),
                  2, {"x_range must be finite"});
  expect_rejected(run_config(config + with_line(histogram, "name = ", "name = \"a\\u0000b\"")), 2,
                  {"[histogram[0]] name must be 1 to 255 printable characters"});
  const std::string section = "\n[[section]]\nname = \"s\"\nplane = \"q1\"\nx = \"q2\"\ny = \"p2\"\n"
                              "x_range = [-1.0, 1.0]\ny_range = [-1.0, 1.0]\n";
  expect_rejected(run_config(config + section + "cap = -1\n"), 2, {"[section[0]] cap must be >= 0"});
  expect_rejected(run_config(config + section + "direction = \"up\"\n"), 2, {"direction must be"});
  expect_rejected(run_config(config + section + "mode = \"cubic\"\n"), 2, {"mode must be"});
  // Mode exact integrates a flow: a discrete map has none, and a plane in p has no closed form.
  expect_rejected(run_config(config + section + "mode = \"exact\"\n"), 2,
                  {"[section[0]] mode: \"exact\" integrates a flow to the plane; map 'suris' is a "
                   "discrete map with no flow between iterates (use \"iterate\")"});
  const std::string flow = read_text(QMAPS_SOURCE_DIR "/ensembles/presets/leapfrog.toml");
  expect_rejected(run_config(flow + with_line(section, "plane = ", "plane = \"p1\"") +
                             "mode = \"exact\"\n"),
                  2, {"[section[1]] mode: \"exact\" needs a plane in q1 or q2 (the plane is p1)"});
  expect_rejected(run_config(config + histogram + "bins = 4\n" + with_line(section, "name = ", "name = \"h\"")),
                  2, {"[section[0]] name: 'h' is used twice"});
  expect_rejected(run_config(config + "\n[invariant_image]\nx = \"H\"\ny = \"K\"\n"
                                      "x_range = [0.0, 1.0]\ny_range = [0.0, 1.0]\n"),
                  2, {"'K' is not an invariant of map 'suris' (H, I1, I2)"});
}

TEST_F(Cli, FailedRunLeavesExistingOutputIdentical) {
  write_text(output, "an earlier run");
  const Result r = run_config(config, {"--set", "map.h=0"});
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(read_text(output), "an earlier run");
  EXPECT_FALSE(dir.has_entry_containing(".tmp-"));
}

TEST_F(Cli, UnknownSimdIsRejected) {
  expect_rejected(run_config(config, {"--simd", "neon"}), 2,
                  {"unknown SIMD instruction set 'neon'"});
}

TEST_F(Cli, MissingConfigFileIsAnIoError) {
  expect_rejected(run({"run", "missing.toml"}, dir), 3, {"cannot read config file 'missing.toml'"});
}

TEST_F(Cli, BadCommandLineIsAUsageError) {
  EXPECT_EQ(run({}, dir).status, 2);
  EXPECT_EQ(run({"frobnicate"}, dir).status, 2);
  EXPECT_EQ(run({"run"}, dir).status, 2);
  const Result threads = run_config(config, {"--threads", "0"});
  EXPECT_EQ(threads.status, 2);
  EXPECT_TRUE(Contains(threads.err, "--threads"));
  EXPECT_FALSE(fs::exists(output));
}

TEST_F(Cli, HelpExitsZeroAndListsOptions) {
  const Result top = run({"--help"}, dir);
  EXPECT_EQ(top.status, 0);
  for (const char* s : {"run", "orbit", "--version"}) EXPECT_TRUE(Contains(top.out, s));
  const Result run_help = run({"run", "--help"}, dir);
  EXPECT_EQ(run_help.status, 0);
  for (const char* s : {"config", "--resume", "--set", "--out", "--threads", "--simd", "--quiet"})
    EXPECT_TRUE(Contains(run_help.out, s));
  const Result orbit_help = run({"orbit", "--help"}, dir);
  EXPECT_EQ(orbit_help.status, 0);
  for (const char* s :
       {"--map", "--set", "--ic", "--steps", "--every", "--start", "--escape-bound"})
    EXPECT_TRUE(Contains(orbit_help.out, s));
}

TEST_F(Cli, ScalarSimdRuns) {
  const Result r = run_config(config, {"--simd", "scalar"});
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(Contains(r.err, "scalar, 1 thread)"));
  EXPECT_TRUE(fs::is_regular_file(output));
}

TEST_F(Cli, UnsupportedSimdExitsFour) {
  // An ISA of the list this build or this CPU cannot run; none when every one runs here.
  const auto runnable = runnable_isas();
  for (Isa isa : all_isas())
    if (std::find(runnable.begin(), runnable.end(), isa) == runnable.end()) {
      const std::string name(isa_name(isa));
      expect_rejected(run_config(config, {"--simd", name}), 4, {"--simd=" + name});
      return;
    }
  GTEST_SKIP() << "every ISA of the list runs here: none unsupported to request";
}

// ---- qmaps orbit ---------------------------------------------------------------------------

std::vector<std::string> orbit_args(const std::string& ic, const std::string& steps,
                                    const std::string& every, const std::string& start) {
  return {"orbit", "--map",     "suris", "--set",   "A=0.7", "--set", "B=0.3",
          "--set", "alpha=0.9", "--set", "h=0.1",   "--ic",  ic,      "--steps",
          steps,   "--every",   every,   "--start", start};
}

std::vector<std::vector<std::string>> csv_rows(const std::string& text) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> fields;
    std::istringstream cells(line);
    for (std::string cell; std::getline(cells, cell, ',');) fields.push_back(cell);
    rows.push_back(fields);
  }
  return rows;
}

TEST_F(Cli, OrbitPrintsEveryKthRowWithRoundTripDigitsEqual) {
  const Result r = run(orbit_args("0.1,0.2,0.3,0.4", "10", "5", "taylor"), dir);
  ASSERT_EQ(r.status, 0) << r.err;
  const auto rows = csv_rows(r.out);
  ASSERT_EQ(rows.size(), 4u);
  EXPECT_EQ(rows[0], (std::vector<std::string>{"n", "q1", "q2", "p1", "p2", "H", "I1", "I2",
                                               "H_cont", "I_case1_cont"}));
  for (std::size_t k = 1; k < rows.size(); ++k) {
    ASSERT_EQ(rows[k].size(), 10u);
    EXPECT_EQ(rows[k][0], std::to_string(5 * (k - 1)));
    for (std::size_t j = 1; j < 10; ++j) {  // each number printed with %.17g: it round-trips
      const double v = std::strtod(rows[k][j].c_str(), nullptr);
      char again[64];
      std::snprintf(again, sizeof again, "%.17g", v);
      EXPECT_EQ(rows[k][j], again);
    }
  }
  EXPECT_EQ(rows[1][1], "0.10000000000000001");
  EXPECT_EQ(std::strtod(rows[1][1].c_str(), nullptr), 0.1);
  EXPECT_EQ(std::strtod(rows[1][2].c_str(), nullptr), 0.2);
}

// --chaos adds λ, FLI and ⟨Y⟩; the other columns are the same bits as without it.
TEST_F(Cli, OrbitChaosColumnsFollowTheSameOrbit) {
  auto args = orbit_args("0.1,0.2,0.3,0.4", "20000", "10000", "taylor");
  const Result plain = run(args, dir);
  args.push_back("--chaos");
  const Result chaos = run(args, dir);
  ASSERT_EQ(chaos.status, 0) << chaos.err;
  const auto p = csv_rows(plain.out), c = csv_rows(chaos.out);
  ASSERT_EQ(c.size(), 4u);
  EXPECT_EQ(c[0], (std::vector<std::string>{"n", "q1", "q2", "p1", "p2", "H", "I1", "I2",
                                            "H_cont", "I_case1_cont", "lyapunov", "fli",
                                            "megno", "lyapunov_1", "lyapunov_2", "lyapunov_3",
                                            "lyapunov_4", "gali_2", "gali_4"}));
  EXPECT_EQ(c[1][10], "nan");  // λ and ⟨Y⟩ are not defined before a step
  EXPECT_EQ(c[1][11], "0");
  for (std::size_t k = 1; k < c.size(); ++k)
    EXPECT_EQ(std::vector<std::string>(c[k].begin(), c[k].begin() + 10), p[k]);
  const double lyapunov = std::strtod(c[3][10].c_str(), nullptr);
  const double megno = std::strtod(c[3][12].c_str(), nullptr);
  EXPECT_GT(lyapunov, 0);
  EXPECT_LT(lyapunov, std::log(20000.0) / 20000);  // a regular orbit: λ_n ≤ ln(n)/n
  EXPECT_NEAR(megno, 2.0, 0.2);  // 2 − O(ln(n)/n): 1.47 after 2000 steps, 1.87 after 20000
}

// A run's [chaos] and [[trajectory]]: a trajectory's rows are `qmaps orbit --chaos`'s for the
// same orbit, value for value (every path reproduces the scalar reference), /chaos holds the last
// row's indicators, and `qmaps info` summarises them.
TEST_F(Cli, ChaosAndTrajectoriesAgreeWithTheOrbitCommand) {
  const std::string extra =
      "\n[chaos]\nspectrum = true\n\n[[trajectory]]\nname = \"two\"\norbits = [5, 2]\n"
      "every = 10\n";
  const Result r = run_config(config + extra);
  ASSERT_EQ(r.status, 0) << r.err;
  const auto root = h5::File::open_read(output).root();
  const auto initial = root.open_group("initial");
  char ic[256];
  std::snprintf(ic, sizeof ic, "%.17g,%.17g,%.17g,%.17g", initial.read_doubles("q1", 100)[5],
                initial.read_doubles("q2", 100)[5], initial.read_doubles("p1", 100)[5],
                initial.read_doubles("p2", 100)[5]);
  auto args = orbit_args(ic, "50", "10", "taylor");
  args.push_back("--chaos");
  const Result orbit = run(args, dir);
  ASSERT_EQ(orbit.status, 0) << orbit.err;
  const auto rows = csv_rows(orbit.out);
  ASSERT_EQ(rows.size(), 7u);  // the header, steps 0, 10, …, 50
  const auto t = root.open_group("trajectories").open_group("two");
  const auto orbits = t.read_int64("orbit", 12), steps = t.read_int64("step", 12);
  for (std::size_t k = 0; k < 6; ++k) {
    EXPECT_EQ(orbits[k], 5);
    EXPECT_EQ(orbits[6 + k], 2);
    EXPECT_EQ(steps[k], static_cast<std::int64_t>(10 * k));
  }
  for (std::size_t j = 1; j < rows[0].size(); ++j) {  // every column but n
    const auto values = t.read_doubles(rows[0][j], 12);
    for (std::size_t k = 0; k < 6; ++k) {
      char text[64];
      std::snprintf(text, sizeof text, "%.17g", values[k]);
      EXPECT_EQ(text, rows[k + 1][j]) << rows[0][j] << " at step " << 10 * k;
    }
  }
  const auto chaos = root.open_group("chaos");
  for (const std::string name : {"lyapunov", "megno", "lyapunov_1", "gali_2"}) {
    char text[64];
    std::snprintf(text, sizeof text, "%.17g", chaos.read_doubles(name, 100)[5]);
    const auto column = std::find(rows[0].begin(), rows[0].end(), name) - rows[0].begin();
    EXPECT_EQ(text, rows[6][static_cast<std::size_t>(column)]) << name;
  }
  const Result info = run({"info", output}, dir);
  ASSERT_EQ(info.status, 0) << info.err;
  for (const std::string part : {"chaos:      ", " regular (MEGNO above / not above 3), 0 escaped",
                                 "  megno", "  log10_gali_2", "median "})
    EXPECT_TRUE(Contains(info.out, part)) << info.out;
}

// Bad [chaos] and [[trajectory]] keys are usage errors naming the key, before anything runs.
TEST_F(Cli, BadChaosAndTrajectoryKeysAreNamed) {
  expect_rejected(run_config(config + "\n[chaos]\northonormalize_every = 0\n"), 2,
                  {"[chaos] orthonormalize_every must be 1 to 1000 (got 0)"});
  expect_rejected(run_config(config + "\n[chaos]\nmegno_threshold = -1\n"), 2,
                  {"[chaos] megno_threshold must be a positive number"});
  expect_rejected(run_config(config + "\n[chaos]\nspectrum = 3\n"), 2, {"[chaos] spectrum"});
  const std::string t = "\n[[trajectory]]\nname = \"a\"\n";
  expect_rejected(run_config(config + t + "orbits = [1, 100]\n"), 2,
                  {"[trajectory[0]] orbits: orbit 100 is not in the ensemble's 0 to 99"});
  expect_rejected(run_config(config + t + "orbits = [1]\nfirst = 3\n"), 2,
                  {"give either orbits = [i, j, ...] or first = N"});
  expect_rejected(run_config(config + t + "first = 3\nevery = 0\n"), 2,
                  {"[trajectory[0]] every must be >= 1"});
  expect_rejected(run_config(config + t + "first = 100\n", {"--set", "run.steps=10000000"}), 2,
                  {"rows; at most 67108864"});
}

// H_cont and the case's second integral of the continuous system at the phase point: on a map
// they oscillate at O(h²) while the map's own invariants hold to round-off; on the flow they are
// its own invariants, the same bits.
TEST_F(Cli, OrbitShowsTheContinuousIntegralsBesideTheMapsInvariants) {
  const auto rows = csv_rows(run(orbit_args("0.1,0.2,0.3,0.4", "1000", "10", "taylor"), dir).out);
  ASSERT_EQ(rows.size(), 102u);
  double spread_map = 0, spread_cont = 0;
  const double H0 = std::strtod(rows[1][5].c_str(), nullptr);
  const double C0 = std::strtod(rows[1][8].c_str(), nullptr);
  for (std::size_t k = 1; k < rows.size(); ++k) {
    spread_map = std::max(spread_map, std::fabs(std::strtod(rows[k][5].c_str(), nullptr) - H0));
    spread_cont = std::max(spread_cont, std::fabs(std::strtod(rows[k][8].c_str(), nullptr) - C0));
  }
  EXPECT_LT(spread_map, 1e-13);  // the map's H: round-off
  EXPECT_GT(spread_cont, 1e-5);  // the continuous H along the map's orbit: O(h²) = O(1e-2)·H
  EXPECT_LT(spread_cont, 1e-2);
  const auto flow = csv_rows(run({"orbit", "--map", "flow", "--set", "A=0.7", "--set", "B=0.3",
                                  "--set", "alpha=0.9", "--set", "beta=0.9", "--set", "delta=1.8",
                                  "--set", "h=0.1", "--ic", "0.1,0.2,0.3,0.4", "--steps", "20",
                                  "--every", "10"},
                                 dir).out);
  ASSERT_EQ(flow[0], (std::vector<std::string>{"n", "q1", "q2", "p1", "p2", "H", "I_case1",
                                               "H_cont", "I_case1_cont"}));
  for (std::size_t k = 1; k < flow.size(); ++k) {
    EXPECT_EQ(flow[k][5], flow[k][7]);
    EXPECT_EQ(flow[k][6], flow[k][8]);
  }
}

// --energy E: p2 solved from the continuous H, the sign of --ic's p2 kept. On the flow, whose
// state is the phase point, H_cont at n = 0 is E to round-off; a map's n = 0 row shows its own
// p (a central difference), O(h²) away.
TEST_F(Cli, OrbitEnergyPlacesTheInitialConditionOnTheEnergySurface) {
  for (const char* p2 : {"0.4", "-0.4"}) {
    const Result r = run({"orbit", "--map", "flow", "--set", "A=0.7", "--set", "B=0.3", "--set",
                          "alpha=0.9", "--set", "beta=0.9", "--set", "delta=1.8", "--set", "h=0.1",
                          "--ic", std::string("0.1,0.2,0.3,") + p2, "--steps", "0", "--energy",
                          "0.25"},
                         dir);
    ASSERT_EQ(r.status, 0) << r.err;
    const auto rows = csv_rows(r.out);
    EXPECT_NEAR(std::strtod(rows[1][7].c_str(), nullptr), 0.25, 1e-15);  // H_cont = E
    EXPECT_EQ(std::strtod(rows[1][4].c_str(), nullptr) < 0, p2[0] == '-');
  }
  auto low = orbit_args("0.1,0.2,0.3,0.4", "0", "1", "taylor");
  low.insert(low.end(), {"--energy", "0.01"});
  expect_rejected(run(low, dir), 2, {"--energy 0.01: below the energy", "no p2 reaches it"});
}

TEST_F(Cli, OrbitEulerStartDiffersFromTaylorAtStepOne) {
  const Result taylor = run(orbit_args("0.1,0.2,0.3,0.4", "1", "1", "taylor"), dir);
  const Result euler = run(orbit_args("0.1,0.2,0.3,0.4", "1", "1", "euler"), dir);
  ASSERT_EQ(taylor.status, 0) << taylor.err;
  ASSERT_EQ(euler.status, 0) << euler.err;
  const auto t = csv_rows(taylor.out), e = csv_rows(euler.out);
  ASSERT_EQ(t.size(), 3u);
  ASSERT_EQ(e.size(), 3u);
  EXPECT_EQ(t[1][1], e[1][1]);  // n = 0: the same q
  EXPECT_NE(t[2][1], e[2][1]);  // n = 1: different q1
  EXPECT_NE(t[2][2], e[2][2]);
}

TEST_F(Cli, OrbitBadInputIsRejected) {
  EXPECT_EQ(run(orbit_args("0.1,0.2", "10", "1", "taylor"), dir).status, 2);
  EXPECT_EQ(run(orbit_args("0.1,0.2,0.3,nan", "10", "1", "taylor"), dir).status, 2);
  EXPECT_EQ(run(orbit_args("0.1,0.2,0.3,0.4", "-1", "1", "taylor"), dir).status, 2);
  EXPECT_EQ(run(orbit_args("0.1,0.2,0.3,0.4", "10", "0", "taylor"), dir).status, 2);
  const Result start = run(orbit_args("0.1,0.2,0.3,0.4", "10", "1", "midpoint"), dir);
  EXPECT_EQ(start.status, 2);
  EXPECT_TRUE(Contains(start.err, "unknown start rule 'midpoint'"));
  const Result missing =
      run({"orbit", "--map", "suris", "--set", "A=0.7", "--ic", "0,0,0,0", "--steps", "1"}, dir);
  EXPECT_EQ(missing.status, 2);
  EXPECT_TRUE(Contains(missing.err, "parameter 'B' is missing"));
}

// ---- ensemble kinds: bad input ---------------------------------------------------------------

namespace kinds {

// The preset's [map], [run] and [output] with this [ensemble] (the preset's is cut out).
std::string with_ensemble(const std::string& config, const std::string& ensemble) {
  const auto begin = config.find("[ensemble]"), end = config.find("[run]");
  return config.substr(0, begin) + "[ensemble]\n" + ensemble + "\n" + config.substr(end);
}

const std::string kShell =
    "kind = \"shell\"\nenergy = 0.2\norbits = 50\nq1 = [-0.5, 0.5]\n"
    "q2 = [-0.5, 0.5]\np1 = [-0.5, 0.5]\n";
const std::string kGrid =
    "kind = \"grid\"\naxes = [\"q1\", \"p1\"]\npoints = [4, 4]\n"
    "q1 = [-0.5, 0.5]\np1 = [-0.5, 0.5]\nq2 = 0.1\np2 = 0.0\n";
const std::string kLine =
    "kind = \"line\"\norbits = 5\nfrom = [0.0, 0.0, 0.0, 0.0]\n"
    "to = [0.5, 0.0, 0.0, 0.5]\n";

}  // namespace kinds

TEST_F(Cli, EveryEnsembleKindRunsAndTheShellReportsItsRejections) {
  for (const auto& ensemble : {kinds::kShell, kinds::kGrid, kinds::kLine}) {
    const Result r = run_config(kinds::with_ensemble(config, ensemble));
    EXPECT_EQ(r.status, 0) << ensemble << r.err;
  }
  const Result shell = run_config(kinds::with_ensemble(config, kinds::kShell));
  EXPECT_TRUE(Contains(shell.err, "qmaps: suris, 50 orbits x 50 steps"));
  EXPECT_TRUE(Contains(shell.err, " rejected -> "));
}

TEST_F(Cli, BadEnsembleOfEveryKindIsRejectedWithoutOutput) {
  using kinds::with_ensemble;
  const auto rejected = [&](const std::string& ensemble, std::vector<std::string> extra, int code,
                            const std::vector<std::string>& parts) {
    const std::string text = with_ensemble(config, ensemble);
    expect_rejected(run_config(text, extra), code, parts);
  };
  // box, grid, shell, line: an empty range
  rejected(with_line(config.substr(config.find("[ensemble]") + 11,
                                   config.find("[run]") - config.find("[ensemble]") - 11),
                     "q1 = ", "q1 = [0.5, -0.5]"),
           {}, 2, {"[ensemble] q1 is an empty range"});
  rejected(kinds::kGrid, {"--set", "ensemble.p1=[0.3, 0.3]"}, 2,
           {"--set ensemble.p1 is an empty range: 4 grid points need lo < hi"});
  rejected(kinds::kShell, {"--set", "ensemble.q2=[0.3, -0.3]"}, 2, {"empty range"});
  rejected(kinds::kLine, {"--set", "ensemble.to=[0.0, 0.0, 0.0, 0.0]"}, 2,
           {"--set ensemble.to is the same point as [ensemble] from"});
  // grid: 0 points, a wrong axis, a range for a fixed coordinate, an orbit count
  rejected(kinds::kGrid, {"--set", "ensemble.points=[0, 4]"}, 2,
           {"--set ensemble.points must be > 0 (got 0)"});
  rejected(kinds::kGrid, {"--set", "ensemble.axes=[\"q1\", \"q3\"]"}, 2,
           {"unknown coordinate 'q3'"});
  rejected(kinds::kGrid, {"--set", "ensemble.q2=[0, 1]"}, 2,
           {"--set ensemble.q2 must be one number: the grid's other coordinates are fixed"});
  rejected(kinds::kGrid, {"--set", "ensemble.orbits=16"}, 2, {"set [ensemble] points instead"});
  // a grid beyond memory: its points are named, not orbits
  rejected(kinds::kGrid, {"--set", "ensemble.points=[100000000, 100000000]"}, 2,
           {"--set ensemble.points: 10000000000000000 orbits need about"});
  // shell: E below the potential's minimum (random and grid), a range for the solved coordinate
  rejected(kinds::kShell, {"--set", "ensemble.energy=-0.1"}, 2,
           {"--set ensemble.energy: orbit 0 found no point of H = -0.1 in 1000 draws"});
  rejected(kinds::kShell + "sampling = \"grid\"\npoints = 5\n",
           {"--set", "ensemble.energy=-0.1", "--set", "ensemble.orbits=1"}, 2,
           {"a shell grid has one orbit per accepted point"});
  expect_rejected(run_config(with_ensemble(config, with_line(kinds::kShell, "orbits = ", "") +
                                                       "sampling = \"grid\"\npoints = 5\n"),
                             {"--set", "ensemble.energy=-0.1"}),
                  2, {"no point of the grid lies on H = -0.1"});
  rejected(kinds::kShell + "p2 = [0.0, 0.1]\n", {}, 2,
           {"[ensemble] p2: this coordinate is solved from H = E"});
  rejected(kinds::kShell, {"--set", "ensemble.sign=up"}, 2, {"sign must be \"+\" or \"-\""});
  // line: not a point
  rejected(kinds::kLine, {"--set", "ensemble.from=[0.0, 1.0]"}, 2,
           {"--set ensemble.from must be an array of 4 finite numbers"});
  // file: missing, not HDF5, not qmaps, another map, other parameters
  rejected("kind = \"file\"\npath = \"missing.h5\"\n", {}, 3,
           {"[ensemble] path: cannot read 'missing.h5'"});
  write_text(dir / "text.h5", "not hdf5");
  rejected("kind = \"file\"\npath = \"text.h5\"\n", {}, 3, {"'text.h5' is not an HDF5 file"});
  const Result earlier = run_config(config, {"--out", "earlier.h5", "--set", "map.A=0.5"});
  ASSERT_EQ(earlier.status, 0) << earlier.err;
  rejected("kind = \"file\"\npath = \"earlier.h5\"\n", {}, 2,
           {"'earlier.h5' holds a run of suris (A = 0.5, B = 0.3, alpha = 0.9, h = 0.1), not of "
            "this run's suris (A = 0.7, B = 0.3, alpha = 0.9, h = 0.1)"});
  rejected("kind = \"file\"\npath = \"earlier.h5\"\n",
           {"--set", "map.name=case2", "--set", "map.B=0.3"}, 2, {"no parameter 'B'"});
  const std::string case2 = with_line(with_line(config, "name = ", "name = \"case2\""), "B = ", "");
  expect_rejected(run_config(with_ensemble(case2, "kind = \"file\"\npath = \"earlier.h5\"\n")), 2,
                  {"holds a run of suris (A = 0.5, B = 0.3, alpha = 0.9, h = 0.1), not of this "
                   "run's case2 (A = 0.7, alpha = 0.9, h = 0.1)"});
  rejected("kind = \"file\"\npath = \"earlier.h5\"\ngroup = \"middle\"\n", {}, 2,
           {"group must be \"final\" or \"initial\""});
  // unknown kind, unknown key
  rejected("kind = \"sphere\"\norbits = 3\n", {}, 2,
           {"unknown ensemble kind 'sphere' (known: box, grid, shell, line, file)"});
  const std::string line_text = with_ensemble(config, kinds::kLine + "spacing = 2\n");
  expect_rejected(run_config(line_text), 2,
                  {"cfg.toml:" + std::to_string(line_of(line_text, "spacing")) +
                   ": [ensemble] spacing: unknown key"});
}

TEST_F(Cli, SetReachesArraysOfTablesInRun) {
  const std::string histogram =
      "\n[[histogram]]\nname = \"h\"\nx = \"q1\"\nx_range = [-1.0, 1.0]\n";
  const Result r = run_config(config + histogram, {"--set", "histogram[0].bins=7"});
  ASSERT_EQ(r.status, 0) << r.err;
  const Result info = run({"info", output}, dir);
  EXPECT_TRUE(Contains(info.out, "h: 7 bins over q1")) << info.out;
  fs::remove(output);
  expect_rejected(run_config(config + histogram, {"--set", "histogram[0].colour=1"}), 2,
                  {"--set histogram[0].colour: unknown key"});
  expect_rejected(run_config(config + histogram, {"--set", "histogram.bins=7"}), 2,
                  {"name one as histogram[i].bins"});
}

// ---- list, info, check -----------------------------------------------------------------------

TEST_F(Cli, ListPrintsEveryMapWithParametersInvariantsAndEquations) {
  const Result r = run({"list"}, dir);
  ASSERT_EQ(r.status, 0) << r.err;
  for (const MapEntry& m : catalogue()) {
    const std::string map = std::string(m.name) + ":";
    EXPECT_TRUE(Contains(r.out, "\n" + map) || r.out.rfind(map, 0) == 0) << map;
  }
  for (const char* part :
       {"invariants: H, I1, I2 (A != B); H, L (A = B)", "(disc-hamilton2)", "(discrete-case2-2)",
        "(levi)", "t_order", "(default 2)",
        "order   order of the composition: 2, 4, 6 or 8 (default 6)",
        "h       time step, > 0 (required)", "gamma11", "(optional)", "invariants: I_1, I_2"})
    EXPECT_TRUE(Contains(r.out, part));
}

TEST_F(Cli, InfoSummarisesARun) {
  const std::string observers =
      "\n[[histogram]]\nname = \"q1q2\"\nx = \"q1\"\ny = \"q2\"\nx_range = [-1.0, 1.0]\n"
      "y_range = [-1.0, 1.0]\nbins = [8, 4]\n"
      "\n[[section]]\nname = \"up\"\nplane = \"q1\"\nx = \"q2\"\ny = \"p2\"\ncap = 3\n"
      "x_range = [-1.0, 1.0]\ny_range = [-1.0, 1.0]\nbins = 4\n";
  ASSERT_EQ(run_config(config + observers, {"--set", "run.escape_bound=0.6"}).status, 0);
  const Result r = run({"info", output}, dir);
  ASSERT_EQ(r.status, 0) << r.err;
  const auto f = h5::File::open_read(output);
  const auto root = f.root();
  const auto escaped = std::to_string(root.attr_int64("escaped"));
  const std::string crossings =
      std::to_string(root.open_group("sections").open_group("up").attr_int64("crossings"));
  for (const std::string& part : std::vector<std::string>{
           "map:        suris (A = 0.7, B = 0.3, alpha = 0.9, h = 0.1)\n",
           "ensemble:   box: 100 orbits uniform in", "orbits:     100, steps 50, start taylor",
           "escaped:    " + escaped + " (" + escaped + " beyond bound)\n", "  H     worst ",
           "  I1    worst ", "  I2    worst ", "q1q2: 8 x 4 bins over q1 x q2",
           "up: q1 = 0 (+, iterate), " + crossings + " crossings"})
    EXPECT_TRUE(Contains(r.out, part));
  EXPECT_NE(escaped, "0") << "a bound of 0.6 lets some orbits escape";
}

// A run written without per-orbit datasets has its counts and histograms summarised.
TEST_F(Cli, InfoSummarisesARunWithoutPerOrbitData) {
  ASSERT_EQ(run_config(config, {"--set", "output.per_orbit=false"}).status, 0);
  const Result r = run({"info", output}, dir);
  ASSERT_EQ(r.status, 0) << r.err;
  for (const std::string& part : std::vector<std::string>{
           "escaped:    0\n", "(no per-orbit data: its histogram of log10)\n",
           "  H     72 bins over log10_relative_drift, 100 samples"})
    EXPECT_TRUE(Contains(r.out, part)) << r.out;
}

TEST_F(Cli, InfoRejectsMissingAndForeignFiles) {
  const Result missing = run({"info", "missing.h5"}, dir);
  EXPECT_EQ(missing.status, 3);
  EXPECT_TRUE(Contains(missing.err, "qmaps: error: cannot read 'missing.h5'"));
  write_text(dir / "text.h5", "not hdf5");
  const Result text = run({"info", "text.h5"}, dir);
  EXPECT_EQ(text.status, 3);
  EXPECT_TRUE(Contains(text.err, "'text.h5' is not an HDF5 file"));
  {
    h5::AtomicFile other(dir / "other.h5");
    auto file = other.create_hdf5();
    file.root().attr("title", "someone else's data");
    file.close();
    other.commit();
  }
  const Result foreign = run({"info", "other.h5"}, dir);
  EXPECT_EQ(foreign.status, 3);
  EXPECT_TRUE(Contains(foreign.err, "'other.h5' is not a qmaps output file"));
}

TEST_F(Cli, CheckReportsDriftPercentilesAndReversibility) {
  const Result r = run({"check", "--map", "suris", "--orbits", "200", "--steps", "300"}, dir);
  ASSERT_EQ(r.status, 0) << r.err;
  for (const char* part :
       {"map suris (A = 0.7, B = 0.3, alpha = 0.9, h = 0.1): 200 orbits uniform in [-0.5, 0.5]^4 "
        "(seed 1), 300 steps, 0 escaped",
        "\ninvariants checked: H, I1, I2 (those the map has at these parameters; ",
        "invariant     median        90%        99%      worst", "\n  H    ", "\n  I1   ",
        "\n  I2   ",
        "reversibility: 300 steps forward, reversed, 300 back: max |(q, p) - (q0, p0)| = "})
    EXPECT_TRUE(Contains(r.out, part));
  // The worst drift and the reversibility error of an integrable map are round-off.
  std::istringstream in(r.out.substr(r.out.find("\n  H ")));
  std::string name;
  double median = 0, p90 = 0, p99 = 0, worst = 1;
  in >> name >> median >> p90 >> p99 >> worst;
  EXPECT_EQ(name, "H");
  EXPECT_LE(median, p90);
  EXPECT_LE(p99, worst);
  EXPECT_LT(worst, 1e-11);
  const double reversibility = std::strtod(r.out.substr(r.out.rfind("= ") + 2).c_str(), nullptr);
  EXPECT_LT(reversibility, 1e-10);
  for (const MapEntry& m : catalogue()) {  // each with its example's parameters
    const std::string map(m.name);
    const Result other = run({"check", "--map", map, "--orbits", "64", "--steps", "100"}, dir);
    EXPECT_EQ(other.status, 0) << map << other.err;
    EXPECT_TRUE(Contains(other.out, "reversibility: ")) << map;
  }
  const Result bad = run({"check", "--map", "suris", "--set", "h=0"}, dir);
  EXPECT_EQ(bad.status, 2);
  EXPECT_TRUE(Contains(bad.err, "h must be > 0"));
  EXPECT_EQ(run({"check", "--map", "nosuch"}, dir).status, 2);
}

}  // namespace
}  // namespace qmaps::testing
