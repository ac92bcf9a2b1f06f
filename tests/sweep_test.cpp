// Sweeps: the axes and points [[sweep]] describes, the bad sweeps refused with their key, and the
// runner of several ensembles at once, byte-identical to each ensemble run alone on every ISA and
// thread count.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "core/runner.hpp"
#include "ensemble_fixtures.hpp"
#include "fixtures.hpp"
#include "ensembles/config/config.hpp"
#include "ensembles/config/map_config.hpp"
#include "ensembles/config/observer_config.hpp"
#include "ensembles/config/sweep_config.hpp"
#include "isas_run.hpp"
#include "run_process.hpp"

namespace qmaps {
namespace {

// A flow run over a shell (tests/fixtures, shared with tests/sweep_test.py): the sweeps' base.
const std::string flow_base = testing::fixture("flow-shell-chaos.toml");

Sweep sweep_of(const std::string& text) {
  const Config config = Config::parse(text, "sweep.toml");
  const auto model = map_of(config);
  const auto sweep = Sweep::from_config(config, *model);
  if (!sweep) throw std::runtime_error("no sweep");
  return *sweep;
}

// The message of the usage error that `text` raises.
std::string refusal(const std::string& text) {
  try {
    sweep_of(text);
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ExitCode::usage);
    return e.what();
  }
  ADD_FAILURE() << "accepted:\n" << text;
  return {};
}

TEST(SweepAxes, LinearGridsHitTheirIntegerNodesExactly) {
  const Sweep s = sweep_of(flow_base + R"(
[[sweep]]
parameter = "beta/alpha"
from = 1
to = 16
points = 16

[[sweep]]
parameter = "delta/alpha"
values = [0, 2, 6, 12]
)");
  ASSERT_EQ(s.points(), 64u);
  EXPECT_EQ(s.shape(), (std::vector<std::size_t>{16, 4}));
  for (std::size_t i = 0; i < 16; ++i) EXPECT_EQ(s.axes()[0].values[i], 1.0 + static_cast<double>(i));
  EXPECT_EQ(s.axes()[0].name(), "beta_over_alpha");
  // Point 7 × 4 + 2: β/α = 8, δ/α = 6, so β = 4, δ = 3 at α = 0.5; the first axis is the slowest.
  const auto p = s.parameters(30);
  EXPECT_EQ(s.axis_value(30, 0), 8.0);
  EXPECT_EQ(s.axis_value(30, 1), 6.0);
  EXPECT_EQ(p[3], 4.0);  // flow's parameters: A, B, alpha, beta, delta, h, order
  EXPECT_EQ(p[4], 3.0);
  EXPECT_EQ(s.label(30), "point 30 (beta/alpha = 8, delta/alpha = 6)");
  const Config point = s.config_of(Config::parse(flow_base, "base"), 30);
  EXPECT_EQ(point.number("map", "beta"), 4.0);
  EXPECT_EQ(point.number("map", "delta"), 3.0);
}

TEST(SweepAxes, LogGridsEndExactlyAndRatiosUseTheOtherAxis) {
  const Sweep s = sweep_of(flow_base + R"(
[[sweep]]
parameter = "alpha"
from = 0.01
to = 100
points = 5
scale = "log"

[[sweep]]
parameter = "beta/alpha"
values = [2]
)");
  ASSERT_EQ(s.points(), 5u);
  EXPECT_EQ(s.axes()[0].values.front(), 0.01);
  EXPECT_EQ(s.axes()[0].values.back(), 100.0);
  EXPECT_NEAR(s.axes()[0].values[2], 1.0, 1e-15);  // independent of the grid's rounding
  for (std::size_t k = 0; k < 5; ++k)  // β = 2α with the point's own α
    EXPECT_EQ(s.parameters(k)[3], 2 * s.axes()[0].values[k]);
}

TEST(SweepAxes, BadSweepsAreRefusedWithTheirTableAndKey) {
  const std::string m = flow_base;
  const std::string parameter_line = std::to_string(std::ranges::count(m, '\n') + 2);
  EXPECT_TRUE(testing::Contains(refusal(m + "[[sweep]]\nparameter = \"gamma\"\nvalues = [1]\n"),
                                "sweep.toml:" + parameter_line + ": [sweep[0]] parameter: flow has no parameter 'gamma' (it has A, B, alpha, "
                                "beta, delta, h, order)"));
  EXPECT_TRUE(testing::Contains(
      refusal(m + "[[sweep]]\nparameter = \"beta/gamma\"\nvalues = [1]\n"), "no parameter 'gamma'"));
  EXPECT_TRUE(testing::Contains(refusal(m + "[[sweep]]\nparameter = \"beta/\"\nvalues = [1]\n"),
                                "a ratio without a denominator"));
  EXPECT_TRUE(testing::Contains(refusal(m + "[[sweep]]\nparameter = \"beta/beta\"\nvalues = [1]\n"),
                                "a ratio of a parameter to itself"));
  EXPECT_TRUE(testing::Contains(refusal(m + "[sweep]\nparameter = \"beta\"\nvalues = [1]\n"),
                                "one [[sweep]] table per axis"));
  EXPECT_TRUE(testing::Contains(
      refusal(m + "[[sweep]]\nparameter = \"beta\"\nvalues = [1]\nfrom = 1\n"),
      "give either values = [...] or from, to and points"));
  EXPECT_TRUE(testing::Contains(
      refusal(m + "[[sweep]]\nparameter = \"beta\"\nfrom = 0\nto = 1\npoints = 3\nscale = \"log\"\n"),
      "\"log\" needs from and to > 0"));
  EXPECT_TRUE(testing::Contains(
      refusal(m + "[[sweep]]\nparameter = \"beta\"\nfrom = 0\nto = 1\npoints = 0\n"),
      "points must be 1 to"));
  EXPECT_TRUE(testing::Contains(refusal(m + "[[sweep]]\nparameter = \"beta\"\nvalues = []\n"),
                                "must be a non-empty array of finite numbers"));
  EXPECT_TRUE(testing::Contains(
      refusal(m + "[[sweep]]\nparameter = \"alpha\"\nvalues = [1, 0]\n[[sweep]]\nparameter = "
                  "\"beta/alpha\"\nvalues = [1]\n"),
      "at point 1 (alpha = 0, beta/alpha = 1), alpha is 0; a ratio needs a finite, non-zero"));
  EXPECT_TRUE(testing::Contains(
      refusal(m + "[[sweep]]\nparameter = \"beta\"\nvalues = [1]\n[[sweep]]\nparameter = "
                  "\"beta\"\nvalues = [2]\n"),
      "both axes set beta"));
  EXPECT_TRUE(testing::Contains(
      refusal(m + "[[sweep]]\nparameter = \"alpha/delta\"\nvalues = [1]\n[[sweep]]\nparameter = "
                  "\"beta/alpha\"\nvalues = [2]\n"),
      "its denominator alpha is itself swept as a ratio"));
  std::string three = m;
  for (const char* p : {"A", "B", "beta"})
    three += std::string("[[sweep]]\nparameter = \"") + p + "\"\nvalues = [1]\n";
  EXPECT_TRUE(testing::Contains(refusal(three), "a sweep has one or two axes, not 3"));
}

// Equal bytes of every orbit's state, escape and invariant record.
void expect_same_orbits(const Ensemble& a, const Ensemble& b, const std::string& what) {
  ASSERT_EQ(a.orbits, b.orbits);
  for (std::size_t i = 0; i < a.orbits; ++i) {
    for (std::size_t k = 0; k < a.state.size(); ++k)
      ASSERT_EQ(std::memcmp(&a.state[k][i], &b.state[k][i], sizeof(double)), 0)
          << what << ": orbit " << i << " component " << k;
    for (std::size_t k = 0; k < a.columns.size(); ++k)
      ASSERT_EQ(std::memcmp(&a.columns[k][i], &b.columns[k][i], sizeof(double)), 0)
          << what << ": orbit " << i << " " << a.column_specs[k].path;
    ASSERT_EQ(a.escape_step[i], b.escape_step[i]) << what << ": orbit " << i;
    ASSERT_EQ(a.escape_reason[i], b.escape_reason[i]) << what << ": orbit " << i;
  }
  EXPECT_EQ(a.step, b.step);
}

void expect_same_observers(const Observers& a, const Observers& b, const std::string& what) {
  ASSERT_EQ(a.densities.size(), b.densities.size());
  for (std::size_t i = 0; i < a.densities.size(); ++i) {
    const auto &x = a.densities[i].histogram, &y = b.densities[i].histogram;
    EXPECT_TRUE(std::ranges::equal(x.counts(), y.counts())) << what;
    EXPECT_EQ(x.underflow(), y.underflow()) << what;
    EXPECT_EQ(x.overflow(), y.overflow()) << what;
  }
  ASSERT_EQ(a.sections.size(), b.sections.size());
  for (std::size_t i = 0; i < a.sections.size(); ++i) {
    const auto p = a.sections[i].points->all(), q = b.sections[i].points->all();
    ASSERT_EQ(p.size(), q.size()) << what;
    EXPECT_GT(p.size(), 0u) << what;
    if (!p.empty()) {
      EXPECT_EQ(std::memcmp(p.data(), q.data(), p.size() * sizeof(SectionPoint)), 0) << what;
    }
    EXPECT_TRUE(std::ranges::equal(a.sections[i].density.counts(), b.sections[i].density.counts()))
        << what;
  }
}

// Three points of different maps, sizes and escapes, with a density and a section each.
struct Point {
  std::unique_ptr<Model> model;
  std::vector<Phase> start;
  Config config;
};

std::vector<Point> points() {
  const char* observers = R"(
[[histogram]]
name = "q1q2"
x = "q1"
y = "q2"
x_range = [-1.0, 1.0]
y_range = [-1.0, 1.0]
bins = [16, 16]

[[section]]
name = "q1up"
plane = "q1"
value = 0.0
direction = "+"
x = "q2"
y = "p2"
cap = 5
x_range = [-1.0, 1.0]
y_range = [-1.0, 1.0]
bins = [8, 8]
)";
  std::vector<Point> out;
  out.push_back({testing::suris(0.7, 0.3, 0.9, 0.1), testing::box_points(37, 0.5, 0.5),
                 Config::parse(observers, "a")});
  out.push_back({testing::suris(0.7, 0.3, -0.4, 0.1), testing::box_points(130, 1.2, 1.0, 3),
                 Config::parse(observers, "b")});  // escaping orbits
  out.push_back({make_model("flow", {{"A", 0.5}, {"B", 2.0}, {"alpha", 0.5}, {"beta", 4.0},
                                     {"delta", 3.0}, {"h", 0.02}, {"order", 6}},
                            ChaosOptions{}),
                 testing::box_points(21, 0.3, 0.3, 5), Config::parse(observers, "c")});
  return out;
}

TEST(SweepRunner, EveryPointEqualsItsRunAloneOnEveryIsaAndThreadCount) {
  auto ps = points();
  RunPlan plan;
  plan.total = plan.last = 120;
  plan.stride = 7;
  plan.escape_bound = 10;
  // Each point alone on the scalar reference path.
  std::vector<Ensemble> alone;
  std::vector<Observers> alone_observers;
  for (auto& p : ps) {
    alone.push_back(p.model->start(p.start, Start::taylor, plan.escape_bound));
    alone_observers.push_back(observers_from_config(p.config, *p.model, p.start.size(), plan.total));
    p.model->advance(alone.back(), plan, Execution{}, &alone_observers.back());
  }
  auto isas = testing::isas_to_run();
  isas.insert(isas.begin(), Isa::scalar);
  for (Isa isa : isas)
    for (int threads : {1, 2, 3}) {
      if (isa == Isa::scalar && threads > 1) continue;
      std::vector<Ensemble> es;
      std::vector<Observers> os;
      for (auto& p : ps) {
        es.push_back(p.model->start(p.start, Start::taylor, plan.escape_bound));
        os.push_back(observers_from_config(p.config, *p.model, p.start.size(), plan.total));
      }
      // In two segments, each into empty observers merged into the run's, as qmaps run does.
      for (const auto& [from, to] : {std::pair{0LL, 50LL}, std::pair{50LL, plan.total}}) {
        RunPlan segment = plan;
        segment.first = from;
        segment.last = to;
        std::vector<Observers> part;
        std::vector<RunPart> parts;
        for (std::size_t k = 0; k < ps.size(); ++k) part.push_back(os[k].empty_copy());
        for (std::size_t k = 0; k < ps.size(); ++k)
          parts.push_back({ps[k].model.get(), &es[k], &part[k]});
        advance_parts(parts, segment, Execution{isa, threads, 8});
        for (std::size_t k = 0; k < ps.size(); ++k) os[k].merge(std::move(part[k]));
      }
      for (std::size_t k = 0; k < ps.size(); ++k) {
        os[k].finish();
        const std::string what = std::string(isa_name(isa)) + ", " + std::to_string(threads) +
                                 " threads, point " + std::to_string(k);
        expect_same_orbits(alone[k], es[k], what);
        expect_same_observers(alone_observers[k], os[k], what);
      }
    }
}

}  // namespace
}  // namespace qmaps
