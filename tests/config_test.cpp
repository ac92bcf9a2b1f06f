// Config: TOML parsing, --set overrides, typed accessors, ranges and unknown keys, and the message
// of every error (source, line, section, key).
#include "ensembles/config/config.hpp"

#include <gtest/gtest.h>

#include <functional>
#include <limits>
#include <string>

#include "core/error.hpp"

namespace qmaps {
namespace {

// Line numbers matter below: [map] is line 1, [run] line 6, [ensemble] line 10.
constexpr const char* kText =
    "[map]\n"             // 1
    "name = \"suris\"\n"  // 2
    "A = 0.7\n"           // 3
    "h = 0.1\n"           // 4
    "\n"                  // 5
    "[run]\n"             // 6
    "steps = 1000\n"      // 7
    "stride = 2\n"        // 8
    "\n"                  // 9
    "[ensemble]\n"        // 10
    "q1 = [-0.5, 0.5]\n"  // 11
    "q2 = 0.25\n"         // 12
    "p1 = [0.5, -0.5]\n"  // 13
    "p2 = [0, inf]\n"     // 14
    "bad = [1, 2, 3]\n"   // 15
    "lo_hi = [nan, 1]\n"  // 16
    "x = nan\n";          // 17

Config config() { return Config::parse(kText, "cfg.toml"); }

// The usage error that `f` throws; fails the test when it throws none or another code.
std::string usage_message(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ExitCode::usage) << e.what();
    return e.what();
  }
  ADD_FAILURE() << "no qmaps::Error thrown";
  return {};
}

::testing::AssertionResult Contains(const std::string& text, const std::string& part) {
  if (text.find(part) != std::string::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "'" << text << "' does not contain '" << part << "'";
}

TEST(Config, ReadsTypedValues) {
  const Config c = config();
  EXPECT_EQ(c.string("map", "name"), "suris");
  EXPECT_EQ(c.number("map", "A"), 0.7);
  EXPECT_EQ(c.integer("run", "steps"), 1000);
  EXPECT_EQ(c.number("run", "steps"), 1000.0);  // an integer is a number
  EXPECT_EQ(c.integer_or("run", "chains", 4), 4);
  EXPECT_EQ(c.string_or("output", "file", "x.h5"), "x.h5");
  EXPECT_TRUE(c.has("map", "h"));
  EXPECT_FALSE(c.has("map", "B"));
}

TEST(Config, MalformedTomlNamesSourceAndLine) {
  const std::string msg =
      usage_message([] { Config::parse("[map]\nA = 0.7\nB = = 0.3\n", "cfg.toml"); });
  EXPECT_TRUE(Contains(msg, "cfg.toml:3:"));
  EXPECT_TRUE(Contains(msg, "malformed TOML"));
}

// A configuration beyond 1 MiB, or with a line beyond 4096 characters (a table header 100000
// levels deep, an array nested as deep), is refused before the TOML parser recurses into it.
TEST(Config, OversizedConfigurationsAreRefusedBeforeParsing) {
  std::string deep = "[map]\nA = 0.7\n[";
  for (int i = 0; i < 100000; ++i) deep += "a.";
  deep += "a]\n";
  const std::string header = usage_message([&] { Config::parse(deep, "cfg.toml"); });
  EXPECT_TRUE(Contains(header, "cfg.toml:3: a line of 200003 characters; at most 4096")) << header;
  const std::string nested = "[map]\nv = " + std::string(100000, '[') + "\n";
  EXPECT_TRUE(Contains(usage_message([&] { Config::parse(nested, "cfg.toml"); }), "cfg.toml:2:"));
  std::string big = "[map]\n";
  while (big.size() <= (std::size_t{1} << 20)) big += "# a comment line of some length\n";
  EXPECT_TRUE(Contains(usage_message([&] { Config::parse(big, "cfg.toml"); }),
                       "a configuration may have at most 1048576"));
  // Within the limits, deep nesting is the parser's ordinary error, not a crash.
  std::string bounded = "[map]\n[";
  for (int i = 0; i < 2000; ++i) bounded += "a.";
  bounded += "a]\nx = 1\n";
  EXPECT_NO_FATAL_FAILURE(usage_message([&] { Config::parse(bounded, "cfg.toml").reject_unknown(); }));
  Config c = config();
  EXPECT_TRUE(Contains(usage_message([&] { c.set("run.steps=" + std::string(5000, '[')); }),
                       "--set run.steps:1: a line of 5000 characters"));
}

TEST(Config, KeyOutsideSectionIsRejected) {
  const std::string msg = usage_message([] { Config::parse("steps = 5\n", "cfg.toml"); });
  EXPECT_TRUE(Contains(msg, "cfg.toml:1:"));
  EXPECT_TRUE(Contains(msg, "'steps' must be a [section]"));
}

TEST(Config, UnknownKeyNamesKeySectionAndLine) {
  Config c = Config::parse("[run]\nsteps = 5\n\n\n\n\nstepz = 6\n", "cfg.toml");
  c.integer("run", "steps");
  EXPECT_EQ(usage_message([&] { c.reject_unknown(); }), "cfg.toml:7: [run] stepz: unknown key");
}

TEST(Config, UnknownSectionNamesSectionAndLine) {
  Config c = Config::parse("[run]\nsteps = 5\n[runn]\nsteps = 6\n", "cfg.toml");
  c.integer("run", "steps");
  EXPECT_EQ(usage_message([&] { c.reject_unknown(); }), "cfg.toml:3: unknown section [runn]");
}

// A section the file lacks, made by --set, is blamed on the --set, not on a line of the file.
TEST(Config, UnknownSectionMadeBySetNamesTheSet) {
  Config c = Config::parse("[run]\nsteps = 5\n", "cfg.toml");
  c.set("runn.steps=6");
  c.integer("run", "steps");
  EXPECT_EQ(usage_message([&] { c.reject_unknown(); }), "--set runn.steps: unknown section [runn]");
  EXPECT_EQ(c.where("runn"), "--set runn.steps: [runn]");
}

TEST(Config, EveryKeyReadMeansNothingUnknown) {
  Config c = Config::parse("[map]\nA = 1\nB = 2\n[run]\nsteps = 5\n", "cfg.toml");
  EXPECT_EQ(c.keys("map").size(), 2u);
  c.integer("run", "steps");
  EXPECT_NO_THROW(c.reject_unknown());
}

TEST(Config, TypeErrorsNameKeyAndLine) {
  const Config c = config();
  EXPECT_EQ(usage_message([&] { c.number("map", "name"); }),
            "cfg.toml:2: [map] name must be a number, not a string");
  EXPECT_EQ(usage_message([&] { c.integer("map", "A"); }),
            "cfg.toml:3: [map] A must be an integer, not a number");
  EXPECT_EQ(usage_message([&] { c.string("run", "steps"); }),
            "cfg.toml:7: [run] steps must be a string, not an integer");
  EXPECT_EQ(usage_message([&] { c.number("ensemble", "x"); }),
            "cfg.toml:17: [ensemble] x must be finite");
}

TEST(Config, MissingKeyNamesKeyAndSection) {
  const std::string msg = usage_message([] { config().number("map", "B"); });
  EXPECT_TRUE(Contains(msg, "cfg.toml"));
  EXPECT_TRUE(Contains(msg, "'B'"));
  EXPECT_TRUE(Contains(msg, "[map]"));
}

TEST(Config, LoadOfMissingFileIsAnIoError) {
  try {
    Config::load("/nonexistent-dir/cfg.toml");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ExitCode::io);
    EXPECT_TRUE(Contains(e.what(), "/nonexistent-dir/cfg.toml"));
  }
}

TEST(Config, SetOverridesAndWhereNamesTheOverride) {
  Config c = config();
  EXPECT_EQ(c.where("run", "steps"), "cfg.toml:7: [run] steps");
  c.set("run.steps=5");
  EXPECT_EQ(c.integer("run", "steps"), 5);
  EXPECT_EQ(c.where("run", "steps"), "--set run.steps");
  EXPECT_EQ(usage_message([&] { c.string("run", "steps"); }),
            "--set run.steps must be a string, not an integer");
}

TEST(Config, SetTakesBareStringsTomlValuesAndNewSections) {
  Config c = config();
  c.set("output.file=out.h5");
  c.set("map.name=\"quoted\"");
  c.set("ensemble.q1=[0.1, 0.2]");
  c.set("run.track=true");
  EXPECT_EQ(c.string("output", "file"), "out.h5");
  EXPECT_EQ(c.string("map", "name"), "quoted");
  EXPECT_EQ(c.range("ensemble", "q1"), (std::array<double, 2>{0.1, 0.2}));
  EXPECT_EQ(usage_message([&] { c.number("run", "track"); }),
            "--set run.track must be a number, not a boolean");
}

TEST(Config, SetReachesATableOfAnArrayOfTablesByIndex) {
  Config c = Config::parse("[[histogram]]\nname = \"a\"\nbins = 4\n[[histogram]]\nname = \"b\"\n",
                           "cfg.toml");
  c.set("histogram[1].bins=[8, 16]");
  c.set("histogram[0].name=first");
  EXPECT_EQ(c.range_or_integer("histogram[1]", "bins"), (std::vector<std::int64_t>{8, 16}));
  EXPECT_EQ(c.string("histogram[0]", "name"), "first");
  EXPECT_EQ(c.integer("histogram[0]", "bins"), 4);
  EXPECT_EQ(c.where("histogram[1]", "bins"), "--set histogram[1].bins");
  EXPECT_EQ(usage_message([&] { c.set("histogram.bins=2"); }),
            "--set histogram.bins: 'histogram' is an array of tables [[histogram]]: name one as "
            "histogram[i].bins (i from 0)");
  EXPECT_EQ(usage_message([&] { c.set("histogram[2].bins=2"); }),
            "--set histogram[2].bins: there is no [[histogram]] number 2 (tables are counted "
            "from 0; the config has 2)");
  EXPECT_EQ(usage_message([&] { c.set("section[0].cap=2"); }),
            "--set section[0].cap: there is no [[section]] number 0 (tables are counted from 0; "
            "the config has 0)");
  EXPECT_EQ(usage_message([&] { c.set("histogram[x].bins=2"); }),
            "--set histogram[x].bins: expected histogram[index]");
}

TEST(Config, BadSetSyntaxThrows) {
  for (const char* bad : {"nodot=1", "a.b", ".key=1", "section.=1", "=1", "a=b.c"}) {
    Config c = config();
    EXPECT_TRUE(Contains(usage_message([&] { c.set(bad); }), "--set expects section.key=value"))
        << bad;
  }
}

TEST(Config, RangeAcceptsPairAndSingleNumber) {
  const Config c = config();
  EXPECT_EQ(c.range("ensemble", "q1"), (std::array<double, 2>{-0.5, 0.5}));
  EXPECT_EQ(c.range("ensemble", "q2"), (std::array<double, 2>{0.25, 0.25}));
}

TEST(Config, RangeRejectsEmptyNonFiniteAndMalformed) {
  const Config c = config();
  const auto range_error = [&](const char* key) {
    return usage_message([&] { c.range("ensemble", key); });
  };
  const std::string empty = range_error("p1");
  EXPECT_TRUE(Contains(empty, "cfg.toml:13: [ensemble] p1"));
  EXPECT_TRUE(Contains(empty, "empty range"));
  EXPECT_TRUE(Contains(range_error("p2"), "cfg.toml:14: [ensemble] p2 must have finite ends"));
  EXPECT_TRUE(
      Contains(range_error("lo_hi"), "cfg.toml:16: [ensemble] lo_hi must have finite ends"));
  EXPECT_TRUE(Contains(range_error("x"), "cfg.toml:17: [ensemble] x must be finite"));
  EXPECT_TRUE(Contains(range_error("bad"), "cfg.toml:15: [ensemble] bad must be a range [lo, hi]"));
  EXPECT_TRUE(Contains(usage_message([&] { c.range("map", "name"); }),
                       "cfg.toml:2: [map] name must be a range [lo, hi] or a number"));
}

TEST(Config, ResolvedReparsesToIdenticalValues) {
  Config c = Config::parse(
      "[map]\nname = \"suris\"\nA = 0.7\nh = 0.1\n[ensemble]\nq1 = [-0.5, 0.5]\n", "cfg.toml");
  c.set("map.h=0.30000000000000004");
  c.set("map.alpha=1e-300");
  c.set("run.steps=5");
  c.set("output.file=out.h5");
  const Config r = Config::parse(c.resolved(), "<resolved>");
  EXPECT_EQ(r.string("map", "name"), "suris");
  EXPECT_EQ(r.number("map", "A"), 0.7);
  EXPECT_EQ(r.number("map", "h"), 0.30000000000000004);
  EXPECT_EQ(r.number("map", "alpha"), 1e-300);
  EXPECT_EQ(r.integer("run", "steps"), 5);
  EXPECT_EQ(r.string("output", "file"), "out.h5");
  EXPECT_EQ(r.range("ensemble", "q1"), (std::array<double, 2>{-0.5, 0.5}));
  EXPECT_EQ(c.text().find("alpha"), std::string::npos);  // text() is the file as given
}

}  // namespace
}  // namespace qmaps
