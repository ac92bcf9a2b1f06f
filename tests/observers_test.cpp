// Observers: histogram totals, section points against crossings recomputed from each orbit's own
// iterates, iterate-mode points on their orbit's level set, the arcsine law of a linear map,
// caps bounding memory, and identical output on every path.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>
#include <tuple>
#include <utility>
#include <vector>

#include "core/observers/invariants/invariant_columns.hpp"
#include "core/isa.hpp"
#include "core/observers/histogram_lanes.hpp"
#include "ensemble_fixtures.hpp"
#include "isas_run.hpp"
#include "kernels/suris.hpp"

namespace qmaps {
namespace {

using kernels::Suris;

Observers observers(std::size_t orbits, std::int64_t cap, bool linear = false) {
  Observers o;
  o.densities.push_back({Histogram("q1q2", {{"q1", -1, 1, 32}, {"q2", -1, 1, 32}}),
                         {Coordinate::q1, Coordinate::q2}});
  o.densities.push_back({Histogram("p1", {{"p1", -0.6, 0.6, 40}}), {Coordinate::p1}});
  Section s;
  s.name = "q1up";
  s.plane = Coordinate::q1;
  s.value = 0.0;
  s.direction = 1;
  s.mode = linear ? SectionMode::linear : SectionMode::iterate;
  s.x = Coordinate::q2;
  s.y = Coordinate::p2;
  s.cap = cap;
  s.density = Histogram("q1up", {{"q2", -1, 1, 16}, {"p2", -1, 1, 16}});
  s.points = std::make_shared<SectionPoints>(orbits, cap);
  o.sections.push_back(std::move(s));
  return o;
}

RunPlan plan_of(long long steps, long long stride, double bound = 1e8) {
  RunPlan plan;
  plan.total = plan.last = steps;
  plan.stride = stride;
  plan.escape_bound = bound;
  return plan;
}

std::int64_t total(const Histogram& h) {
  std::int64_t t = h.underflow() + h.overflow();
  for (auto c : h.counts()) t += c;
  return t;
}

bool same_bytes(const Observers& a, const Observers& b) {
  for (std::size_t i = 0; i < a.densities.size(); ++i) {
    const auto &x = a.densities[i].histogram, &y = b.densities[i].histogram;
    if (!std::ranges::equal(x.counts(), y.counts()) || x.underflow() != y.underflow() || x.overflow() != y.overflow())
      return false;
  }
  for (std::size_t i = 0; i < a.sections.size(); ++i) {
    const auto &x = a.sections[i], &y = b.sections[i];
    const auto p = x.points->all(), q = y.points->all();
    if (p.size() != q.size() || !std::ranges::equal(x.density.counts(), y.density.counts())) return false;
    if (!p.empty() && std::memcmp(p.data(), q.data(), p.size() * sizeof(SectionPoint)) != 0)
      return false;
  }
  return true;
}

TEST(Observers, OutputIsBitIdenticalOnEveryIsaThreadCountAndBlockSize) {
  for (double alpha : {0.9, -0.4}) {  // bounded, and escaping orbits
    const auto model = testing::suris(0.7, 0.3, alpha, 0.1);
    const auto points = testing::box_points(1001, alpha > 0 ? 0.5 : 1.2, alpha > 0 ? 0.5 : 1.0);
    const RunPlan plan = plan_of(300, 7, alpha > 0 ? 1e8 : 10);
    for (bool linear : {false, true}) {
      Observers ref = observers(points.size(), 3, linear);
      Ensemble e0 = model->start(points, Start::taylor, plan.escape_bound);
      model->advance(e0, plan, Execution{}, &ref);
      for (Isa isa : runnable_isas())
        for (int threads : {1, 2})
          for (int chains : {1, 4, 8}) {
            Observers o = observers(points.size(), 3, linear);
            Ensemble e = model->start(points, Start::taylor, plan.escape_bound);
            model->advance(e, plan, Execution{isa, threads, chains}, &o);
            EXPECT_TRUE(same_bytes(ref, o)) << isa_name(isa) << " " << threads << " threads, "
                                            << chains << " chains, alpha " << alpha;
          }
    }
  }
}

Section section(std::string name, Coordinate plane, int direction, bool linear, std::int64_t cap,
                std::size_t orbits) {
  Section s;
  s.name = std::move(name);
  s.plane = plane;
  s.direction = direction;
  s.mode = linear ? SectionMode::linear : SectionMode::iterate;
  s.x = plane == Coordinate::q1 ? Coordinate::q2 : Coordinate::q1;
  s.y = plane == Coordinate::q1 ? Coordinate::p2 : Coordinate::p1;
  s.cap = cap;
  s.density = Histogram(s.name, {{"x", -1, 1, 16}, {"y", -1, 1, 16}});
  s.points = std::make_shared<SectionPoints>(orbits, cap);
  return s;
}

// Runs `make()`'s observers on the reference and on every ISA × threads × chains; every path
// must give the reference's bytes (observers, states, escapes). Returns the reference.
template <class Make>
std::pair<Observers, Ensemble> expect_every_path_equal(const Model& model,
                                                        const std::vector<Phase>& points,
                                                        const RunPlan& plan, Make make,
                                                        const std::string& what,
                                                        Start start = Start::taylor) {
  Observers ref = make();
  Ensemble e0 = model.start(points, start, plan.escape_bound);
  model.advance(e0, plan, Execution{}, &ref);
  for (Isa isa : testing::isas_to_run())
    for (int threads : {1, 2})
      for (int chains : {1, 4, 8}) {
        Observers o = make();
        Ensemble e = model.start(points, start, plan.escape_bound);
        model.advance(e, plan, Execution{isa, threads, chains}, &o);
        const std::string where = what + ": " + std::string(isa_name(isa)) + ", " +
                                  std::to_string(threads) + " threads, " +
                                  std::to_string(chains) + " chains";
        EXPECT_TRUE(same_bytes(ref, o)) << where;
        EXPECT_EQ(std::memcmp(e.escape_step.data(), e0.escape_step.data(), e.orbits * 8), 0)
            << where;
        for (std::size_t k = 0; k < e.state.size(); ++k)
          EXPECT_EQ(std::memcmp(e.state[k].data(), e0.state[k].data(), e.orbits * 8), 0) << where;
      }
  return {std::move(ref), std::move(e0)};
}

// Sections are watched inside chunks of up to 256 steps (no samples between): crossings at a
// chunk's first and last step, several in one chunk, and escapes in the step right after a
// crossing are recorded exactly as the reference records them.
TEST(Observers, SectionsWatchedInsideChunksAreBitIdenticalOnEveryPath) {
  for (double alpha : {0.9, -0.4}) {
    const auto model = testing::suris(0.7, 0.3, alpha, 0.1);
    const auto points = testing::box_points(2001, alpha > 0 ? 0.5 : 1.2, alpha > 0 ? 0.5 : 1.0);
    RunPlan plan = plan_of(1000, 1000, alpha > 0 ? 1e8 : 10);
    plan.measure_orbits = false;
    const auto make = [&] {
      Observers o;
      o.sections.push_back(section("q1both", Coordinate::q1, 0, false, 1000, points.size()));
      return o;
    };
    const auto [ref, e0] = expect_every_path_equal(*model, points, plan, make,
                                                   "alpha " + std::to_string(alpha));
    const auto pts = ref.sections[0].points->all();
    ASSERT_FALSE(pts.empty());
    bool first_of_chunk = false, last_of_chunk = false, twice_in_a_chunk = false,
         escape_after = false;
    for (std::size_t i = 0; i < pts.size(); ++i) {
      first_of_chunk |= pts[i].step % 256 == 1;
      last_of_chunk |= pts[i].step % 256 == 0;
      if (i > 0 && pts[i - 1].orbit == pts[i].orbit)
        twice_in_a_chunk |= (pts[i - 1].step - 1) / 256 == (pts[i].step - 1) / 256;
      escape_after |= e0.escape_step[static_cast<std::size_t>(pts[i].orbit)] == pts[i].step + 1;
    }
    EXPECT_TRUE(first_of_chunk && last_of_chunk && twice_in_a_chunk) << "alpha " << alpha;
    if (alpha < 0) {
      EXPECT_TRUE(escape_after) << "no orbit escapes right after a crossing";
    }
  }
}

// A chunk packs every lane that crosses, at every one of its steps if need be: with h = 2,
// Suris' map has a stable 2-cycle q, −q at |q|² = (−a − 1)/g (a = 1 − Ah², g = 2αh²; here
// q1 = ±1/3, q2 = 0), and the orbits started near it (an Euler start, q_1 = q_0 + h p ≈ −q_0)
// cross q1 = 0 at every step, so that each chunk's packed lanes fill its room.
TEST(Observers, SectionCrossedAtEveryStepIsBitIdenticalOnEveryPath) {
  const double h = 2;
  const auto model = testing::suris(0.7, 0.3, 0.9, h);
  std::vector<Phase> points = testing::box_points(1001, 0.05, 0.05);
  for (std::size_t i = 0; i < points.size(); ++i) {  // jitter of q and of q_1 + q_0 up to 0.05
    Phase& x = points[i];
    const double q1 = (i % 2 ? 1.0 : -1.0) / 3 + x.q1, q2 = x.q2;
    x = {q1, q2, (x.p1 - 2 * q1) / h, (x.p2 - 2 * q2) / h};
  }
  const auto make = [&] {
    Observers o;
    o.sections.push_back(section("q1both", Coordinate::q1, 0, false, 600, points.size()));
    return o;
  };
  const auto [ref, e0] =
      expect_every_path_equal(*model, points, plan_of(600, 600), make, "h = 2", Start::euler);
  std::size_t every_step = 0;  // orbits that crossed at every step
  for (const std::int64_t kept : ref.sections[0].points->kept()) every_step += kept == 600;
  EXPECT_GT(every_step, 990u) << "the orbits must cross at every step";
}

TEST(Observers, SectionWithCapZeroCountsItsDensityOnlyOnEveryPath) {
  const auto model = testing::suris();
  const auto points = testing::box_points(1001, 0.5, 0.5);
  const auto make = [&] {
    Observers o;
    o.sections.push_back(section("q1up", Coordinate::q1, 1, false, 0, points.size()));
    return o;
  };
  const auto [ref, e0] = expect_every_path_equal(*model, points, plan_of(600, 50), make, "cap 0");
  EXPECT_EQ(ref.sections[0].points->size(), 0u);
  EXPECT_GT(total(ref.sections[0].density), 1000);
}

// Two sections (one over a momentum plane, interpolated) and two densities at once; and five
// sections, more than the chunks watch, checked step by step.
TEST(Observers, SeveralSectionsAndDensitiesAtOnceAreBitIdenticalOnEveryPath) {
  const auto model = testing::suris();
  const auto points = testing::box_points(1001, 0.5, 0.5);
  const auto two = [&] {
    Observers o = observers(points.size(), 5);
    o.sections.push_back(section("p2down", Coordinate::p2, -1, true, 5, points.size()));
    return o;
  };
  const auto [ref, e0] = expect_every_path_equal(*model, points, plan_of(500, 10), two, "two");
  EXPECT_GT(ref.sections[1].points->size(), 0u);
  const auto five = [&] {
    Observers o;
    for (int i = 0; i < 5; ++i)
      o.sections.push_back(section(std::string(1, static_cast<char>('a' + i)),
                                   i % 2 ? Coordinate::q2 : Coordinate::q1,
                                   i % 3 - 1, i == 4, 10, points.size()));
    return o;
  };
  expect_every_path_equal(*model, points, plan_of(300, 300), five, "five");
}

// Without sections the runner samples inside its chunks, every step at stride 1 and every 7th at
// stride 7; a chunk whose escape test trips is replayed step by step, taking only the samples it
// had not taken. Both must give the reference's bytes.
TEST(Observers, DensitiesAndDriftWithoutSectionsAreBitIdenticalAtStrideOneAndSeven) {
  const auto same_column = [](const auto& x, const auto& y, std::size_t n) {
    return std::memcmp(x.data(), y.data(), n * sizeof(x[0])) == 0;
  };
  for (double alpha : {0.9, -0.4})
    for (long long stride : {1, 7}) {
      const auto model = testing::suris(0.7, 0.3, alpha, 0.1);
      const auto points = testing::box_points(1001, alpha > 0 ? 0.5 : 1.2, alpha > 0 ? 0.5 : 1.0);
      const RunPlan plan = plan_of(300, stride, alpha > 0 ? 1e8 : 10);
      Observers ref = observers(points.size(), 3);
      ref.sections.clear();
      Ensemble e0 = model->start(points, Start::taylor, plan.escape_bound);
      model->advance(e0, plan, Execution{}, &ref);
      for (Isa isa : runnable_isas())
        for (int chains : {1, 8}) {
          Observers o = observers(points.size(), 3);
          o.sections.clear();
          Ensemble e = model->start(points, Start::taylor, plan.escape_bound);
          model->advance(e, plan, Execution{isa, 2, chains}, &o);
          const std::string where = std::string(isa_name(isa)) + " " + std::to_string(chains) +
                                    " chains, stride " + std::to_string(stride) + ", alpha " +
                                    std::to_string(alpha);
          EXPECT_TRUE(same_bytes(ref, o)) << where;
          EXPECT_TRUE(same_column(e.escape_step, e0.escape_step, e.orbits)) << where;
          for (std::size_t k = 0; k < e.state.size(); ++k)
            EXPECT_TRUE(same_column(e.state[k], e0.state[k], e.orbits)) << where;
          for (std::size_t k = 0; k < e.columns.size(); ++k)
            EXPECT_TRUE(same_column(e.columns[k], e0.columns[k], e.orbits)) << where;
        }
    }
}

TEST(Observers, PendingTalliesReachTheCountsExactlyPastSixteenBits) {
  Histogram h("h", {{"x", 0, 1, 2}});
  const double inside[2] = {0.75, 0}, below[2] = {-1, 0};  // one axis; add_lanes reads up to two
  for (int i = 0; i < 200000; ++i) h.add_lanes<double>(inside, true);
  h.add_lanes<double>(below, true);
  h.add_lanes<double>(below, false);  // discarded
  Histogram merged = h.empty_copy();
  merged.merge(h);  // takes the pending tallies too
  EXPECT_EQ(merged.counts()[1], 200000);
  EXPECT_EQ(merged.underflow(), 1);
  EXPECT_EQ(merged.samples(), 200001);  // not the discarded lane
  h.flush();
  EXPECT_TRUE(std::ranges::equal(h.counts(), merged.counts()));
  EXPECT_EQ(h.underflow(), 1);
  EXPECT_EQ(h.counts()[0], 0);
}

TEST(Observers, HistogramTotalIsOrbitsTimesSamplesMinusSamplesLostToEscapes) {
  const auto model = testing::suris(0.7, 0.3, -0.4, 0.1);
  const auto points = testing::box_points(2000, 1.2, 1.0);
  const RunPlan plan = plan_of(250, 10, 10);
  Observers o = observers(points.size(), 5);
  Ensemble e = model->start(points, Start::taylor, plan.escape_bound);
  model->advance(e, plan, Execution{best_isa(), 2, 4}, &o);
  ASSERT_GT(e.escaped(), 100u);
  std::int64_t expected = 0;  // samples at n = 0, 10, …, 250 while not escaped (n < escape step)
  for (std::size_t i = 0; i < e.orbits; ++i)
    for (long long n = 0; n <= plan.total; n += plan.stride)
      expected += e.escape_step[i] < 0 || n < e.escape_step[i];
  for (const auto& d : o.densities) {
    EXPECT_EQ(total(d.histogram), expected) << d.histogram.name();
    EXPECT_EQ(d.histogram.samples(), expected);
  }
}

TEST(Observers, SectionPointsAreTheCrossingsOfEachOrbitsOwnIterates) {
  const auto model = testing::suris();
  const auto c = Suris::coefficients(std::array{0.7, 0.3, 0.9, 0.1});
  const auto points = testing::box_points(50, 0.5, 0.5, 9);
  const RunPlan plan = plan_of(2000, 1);
  for (bool linear : {false, true}) {
    Observers o = observers(points.size(), 1000, linear);
    Ensemble e = model->start(points, Start::taylor, plan.escape_bound);
    model->advance(e, plan, Execution{best_isa(), 2, 4}, &o);
    std::vector<SectionPoint> expected;
    for (std::size_t i = 0; i < points.size(); ++i) {
      auto s = Suris::from_phase_space(c, points[i], Start::taylor);
      auto before = Suris::phase(c, s);
      for (long long n = 1; n <= plan.total; ++n) {
        Suris::step(c, s);
        const auto after = Suris::phase(c, s);
        if (before[0] < 0 && after[0] >= 0) {
          double x = after[1], y = after[3];
          if (linear) {
            const double f = (0 - before[0]) / (after[0] - before[0]);
            x = before[1] + f * (after[1] - before[1]);
            y = before[3] + f * (after[3] - before[3]);
          }
          expected.push_back({static_cast<std::int64_t>(i), n, x, y});
        }
        before = after;
      }
    }
    const auto got = o.sections[0].points->all();
    ASSERT_EQ(got.size(), expected.size());
    for (std::size_t k = 0; k < got.size(); ++k) {
      EXPECT_EQ(got[k].orbit, expected[k].orbit);
      EXPECT_EQ(got[k].step, expected[k].step);
      EXPECT_EQ(got[k].x, expected[k].x);
      EXPECT_EQ(got[k].y, expected[k].y);
    }
  }
}

TEST(Observers, IteratePointsLieOnTheirOrbitsLevelSetWithinTolerance) {
  // The iterate after a crossing is a point of the orbit: its state conserves H, I1, I2.
  const auto model = testing::suris();
  const auto c = Suris::coefficients(std::array{0.7, 0.3, 0.9, 0.1});
  const auto points = testing::box_points(20, 0.5, 0.5, 4);
  Observers o = observers(points.size(), 1000);
  Ensemble e = model->start(points, Start::taylor, 1e8);
  model->advance(e, plan_of(3000, 1), Execution{best_isa(), 1, 4}, &o);
  ASSERT_GT(o.sections[0].points->size(), 200u);
  for (const auto& p : o.sections[0].points->all()) {
    auto s = Suris::from_phase_space(c, points[static_cast<std::size_t>(p.orbit)], Start::taylor);
    double I0[3], I[3];
    Suris::invariants(c, s, I0);
    for (long long n = 0; n < p.step; ++n) Suris::step(c, s);
    const auto x = Suris::phase(c, s);
    ASSERT_EQ(x[1], p.x);
    ASSERT_EQ(x[3], p.y);
    EXPECT_GE(x[0], 0.0);
    Suris::invariants(c, s, I);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(I[k], I0[k], 1e-12 * std::fabs(I0[k]));
  }
}

TEST(Observers, LinearMapDensityFollowsArcsineLawWithinTolerance) {
  // α = 0: q1_n = C cos(θn + φ), cos θ = a = 1 − Ah², C² = I1/(1 − a²); the density of q1 over a
  // long orbit is 1/(π√(C² − x²)), whose distribution function is ½ + arcsin(x/C)/π.
  const auto model = testing::suris(0.7, 0.3, 0.0, 0.1);
  const Phase x0{0.3, -0.2, 0.1, 0.4};
  Ensemble e = model->start(std::span(&x0, 1), Start::taylor, 1e8);
  const double a = 1 - 0.7 * 0.01, C = std::sqrt(invariant_initial(e, 1)[0] / (1 - a * a));
  Observers o;
  o.densities.push_back({Histogram("q1", {{"q1", -C, C, 50}}), {Coordinate::q1}});
  model->advance(e, plan_of(1000000, 1), Execution{}, &o);
  const auto& h = o.densities[0].histogram;
  EXPECT_EQ(h.underflow() + h.overflow(), 0);
  double cumulative = 0, worst = 0;
  const auto edges = h.axes()[0].edges();
  for (std::size_t k = 0; k < h.counts().size(); ++k) {
    cumulative += static_cast<double>(h.counts()[k]) / static_cast<double>(h.samples());
    const double law = 0.5 + std::asin(std::clamp(edges[k + 1] / C, -1.0, 1.0)) / std::numbers::pi;
    worst = std::max(worst, std::fabs(cumulative - law));
  }
  std::printf("[ arcsine ] 1e6 samples, max |F_n − F| = %.2e\n", worst);
  EXPECT_LT(worst, 1e-4);  // Kolmogorov–Smirnov distance at the bin edges; measured 7.5e-6
}

TEST(Observers, CapsBoundTheStoredPointsWhileTheDensityCountsEveryCrossing) {
  const auto model = testing::suris();
  const auto points = testing::box_points(500, 0.5, 0.5, 8);
  Observers o = observers(points.size(), 2);
  Ensemble e = model->start(points, Start::taylor, 1e8);
  model->advance(e, plan_of(2000, 50), Execution{best_isa(), 2, 4}, &o);
  const auto& s = o.sections[0];
  EXPECT_LE(s.points->size(), 2 * points.size());
  std::vector<int> per_orbit(points.size(), 0);
  for (const auto& p : s.points->all()) ++per_orbit[static_cast<std::size_t>(p.orbit)];
  for (int n : per_orbit) EXPECT_LE(n, 2);
  EXPECT_GT(s.density.samples(), static_cast<std::int64_t>(10 * points.size()));
  EXPECT_EQ(total(s.density), s.density.samples());
}

// Points kept in any order of orbits (as threads and chunks keep them) read back in (orbit, step)
// order, at most per_orbit() each, whole or in parts from any point.
TEST(Observers, SectionPointsReadInOrbitStepOrderWithinEachOrbitsSlots) {
  SectionPoints p(64, 3);
  p.keep(40, 3, 1, 0);
  p.keep(7, 2, 2, 0);
  p.keep(40, 9, 3, 0);
  p.keep(0, 6, 4, 0);
  p.keep(7, 4, 5, 0);
  p.keep(7, 8, 6, 0);
  p.keep(7, 9, 7, 0);  // beyond its 3 slots: not kept
  p.keep(63, 1, 8, 0);
  const std::vector<std::tuple<std::int64_t, std::int64_t, double>> expected = {
      {0, 6, 4}, {7, 2, 2}, {7, 4, 5}, {7, 8, 6}, {40, 3, 1}, {40, 9, 3}, {63, 1, 8}};
  std::vector<std::tuple<std::int64_t, std::int64_t, double>> got;
  for (const auto& q : p.all()) got.emplace_back(q.orbit, q.step, q.x);
  EXPECT_EQ(got, expected);
  EXPECT_EQ(p.size(), expected.size());
  EXPECT_EQ(p.kept()[7], 3);
  for (std::size_t first = 0; first < expected.size(); ++first)  // parts of 2 from any point
    for (std::size_t n = 1; n <= 2 && first + n <= expected.size(); ++n) {
      std::vector<SectionPoint> part(n);
      SectionPoints::Cursor cursor;
      if (first > 0) p.read(first - 1, std::span(part).first(1), cursor);  // a cursor behind
      p.read(first, part, cursor);
      for (std::size_t i = 0; i < n; ++i)
        EXPECT_EQ(std::get<1>(expected[first + i]), part[i].step) << first << " + " << i;
    }
  std::vector<SectionPoint> past(1);
  SectionPoints::Cursor cursor;
  EXPECT_THROW(p.read(expected.size(), past, cursor), std::out_of_range);
  p.clear();
  EXPECT_EQ(p.size(), 0u);
  EXPECT_EQ(p.bytes(), 64u * (8 + 3 * 24));
}

// An orbit's slots: no more than the cap, nor than the crossings its steps allow.
TEST(Observers, SlotsPerOrbitAreBoundedByTheCapAndTheSteps) {
  EXPECT_EQ(Section::slots_per_orbit(100, 0, 1000), 100);
  EXPECT_EQ(Section::slots_per_orbit(100, 0, 30), 30);   // one crossing a step, both ways
  EXPECT_EQ(Section::slots_per_orbit(100, 1, 31), 16);   // one in two steps, one way
  EXPECT_EQ(Section::slots_per_orbit(100, -1, 30), 15);
  EXPECT_EQ(Section::slots_per_orbit(0, 1, 30), 0);
}

}  // namespace
}  // namespace qmaps
