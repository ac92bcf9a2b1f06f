// The HDF5 file of a run (docs/hdf5-schema.md), read back as written by the qmaps binary; a
// killed run leaves no file under the final name; AtomicFile commits by rename.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <regex>
#include <string>
#include <vector>

#include <sys/wait.h>
#include <unistd.h>

#include "ensembles/config/config.hpp"
#include "core/error.hpp"
#include "core/isa.hpp"
#include "ensembles/io/h5.hpp"
#include "core/version.hpp"
#include "kernels/suris.hpp"
#include "run_process.hpp"
#include "h5_read.hpp"

namespace qmaps::testing {
namespace {

using kernels::Suris;
using State = Suris::State<double>;

const std::vector<std::string> kInvariants = {"H", "I1", "I2"};

std::string edited(std::string text,
                   const std::vector<std::pair<std::string, std::string>>& edits) {
  for (const auto& [prefix, line] : edits) text = with_line(text, prefix, line);
  return text;
}

// The preset (100 orbits, 50 steps) with a box whose ranges differ, run with `extra` options.
class Io : public ::testing::Test {
 protected:
  TempDir dir;
  const std::string output = dir / "run.h5";
  std::string config = edited(preset_config(output), {{"seed = ", "seed = 7"},
                                                      {"q1 = ", "q1 = [0.1, 0.2]"},
                                                      {"q2 = ", "q2 = 0.3"},
                                                      {"p2 = ", "p2 = [0, 0.001]"},
                                                      {"stride = ", "stride = 7"}});

  std::vector<h5::File> files;  // open for as long as the test

  // Runs the binary on `config` and opens the file it wrote (at `path`, when given).
  h5::Group run_root(std::vector<std::string> extra = {}, const std::string& path = "") {
    write_text(dir / "cfg.toml", config);
    extra.insert(extra.begin(), {"run", "cfg.toml"});
    if (!path.empty()) extra.insert(extra.end(), {"--out", path});
    const Result r = run(extra, dir);
    EXPECT_EQ(r.status, 0) << r.err;
    files.push_back(h5::File::open_read(path.empty() ? output : path));
    return files.back().root();
  }
};

std::vector<std::uint8_t> read_uint8(const h5::Group& g, const std::string& name) {
  h5::Handle d(H5Dopen2(g.id(), name.c_str(), H5P_DEFAULT), H5Dclose);
  h5::Handle s(H5Dget_space(d.id()), H5Sclose);
  std::vector<std::uint8_t> out(static_cast<std::size_t>(H5Sget_simple_extent_npoints(s.id())));
  H5Dread(d.id(), H5T_NATIVE_UINT8, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data());
  return out;
}

const Suris::Coeffs& coeffs() {  // the preset's parameters
  static const Suris::Coeffs c = Suris::coefficients(std::vector<double>{0.7, 0.3, 0.9, 0.1});
  return c;
}

std::vector<State> read_states(const h5::Group& state) {
  std::vector<std::vector<double>> columns;
  for (const char* name : {"q1_n", "q2_n", "q1_n+1", "q2_n+1"})
    columns.push_back(testing::all_doubles(state, name));
  std::vector<State> out(columns[0].size());
  for (std::size_t i = 0; i < out.size(); ++i)
    out[i] = {columns[0][i], columns[1][i], columns[2][i], columns[3][i]};
  return out;
}

std::vector<Phase> read_phases(const h5::Group& g) {
  const auto q1 = testing::all_doubles(g, "q1"), q2 = testing::all_doubles(g, "q2"), p1 = testing::all_doubles(g, "p1"),
             p2 = testing::all_doubles(g, "p2");
  std::vector<Phase> out(q1.size());
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = {q1[i], q2[i], p1[i], p2[i]};
  return out;
}

TEST_F(Io, RootAttributesHoldTheRun) {
  const auto root = run_root({"--simd", "scalar"});
  EXPECT_EQ(root.attr_int64("schema_version"), 1);
  EXPECT_EQ(root.attr_string("qmaps_version"), build::version);
  EXPECT_EQ(root.attr_string("git_commit"), build::commit);
  EXPECT_EQ(root.attr_string("compiler"), build::compiler);
  EXPECT_EQ(root.attr_string("compiler_flags"), build::engine_flags);
  EXPECT_TRUE(Contains(root.attr_string("compiler_flags"), "-ffp-contract=off"));
  EXPECT_EQ(root.attr_string("kernel_flags"), kernel_flags());
  EXPECT_EQ(root.attr_int64("per_orbit"), 1);
  EXPECT_EQ(root.attr_string("map"), "suris");
  EXPECT_EQ(root.attr_double("param.A"), 0.7);
  EXPECT_EQ(root.attr_double("param.B"), 0.3);
  EXPECT_EQ(root.attr_double("param.alpha"), 0.9);
  EXPECT_EQ(root.attr_double("param.h"), 0.1);
  EXPECT_EQ(root.attr_int64("steps"), 50);
  EXPECT_EQ(root.attr_double("time"), 50 * 0.1);
  EXPECT_EQ(root.attr_int64("orbits"), 100);
  EXPECT_EQ(root.attr_string("ensemble"), "box");
  EXPECT_EQ(root.attr_string("ensemble_description"),
            "box: 100 orbits uniform in q1 [0.1, 0.2], q2 0.3, p1 [-0.5, 0.5], p2 [0, 0.001], "
            "seed 7");
  EXPECT_EQ(root.attr_int64("seed"), 7);
  EXPECT_EQ(root.attr_int64("rejected"), 0);
  EXPECT_EQ(root.attr_string("start"), "taylor");
  EXPECT_EQ(root.attr_int64("stride"), 7);
  EXPECT_EQ(root.attr_double("escape_bound"), 1e8);
  EXPECT_EQ(root.attr_int64("escaped"), 0);
  EXPECT_EQ(root.attr_string("isa"), "scalar");
  EXPECT_EQ(root.attr_int64("threads"), 1);
  EXPECT_EQ(root.attr_int64("chains"), 8);
  EXPECT_EQ(root.attr_string("config"), config);
  const Config resolved = Config::parse(root.attr_string("config_resolved"), "config_resolved");
  EXPECT_EQ(resolved.integer("run", "steps"), 50);
  EXPECT_EQ(resolved.string("output", "file"), output);
  EXPECT_EQ(root.attr_string("command_line"),
            std::string(QMAPS_BINARY) + " run cfg.toml --simd scalar");
  const std::regex iso(R"(\d{4}-\d\d-\d\dT\d\d:\d\d:\d\dZ)");
  EXPECT_TRUE(std::regex_match(root.attr_string("started"), iso));
  EXPECT_TRUE(std::regex_match(root.attr_string("finished"), iso));
  EXPECT_LE(root.attr_string("started"), root.attr_string("finished"));
  // One session: steps 0-50, the path, the threads, its start and end, the command line.
  EXPECT_EQ(root.attr_string("sessions"),
            "steps 0-50, scalar, 1 thread, " + root.attr_string("started") + " to " +
                root.attr_string("finished") + ": " + root.attr_string("command_line") + "\n");
}

// Names, types and shapes are checked against docs/hdf5-schema.md by tests/schema_test.py; here
// what they hold: no observer groups unless configured, the state's step, every orbit in its
// drift histogram once, the reason codes.
TEST_F(Io, GroupsHoldTheRun) {
  const auto root = run_root();
  EXPECT_EQ(root.members(), (std::vector<std::string>{"escape", "final", "initial", "invariants"}));
  EXPECT_EQ(root.open_group("final").open_group("state").attr_int64("step"), 50);
  const auto invariants = root.open_group("invariants");
  EXPECT_EQ(invariants.members(), kInvariants);
  for (const auto& name : kInvariants) {
    const auto drift = invariants.open_group(name).open_group("drift_histogram");
    std::int64_t total = drift.attr_int64("zero") + drift.attr_int64("underflow") +
                         drift.attr_int64("overflow");
    for (auto c : testing::all_int64(drift, "counts")) total += c;
    EXPECT_EQ(total, 100) << "every orbit counts once";
  }
  EXPECT_EQ(root.open_group("escape").attr_string("reason_codes"),
            "0 none, 1 non-finite, 2 beyond bound, 3 solver did not converge, 4 solver derivative vanished, 5 solver root off the physical branch, 6 linear equations singular");
}

TEST_F(Io, WithoutPerOrbitDatasetsOnlyHistogramsAreWritten) {
  const auto full = run_root();
  const auto root = run_root({"--set", "output.per_orbit=false"}, dir / "small.h5");
  EXPECT_EQ(root.attr_int64("per_orbit"), 0);
  EXPECT_EQ(root.attr_int64("escaped"), full.attr_int64("escaped"));
  EXPECT_EQ(root.members(), (std::vector<std::string>{"invariants"}));
  for (const auto& name : kInvariants) {
    const auto g = root.open_group("invariants").open_group(name);
    EXPECT_EQ(g.members(), (std::vector<std::string>{"drift_histogram"}));
    EXPECT_EQ(testing::all_int64(g.open_group("drift_histogram"), "counts"),
              testing::all_int64(full.open_group("invariants").open_group(name).open_group("drift_histogram"), "counts"));
  }
}

TEST_F(Io, InitialPointsLieInTheBox) {
  const auto initial = read_phases(run_root().open_group("initial"));
  ASSERT_EQ(initial.size(), 100u);
  for (const auto& x : initial) {
    EXPECT_TRUE(x.q1 >= 0.1 && x.q1 <= 0.2) << x.q1;
    EXPECT_EQ(x.q2, 0.3);
    EXPECT_TRUE(x.p1 >= -0.5 && x.p1 <= 0.5) << x.p1;
    EXPECT_TRUE(x.p2 >= 0 && x.p2 <= 0.001) << x.p2;
  }
}

// /final is the kernel's phase of /final/state (central difference), /invariants/*/final its
// invariants, /invariants/*/initial those of the start; never escaped: drift ≥ |final − initial|.
TEST_F(Io, FinalPhaseAndInvariantsEqualKernelOfState) {
  const auto root = run_root();
  const auto initial = read_phases(root.open_group("initial"));
  const auto final = read_phases(root.open_group("final"));
  const auto states = read_states(root.open_group("final").open_group("state"));
  const auto steps = testing::all_int64(root.open_group("escape"), "step");
  const auto inv = root.open_group("invariants");
  for (std::size_t k = 0; k < kInvariants.size(); ++k) {
    const auto g = inv.open_group(kInvariants[k]);
    const auto at0 = testing::all_doubles(g, "initial"), at_end = testing::all_doubles(g, "final"),
               drift = testing::all_doubles(g, "max_abs_drift");
    for (std::size_t i = 0; i < states.size(); ++i) {
      double v0[3], v[3];
      Suris::invariants(coeffs(), Suris::from_phase_space(coeffs(), initial[i], Start::taylor), v0);
      Suris::invariants(coeffs(), states[i], v);
      EXPECT_EQ(at0[i], v0[k]);
      EXPECT_EQ(at_end[i], v[k]);
      EXPECT_GE(drift[i], std::fabs(at_end[i] - at0[i]));
    }
  }
  for (std::size_t i = 0; i < states.size(); ++i) {
    EXPECT_EQ(steps[i], -1);
    const Phase p = Suris::to_phase_space(coeffs(), states[i]);
    EXPECT_EQ(final[i].q1, states[i][0]);
    EXPECT_EQ(final[i].q2, states[i][1]);
    EXPECT_EQ(final[i].p1, p.p1);
    EXPECT_EQ(final[i].p2, p.p2);
  }
}

// The per-orbit values of the file (final points, invariants, drift histograms) are computed
// each orbit's alone, whatever the run's threads: one thread and two write the same datasets.
TEST_F(Io, OneThreadAndTwoWriteTheSameDatasets) {
  config = with_line(config, "orbits = ", "orbits = 3001");
  run_root({"--threads", "1"}, dir / "one.h5");
  run_root({"--threads", "2"}, dir / "two.h5");
  EXPECT_TRUE(SameDatasets(dir / "one.h5", dir / "two.h5"));
}

TEST_F(Io, ContinuingFinalStateIsIdenticalToLongerRun) {
  const auto full = read_states(run_root().open_group("final").open_group("state"));
  config = with_line(config, "steps = ", "steps = 30");
  auto part = read_states(run_root({}, dir / "part.h5").open_group("final").open_group("state"));
  ASSERT_EQ(part.size(), full.size());
  for (std::size_t i = 0; i < part.size(); ++i) {
    for (int n = 30; n < 50; ++n) Suris::step(coeffs(), part[i]);
    EXPECT_EQ(part[i], full[i]) << "orbit " << i;
  }
}

// Escaped orbits: step and reason agree, `escaped` counts them, the state is frozen at the
// last state within the bound, and one more step leaves it.
TEST_F(Io, EscapedOrbitIsFrozenAtLastStateWithinBound) {
  config = edited(
      config, {{"q1 = ", "q1 = [-0.5, 0.5]"}, {"stride = ", "stride = 1\nescape_bound = 0.55"}});
  const auto root = run_root();
  const auto initial = read_phases(root.open_group("initial"));
  const auto states = read_states(root.open_group("final").open_group("state"));
  const auto escape = root.open_group("escape");
  const auto step = testing::all_int64(escape, "step");
  const auto reason = read_uint8(escape, "reason");
  const double bound2 = 0.55 * 0.55;
  std::int64_t escaped = 0;
  for (std::size_t i = 0; i < states.size(); ++i) {
    EXPECT_EQ(reason[i], step[i] < 0 ? 0 : 2) << "orbit " << i;
    ASSERT_GE(step[i], -1);
    ASSERT_LE(step[i], 50);
    const long long last = step[i] < 0 ? 50 : std::max<long long>(step[i] - 1, 0);
    State s = Suris::from_phase_space(coeffs(), initial[i], Start::taylor);
    for (long long n = 0; n < last; ++n) Suris::step(coeffs(), s);
    EXPECT_EQ(states[i], s) << "orbit " << i;
    if (step[i] > 0) {
      EXPECT_LE(Suris::escape_measure(s), bound2);
      Suris::step(coeffs(), s);
      EXPECT_GT(Suris::escape_measure(s), bound2);
    }
    escaped += step[i] >= 0;
  }
  EXPECT_EQ(root.attr_int64("escaped"), escaped);
  EXPECT_GT(escaped, 0);
  EXPECT_LT(escaped, 100);
}

TEST_F(Io, KilledRunLeavesNoFileUnderFinalName) {
  config = edited(config, {{"orbits = ", "orbits = 20000"}, {"steps = ", "steps = 3000"}});
  write_text(dir / "cfg.toml", config);
  const pid_t pid = spawn({"run", "cfg.toml"}, dir, "1000:KILL");
  const std::string temporary = output + ".tmp-" + std::to_string(pid);
  const Result r = finish(pid, dir);
  EXPECT_EQ(r.status, 128 + SIGKILL) << "the run was not killed at step 1000: " << r.err;
  EXPECT_TRUE(fs::exists(temporary)) << "killed while writing to its temporary";
  EXPECT_FALSE(fs::exists(output));
}

TEST(IoAtomicFile, DestroyedWithoutCommitRemovesTemporary) {
  TempDir dir;
  const std::string path = dir / "x.h5";
  std::string temporary;
  {
    h5::AtomicFile out(path);
    temporary = out.temporary();
    EXPECT_EQ(temporary, path + ".tmp-" + std::to_string(getpid()));
    h5::File::create(temporary).root().attr("a", std::int64_t{1});
    EXPECT_TRUE(fs::exists(temporary));
  }
  EXPECT_FALSE(fs::exists(temporary));
  EXPECT_FALSE(fs::exists(path));
}

TEST(IoAtomicFile, CommitRenamesTemporary) {
  TempDir dir;
  const std::string path = dir / "x.h5";
  std::string temporary;
  {
    h5::AtomicFile out(path);
    temporary = out.temporary();
    h5::File::create(temporary).root().attr("a", std::int64_t{42});
    EXPECT_FALSE(fs::exists(path));
    out.commit();
    EXPECT_TRUE(fs::exists(path));
    EXPECT_FALSE(fs::exists(temporary));
  }
  EXPECT_TRUE(fs::exists(path));  // the destructor leaves a committed file alone
  EXPECT_EQ(h5::File::open_read(path).root().attr_int64("a"), 42);
}

// A process that ends right after the commit, its groups still open (as a run ended by SIGPIPE
// while printing its summary), leaves the committed file complete: close() closed it.
TEST(IoAtomicFile, CommittedFileIsCompleteWhileItsGroupsAreStillOpen) {
  TempDir dir;
  const std::string path = dir / "x.h5";
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    h5::AtomicFile out(path);
    auto file = out.create_hdf5();
    const auto group = file.root().create_group("g");
    const std::vector<double> values(100000, 0.25);
    group.write("v", values);
    group.attr("n", std::int64_t{7});
    file.close();
    out.commit();
    _exit(0);  // no destructor: `group` never closes
  }
  int status = 0;
  ASSERT_EQ(waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  const auto g = h5::File::open_read(path).root().open_group("g");
  EXPECT_EQ(g.attr_int64("n"), 7);
  const auto v = g.read_doubles("v", 100000);
  EXPECT_TRUE(std::all_of(v.begin(), v.end(), [](double x) { return x == 0.25; }));
}

TEST(IoAtomicFile, FailedCommitIsAnIoError) {
  TempDir dir;
  h5::AtomicFile out(dir / "x.h5");  // no temporary was written: nothing to rename
  try {
    out.commit();
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ExitCode::io);
    EXPECT_TRUE(Contains(e.what(), "cannot rename"));
  }
}

}  // namespace
}  // namespace qmaps::testing
