// Checkpoint and resume, through the qmaps binary: a run interrupted by SIGINT or SIGTERM at a
// random step writes <output>.ckpt, exits with ExitCode::interrupted and leaves no file under the
// final name; resumed (with another thread count and ISA), it writes datasets identical byte for
// byte to an uninterrupted run's (chaos indicators and trajectories included). Periodic
// checkpoints change nothing; bad checkpoints are errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <csignal>
#include <filesystem>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "ensembles/config/config.hpp"
#include "ensembles/config/map_config.hpp"
#include "ensembles/io/checkpoint.hpp"
#include "ensembles/kinds/initial_conditions.hpp"
#include "ensembles/program/run_setup.hpp"
#include "fixtures.hpp"
#include "ensembles/io/h5.hpp"
#include "core/isa.hpp"
#include "core/version.hpp"
#include "h5_read.hpp"
#include "run_process.hpp"

namespace qmaps::testing {
namespace {

constexpr int kInterrupted = static_cast<int>(ExitCode::interrupted);

// The Suris preset with its observers, chaos indicators and a trajectory, 1500 orbits × 1500
// steps, a fifth of them escaping (beyond |q| = 0.6).
std::string config_text(const std::string& output) {
  std::string text = read_text(QMAPS_SOURCE_DIR "/ensembles/presets/suris.toml");
  text = with_line(text, "orbits = ", "orbits = 1500");
  text = with_line(text, "steps = ", "steps = 1500\nescape_bound = 0.6");
  text += "\n[chaos]\n\n[[trajectory]]\nname = \"some\"\norbits = [3, 1, 1415]\nevery = 100\n";
  return with_line(text, "file = ", "file = \"" + output + "\"");
}

// An ISA other than the default one, for the resumed session: sse2 when it runs here, else scalar.
std::string other_isa() {
  for (Isa isa : runnable_isas())
    if (isa != best_isa()) return std::string(isa_name(isa));
  return "scalar";
}

class Checkpoint : public ::testing::Test {
 protected:
  static inline TempDir* shared = nullptr;  // the uninterrupted run, made once
  TempDir dir;
  const std::string output = dir / "run.h5";
  const std::string checkpoint = output + ".ckpt";

  static void SetUpTestSuite() {
    shared = new TempDir;
    write_text(*shared / "cfg.toml", config_text("reference.h5"));
    const Result r = run({"run", "cfg.toml"}, *shared);
    ASSERT_EQ(r.status, 0) << r.err;
  }
  static void TearDownTestSuite() { delete shared; }
  static std::string reference() { return *shared / "reference.h5"; }

  void SetUp() override { write_text(dir / "cfg.toml", config_text(output)); }

  // Starts the run with checkpoints every `every` steps, has it signal itself with `sig` at its
  // first checkpoint's step, and checks what an interrupted run leaves.
  Result interrupt(long long every, int sig, std::vector<std::string> extra = {}) {
    extra.insert(extra.begin(),
                 {"run", "cfg.toml", "--set", "run.checkpoint_every=" + std::to_string(every)});
    const std::string name = sig == SIGINT ? "SIGINT" : "SIGTERM";
    const pid_t pid = spawn(extra, dir, std::to_string(every) + ":" + name.substr(3));
    const Result r = finish(pid, dir);
    EXPECT_EQ(r.status, kInterrupted) << "the run ended before the signal: " << r.err;
    EXPECT_TRUE(Contains(r.err, name + " at step " + std::to_string(every) + " of "));
    EXPECT_TRUE(Contains(r.err, "qmaps run --resume " + checkpoint));
    EXPECT_FALSE(fs::exists(output));
    EXPECT_FALSE(dir.has_entry_containing(".tmp-"));
    EXPECT_TRUE(fs::exists(checkpoint));
    return r;
  }

  Result resume(std::vector<std::string> extra = {}) {
    extra.insert(extra.begin(), {"run", "--resume", checkpoint});
    return run(extra, dir);
  }
};

TEST_F(Checkpoint, InterruptedBySigintAndResumedElsewhereEqualsUninterruptedRun) {
  const unsigned seed = std::random_device{}();
  std::mt19937 random(seed);
  const long long every = std::uniform_int_distribution<long long>(20, 600)(random);
  std::cout << "[ seed ] " << seed << ": checkpoint_every = " << every << '\n';
  SCOPED_TRACE("seed " + std::to_string(seed) + ", checkpoint_every = " + std::to_string(every));
  interrupt(every, SIGINT);
  const Result r = resume({"--threads", "1", "--simd", other_isa()});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_FALSE(fs::exists(checkpoint)) << "the checkpoint goes once the file is written";
  EXPECT_FALSE(dir.has_entry_containing(".tmp-"));
  EXPECT_TRUE(SameDatasets(output, reference()));
  const auto root = h5::File::open_read(output).root();
  EXPECT_EQ(root.attr_string("isa"), other_isa());
  EXPECT_EQ(root.attr_int64("threads"), 1);
}

TEST_F(Checkpoint, InterruptedBySigtermTwiceAndResumedEqualsUninterruptedRun) {
  interrupt(100, SIGTERM);
  // The resumed run is interrupted in turn at its next checkpoint.
  const Result second = run({"run", "--resume", checkpoint}, dir, "200:TERM");
  ASSERT_EQ(second.status, kInterrupted) << second.err;
  EXPECT_TRUE(Contains(second.err, "SIGTERM at step 200 of "));
  EXPECT_FALSE(fs::exists(output));
  const Result r = resume();
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(SameDatasets(output, reference()));
  // Three sessions, each one line: its steps, path, threads, times and command line.
  const std::string sessions = h5::File::open_read(output).root().attr_string("sessions");
  EXPECT_EQ(std::count(sessions.begin(), sessions.end(), '\n'), 3) << sessions;
  EXPECT_TRUE(Contains(sessions, "steps 0-"));
  EXPECT_TRUE(Contains(sessions, "-1500, "));
  EXPECT_TRUE(Contains(sessions, "run --resume " + checkpoint + "\n"));
}

TEST_F(Checkpoint, WithoutPerOrbitDatasetsResumedHistogramsEqualUninterruptedRuns) {
  interrupt(150, SIGINT, {"--set", "output.per_orbit=false"});
  ASSERT_EQ(resume({"--threads", "1"}).status, 0);
  EXPECT_EQ(h5::File::open_read(output).root().attr_int64("per_orbit"), 0);
  EXPECT_FALSE(h5::File::open_read(output).root().has("initial"));
  EXPECT_TRUE(SameDatasets(output, reference(), true));
}

// A flow's section of mode exact, with its count of interpolated crossings, survives a checkpoint.
TEST_F(Checkpoint, FlowsExactSectionResumedEqualsUninterruptedRun) {
  std::string text = read_text(QMAPS_SOURCE_DIR "/ensembles/presets/leapfrog.toml");
  text = with_line(text, "orbits = ", "orbits = 2000");
  text = with_line(text, "steps = ", "steps = 1000");
  write_text(dir / "flow.toml", with_line(text, "file = ", "file = \"flow.h5\""));
  ASSERT_EQ(run({"run", "flow.toml", "--out", "whole.h5"}, dir).status, 0);
  const pid_t pid = spawn({"run", "flow.toml", "--set", "run.checkpoint_every=300"}, dir, "300:INT");
  ASSERT_EQ(finish(pid, dir).status, kInterrupted);
  const Result r = run({"run", "--resume", dir / "flow.h5.ckpt", "--simd", other_isa()}, dir);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(SameDatasets(dir / "flow.h5", dir / "whole.h5"));
  const auto resumed = h5::File::open_read(dir / "flow.h5").root().open_group("sections").open_group("q1up");
  const auto whole = h5::File::open_read(dir / "whole.h5").root().open_group("sections").open_group("q1up");
  EXPECT_EQ(resumed.attr_string("mode"), "exact");
  EXPECT_EQ(resumed.attr_int64("interpolated"), whole.attr_int64("interpolated"));
  EXPECT_GT(resumed.attr_int64("crossings"), 2000);
}

TEST_F(Checkpoint, PeriodicCheckpointsChangeNothingAndAreRemoved) {
  const Result r = run({"run", "cfg.toml", "--set", "run.checkpoint_every=700"}, dir);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_FALSE(fs::exists(checkpoint));
  EXPECT_TRUE(SameDatasets(output, reference()));
}

TEST_F(Checkpoint, ResumedFileRecordsTheFirstSessionsProvenance) {
  interrupt(50, SIGINT);
  ASSERT_EQ(resume({"--threads", "1"}).status, 0);
  const auto root = h5::File::open_read(output).root();
  const auto original = h5::File::open_read(reference()).root();
  EXPECT_EQ(root.attr_string("config"), read_text(dir / "cfg.toml"));
  EXPECT_EQ(root.attr_string("command_line"),
            std::string(QMAPS_BINARY) + " run cfg.toml --set run.checkpoint_every=50");
  EXPECT_TRUE(Contains(root.attr_string("config_resolved"), "checkpoint_every = 50"));
  for (const char* name : {"qmaps_version", "git_commit", "compiler", "compiler_flags", "kernel_flags"})
    EXPECT_EQ(root.attr_string(name), original.attr_string(name)) << name;
  EXPECT_EQ(root.attr_string("compiler_flags"), build::engine_flags);
  EXPECT_TRUE(Contains(root.attr_string("compiler_flags"), "-ffp-contract=off"));
  EXPECT_LE(root.attr_string("started"), root.attr_string("finished"));
  const std::string sessions = root.attr_string("sessions");
  EXPECT_EQ(std::count(sessions.begin(), sessions.end(), '\n'), 2) << sessions;
  EXPECT_TRUE(Contains(sessions, ", 1 thread, "));
}

class BadCheckpoint : public ::testing::Test {
 protected:
  TempDir dir;

  void expect_error(const std::vector<std::string>& args, int code,
                    const std::vector<std::string>& parts) {
    const Result r = run(args, dir);
    EXPECT_EQ(r.status, code) << r.err;
    for (const auto& part : parts) EXPECT_TRUE(Contains(r.err, part));
    EXPECT_FALSE(fs::exists(dir / "run.h5"));
    EXPECT_FALSE(dir.has_entry_containing(".tmp-"));
  }
};

TEST_F(BadCheckpoint, MissingFileIsAnIoError) {
  expect_error({"run", "--resume", "run.h5.ckpt"}, 3, {"cannot read 'run.h5.ckpt'"});
}

TEST_F(BadCheckpoint, GarbageOrTruncatedFileIsAnIoError) {
  write_text(dir / "run.h5.ckpt", "not a checkpoint");
  expect_error({"run", "--resume", "run.h5.ckpt"}, 3, {"'run.h5.ckpt' is not an HDF5 file"});
  write_text(dir / "cfg.toml", preset_config("full.h5", 1000, 20));
  ASSERT_EQ(run({"run", "cfg.toml", "--set", "run.checkpoint_every=10"}, dir).status, 0);
  // A checkpoint cut short: the final file of that run, truncated.
  const std::string text = read_text(dir / "full.h5");
  write_text(dir / "run.h5.ckpt", text.substr(0, text.size() / 2));
  expect_error({"run", "--resume", "run.h5.ckpt"}, 3, {"run.h5.ckpt"});
}

TEST_F(BadCheckpoint, FinalFileIsNoCheckpoint) {
  write_text(dir / "cfg.toml", preset_config("run.h5", 100, 5));
  ASSERT_EQ(run({"run", "cfg.toml"}, dir).status, 0);
  fs::rename(dir / "run.h5", dir / "x.h5.ckpt");
  const Result r = run({"run", "--resume", "x.h5.ckpt"}, dir);
  EXPECT_EQ(r.status, 3);
  EXPECT_TRUE(Contains(r.err, "'x.h5.ckpt' is not a checkpoint qmaps can resume"));
  EXPECT_TRUE(Contains(r.err, "no attribute checkpoint_version"));
  EXPECT_FALSE(fs::exists(dir / "x.h5"));
}

TEST_F(BadCheckpoint, OtherVersionIsRefusedNamingBoth) {
  write_text(dir / "cfg.toml", preset_config("run.h5", 20000, 2000));
  ASSERT_EQ(run({"run", "cfg.toml", "--set", "run.checkpoint_every=1"}, dir, "5:INT").status,
            kInterrupted);
  {
    h5::Handle file(H5Fopen((dir / "run.h5.ckpt").c_str(), H5F_ACC_RDWR, H5P_DEFAULT), H5Fclose);
    ASSERT_GE(file.id(), 0);
    h5::Group(h5::Handle(H5Gopen2(file.id(), "/", H5P_DEFAULT), H5Gclose), "/")
        .attr("checkpoint_version", std::int64_t{99});
  }
  expect_error({"run", "--resume", "run.h5.ckpt"}, 3,
               {"checkpoint version 99", "resumes checkpoint version 1"});
}

// A chaos record no run writes (a step count that is not a whole number) is refused by name.
TEST_F(BadCheckpoint, ForgedChaosRecordIsRefused) {
  write_text(dir / "cfg.toml", preset_config("run.h5", 2000, 2000) + "\n[chaos]\n");
  ASSERT_EQ(run({"run", "cfg.toml", "--set", "run.checkpoint_every=1"}, dir, "5:INT").status,
            kInterrupted);
  {
    h5::Handle file(H5Fopen((dir / "run.h5.ckpt").c_str(), H5F_ACC_RDWR, H5P_DEFAULT), H5Fclose);
    ASSERT_GE(file.id(), 0);
    h5::Handle set(H5Dopen2(file.id(), "/final/state/chaos.steps", H5P_DEFAULT), H5Dclose);
    ASSERT_GE(set.id(), 0);
    const std::vector<double> forged(2000, -1.5);
    ASSERT_GE(H5Dwrite(set.id(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, forged.data()),
              0);
  }
  expect_error({"run", "--resume", "run.h5.ckpt"}, 3,
               {"orbit 0: its chaos record's step count is not a whole number >= 0"});
}

TEST_F(BadCheckpoint, ResumeWithConfigSetOrOtherNameIsAUsageError) {
  write_text(dir / "cfg.toml", preset_config("run.h5"));
  expect_error({"run", "cfg.toml", "--resume", "run.h5.ckpt"}, 2, {"give no config, --set or --out"});
  expect_error({"run", "--resume", "run.h5.ckpt", "--set", "run.steps=3"}, 2, {"give no config"});
  expect_error({"run", "--resume", "run.h5"}, 2, {"a checkpoint is named <output>.ckpt"});
  expect_error({"run"}, 2, {"needs a config file, or --resume"});
}

TEST_F(BadCheckpoint, NegativeCheckpointEveryIsAUsageError) {
  write_text(dir / "cfg.toml", preset_config("run.h5"));
  expect_error({"run", "cfg.toml", "--set", "run.checkpoint_every=-1"}, 2,
               {"--set run.checkpoint_every must be >= 0"});
}


// A run of the shared fixture, advanced in process and checkpointed: read back, every measured
// per-orbit column (core/observers/lane_observers.hpp), the state and the escapes equal the
// ensemble's, byte for byte, though the checkpoint's reader names no measurement. Columns a
// checkpoint alters to a value no run leaves are refused by name (tests/hostile_files_test.py).
TEST(CheckpointColumns, EveryMeasuredColumnReadsBackByteForByte) {
  TempDir dir;
  const Config config =
      Config::parse(fixture("small-suris-box.toml"), "small-suris-box.toml");
  const auto initial = InitialConditions::from_config(config, *map_of(config));
  SpecSource source;
  source.write_to = dir / "run.h5";
  source.threads = 1;
  qmaps::Run r = run_of(config, map_of(config), initial.orbits(), source);
  r.plan.escape_bound = 0.55;  // some orbits escape, at the start or on the way
  Ensemble e = r.model->ensemble(r.orbits, r.measured);
  initial.start(*r.model, e, r.start, r.plan.escape_bound, [](std::size_t, std::span<const Phase>) {});
  r.model->advance(e, r.plan, r.x, &r.observers);
  e.step = r.plan.total;
  ASSERT_GT(e.escaped(), 0u);
  ASSERT_LT(e.escaped(), e.orbits);
  ASSERT_FALSE(e.columns.empty());

  const std::string path = dir / "run.h5.ckpt";
  write_checkpoint(path, record_of(r, e, 0, "", "", ""), nullptr);
  Ensemble back = r.model->ensemble(r.orbits, r.measured);
  read_ensemble(open_checkpoint(path).root(), *r.model, back);
  ASSERT_EQ(back.column_specs.size(), e.column_specs.size());
  const auto same = [&](const auto& a, const auto& b) {
    return std::memcmp(a.data(), b.data(), e.orbits * sizeof(a[0])) == 0;
  };
  for (std::size_t c = 0; c < e.columns.size(); ++c)
    EXPECT_TRUE(same(back.columns[c], e.columns[c])) << e.column_specs[c].path;
  for (std::size_t k = 0; k < e.state.size(); ++k) EXPECT_TRUE(same(back.state[k], e.state[k]));
  EXPECT_TRUE(same(back.escape_step, e.escape_step));
  EXPECT_TRUE(same(back.escape_reason, e.escape_reason));
  EXPECT_EQ(back.step, e.step);
}

}  // namespace
}  // namespace qmaps::testing
