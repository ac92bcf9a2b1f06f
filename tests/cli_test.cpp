// The qmaps command line, run as a process: a valid run, every kind of bad input (a clear message,
// the right exit code, no file left behind), `qmaps orbit` output, --help and --simd.
#include <gtest/gtest.h>
#include <pty.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

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

TEST_F(Cli, SmallRunWritesFileAndOneLineSummary) {
  const Result r = run_config(config);
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out, "");
  EXPECT_TRUE(Contains(r.err, "qmaps: suris, 100 orbits x 50 steps in "));
  EXPECT_TRUE(Contains(r.err, "0 escaped -> " + output + "\n"));
  EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << "one line: " << r.err;
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
                  {"unknown start rule 'leapfrog'"});
}

TEST_F(Cli, UnknownConfigKeyNamesItsLine) {
  const std::string text = with_line(config, "steps = ", "steps = 50\nstepz = 5");
  expect_rejected(
      run_config(text), 2,
      {"cfg.toml:" + std::to_string(line_of(text, "stepz")) + ": [run] stepz: unknown key"});
}

TEST_F(Cli, MalformedTomlNamesItsLine) {
  const std::string text = with_line(config, "B = ", "B = = 0.3");
  expect_rejected(run_config(text), 2,
                  {"cfg.toml:" + std::to_string(line_of(text, "B = ")) + ":", "malformed TOML"});
}

TEST_F(Cli, UnwritableOutputIsAnIoError) {
  expect_rejected(run_config(config, {"--out", "/nonexistent-dir/x.h5"}), 3,
                  {"cannot create output file", "/nonexistent-dir/x.h5"});
}

TEST_F(Cli, OutputPathThatIsADirectoryIsRefusedBeforeTheRun) {
  fs::create_directory(dir / "sub");
  const Result r = run_config(config, {"--out", "sub"});
  EXPECT_EQ(r.status, 3);
  EXPECT_TRUE(Contains(r.err, "output path 'sub' is a directory"));
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
                  {"10000000000000 orbits need about", "GiB; this machine has"});
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
  const std::string section = "\n[[section]]\nname = \"s\"\nplane = \"q1\"\nx = \"q2\"\ny = \"p2\"\n"
                              "x_range = [-1.0, 1.0]\ny_range = [-1.0, 1.0]\n";
  expect_rejected(run_config(config + section + "cap = -1\n"), 2, {"[section[0]] cap must be >= 0"});
  expect_rejected(run_config(config + section + "direction = \"up\"\n"), 2, {"direction must be"});
  expect_rejected(run_config(config + section + "mode = \"cubic\"\n"), 2, {"mode must be"});
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
  __builtin_cpu_init();
#ifdef QMAPS_HAVE_AVX512
  if (__builtin_cpu_supports("avx512f"))
    GTEST_SKIP() << "this CPU supports avx512: no unsupported ISA to request";
#endif
  expect_rejected(run_config(config, {"--simd", "avx512"}), 4, {"--simd=avx512"});
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
  EXPECT_EQ(rows[0], (std::vector<std::string>{"n", "q1", "q2", "p1", "p2", "H", "I1", "I2"}));
  for (std::size_t k = 1; k < rows.size(); ++k) {
    ASSERT_EQ(rows[k].size(), 8u);
    EXPECT_EQ(rows[k][0], std::to_string(5 * (k - 1)));
    for (std::size_t j = 1; j < 8; ++j) {  // each number printed with %.17g: it round-trips
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

}  // namespace
}  // namespace qmaps::testing
