// Sections of mode exact (Hénon's method, kernels/flow.hpp): points on the plane to round-off,
// the error of one composition over the distance to the plane falling at the integrator's order
// against a high-precision crossing, the run's points those of each orbit's own iterates on every
// path, the linear fallback where no iterate heads to the plane.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstring>
#include <vector>

#include "core/observers/section/section_lanes.hpp"
#include "ensemble_fixtures.hpp"
#include "isas_run.hpp"
#include "kernels/flow.hpp"

namespace qmaps {
namespace {

using kernels::Flow;
using kernels::Leapfrog;

// Case IV's potential (no second integral is needed here) at step h and order `order`.
Flow::Coeffs flow(int order, double h = 0.05) {
  return Flow::coefficients(std::array{0.7, 2.8, 0.9, 7.2, 5.4, h, double(order)});
}

// How far a point may lie off its plane: the round-off of summing the composition's drifts.
constexpr double on_plane_round_off = 1e-14;

TEST(ExactSection, PointsLieOnThePlaneToRoundOff) {
  const auto points = testing::box_points(2000, 0.4, 0.8, 11);
  for (int order : {2, 4, 6, 8}) {
    const auto c = flow(order);
    for (std::size_t k : {0, 1})
      for (double value : {0.0, 0.1, -0.25}) {
        double worst = 0;
        for (const Phase& x : points) {
          std::array<double, 4> s = {x.q1, x.q2, x.p1, x.p2};
          // Heading to the plane from a distance up to 0.05 (a step's move at h = 0.05).
          const double distance = 0.05 * std::fabs(x.q1 - x.q2) / 0.8;
          s[k] = s[2 + k] > 0 ? value - distance : value + distance;
          const auto y = Flow::to_plane(c, s, k, value - s[k]);
          ASSERT_TRUE(std::isfinite(y[k]));
          worst = std::max(worst, std::fabs(y[k] - value));
        }
        EXPECT_LE(worst, on_plane_round_off) << "order " << order << ", plane q" << k + 1
                                             << " = " << value;
      }
  }
}

// The reference: the flow in long double, order 8 at step T/500, from the point P on the plane
// backward for time T (reversed: momenta flipped, forward, flipped back).
std::array<double, 4> before_plane(const std::array<double, 4>& P, double T) {
  const auto c = flow(8, T / 500);
  std::array<long double, 4> s = {P[0], P[1], -static_cast<long double>(P[2]),
                                  -static_cast<long double>(P[3])};
  for (int n = 0; n < 500; ++n) Flow::step(c, s);
  return {static_cast<double>(s[0]), static_cast<double>(s[1]), -static_cast<double>(s[2]),
          -static_cast<double>(s[3])};
}

// Points P of the plane q1 = 0 and where the flow was a time T before each.
struct Crossings {
  std::vector<std::array<double, 4>> on_plane, before;
};
Crossings crossings(double T) {
  Crossings out;
  for (const Phase& x : testing::box_points(20, 0.3, 0.5, 5)) {
    out.on_plane.push_back({0.0, x.q2, 0.8 + x.p1, x.p2});
    out.before.push_back(before_plane(out.on_plane.back(), T));
  }
  return out;
}

// The largest error of the exact points against the reference.
double worst_error(const Flow::Coeffs& c, const Crossings& x) {
  double worst = 0;
  for (std::size_t n = 0; n < x.before.size(); ++n) {
    const auto y = Flow::to_plane(c, x.before[n], 0, -x.before[n][0]);
    for (std::size_t i = 1; i < 4; ++i) worst = std::max(worst, std::fabs(y[i] - x.on_plane[n][i]));
  }
  return worst;
}

// An error falling at order p over one composition falls by 2^(p+1) when the distance halves;
// measured ratios (case IV's potential, |p1| 0.3 to 1.3): 9.1 and 8.6 at order 2 (8), 47 and 37
// at order 4 (32), 160 and 143 at order 6 (128), 467 and 460 at order 8 (512). The tolerance
// against the independent reference: 60% of 2^(p+1).
constexpr double order_ratio_tolerance = 0.6;

TEST(ExactSection, ErrorAgainstAHighPrecisionCrossingFallsAtTheIntegratorsOrder) {
  std::vector<Crossings> at;  // T = 0.2, 0.1, …, 0.0125
  for (double T = 0.2; T > 0.01; T /= 2) at.push_back(crossings(T));
  for (int order : {2, 4, 6, 8}) {
    const auto c = flow(order);
    const std::size_t first = order == 8 ? 2 : 0;  // order 8 from T = 0.05, above round-off
    double e[3];
    for (std::size_t i = 0; i < 3; ++i) e[i] = worst_error(c, at[first + i]);
    std::printf("order %d: worst error %.3g, %.3g, %.3g (distance halved each time)\n", order,
                e[0], e[1], e[2]);
    const double expected = std::pow(2.0, order + 1);
    EXPECT_GE(e[0] / e[1], order_ratio_tolerance * expected) << "order " << order;
    EXPECT_GE(e[1] / e[2], order_ratio_tolerance * expected) << "order " << order;
  }
}

TEST(ExactSection, LeapfrogsPointsAreItsOwnCompositionsOfOrderTwo) {
  const auto c = Leapfrog::coefficients(std::array{0.7, 2.8, 0.9, 7.2, 5.4, 0.05});
  const auto reference = flow(2);
  for (const Phase& x : testing::box_points(50, 0.3, 0.5, 3)) {
    const std::array<double, 4> s = {-0.03, x.q2, 0.8 + x.p1, x.p2};
    const auto a = Leapfrog::to_plane(c, s, 0, 0.03), b = Flow::to_plane(reference, s, 0, 0.03);
    EXPECT_EQ(std::memcmp(a.data(), b.data(), sizeof a), 0);
  }
}

// A crossing from which neither iterate heads to the plane (momentum away from it at both)
// cannot be integrated: its point is the linear interpolation, and the lane is counted.
TEST(ExactSection, CrossingNoIterateHeadsToIsInterpolatedAndCounted) {
  const auto c = flow(4);
  Section s;
  s.plane = Coordinate::q1;
  s.mode = SectionMode::exact;
  const std::array<double, 5> before = {-0.1, 0.2, -1.0, 0.3, 0}, after = {0.1, 0.4, -1.0, 0.5, 0};
  bool interpolated = false;
  const auto xy = section_point<Flow>(c, s, before, after, interpolated);
  EXPECT_TRUE(interpolated);
  EXPECT_EQ(xy[0], 0.2 + 0.5 * (0.4 - 0.2));  // halfway: the linear interpolation
  EXPECT_EQ(xy[1], 0.3 + 0.5 * (0.5 - 0.3));
  // Heading there from before: integrated, on the plane.
  const std::array<double, 5> heading = {-0.1, 0.2, 1.0, 0.3, 0};
  section_point<Flow>(c, s, heading, after, interpolated);
  EXPECT_FALSE(interpolated);
}

Observers exact_section(std::size_t orbits) {
  Observers o;
  Section s;
  s.name = "q1up";
  s.mode = SectionMode::exact;
  s.direction = 0;
  s.cap = 40;
  s.density = Histogram("q1up", {{"q2", -1, 1, 16}, {"p2", -1, 1, 16}});
  s.points = std::make_shared<SectionPoints>(orbits, s.cap);
  o.sections.push_back(std::move(s));
  return o;
}

TEST(ExactSection, RunRecordsEachOrbitsOwnExactPointsOnEveryPath) {
  const ParamValues params = {{"A", 0.7}, {"B", 2.8}, {"alpha", 0.9}, {"beta", 7.2},
                              {"delta", 5.4}, {"h", 0.05}, {"order", 4}};
  const auto model = make_model("flow", params);
  const auto c = flow(4);
  const auto points = testing::box_points(301, 0.5, 0.5);
  RunPlan plan;
  plan.total = plan.last = 300;
  plan.stride = 7;
  plan.escape_bound = 1e8;

  // Expected: from each orbit's own iterates, the rule of section_point at V = double.
  std::vector<SectionPoint> expected;
  for (std::size_t i = 0; i < points.size(); ++i) {
    auto s = Flow::from_phase_space(c, points[i], Start::taylor);
    std::int64_t kept = 0;
    for (long long n = 1; n <= plan.total; ++n) {
      const auto before = s;
      Flow::step(c, s);
      if (kept == 40 || !((before[0] < 0 && s[0] >= 0) || (before[0] > 0 && s[0] <= 0))) continue;
      const bool after_heads = s[0] * s[2] > 0 || s[0] == 0;
      const bool from_before = before[0] * before[2] < 0 &&
                               (!after_heads || std::fabs(before[0]) <= std::fabs(s[0]));
      const auto y = from_before ? Flow::to_plane(c, before, 0, -before[0])
                                 : Flow::to_plane(c, s, 0, -s[0]);
      expected.push_back({static_cast<std::int64_t>(i), n, y[1], y[3]});
      ++kept;
    }
  }

  Observers ref = exact_section(points.size());
  Ensemble e0 = model->start(points, Start::taylor, plan.escape_bound);
  model->advance(e0, plan, Execution{Isa::scalar, 1, 1}, &ref);
  const auto got = ref.sections[0].points->all();
  EXPECT_EQ(ref.sections[0].interpolated, 0);
  ASSERT_EQ(got.size(), expected.size());
  ASSERT_GT(got.size(), points.size());
  for (std::size_t k = 0; k < got.size(); ++k) {
    EXPECT_EQ(got[k].orbit, expected[k].orbit);
    EXPECT_EQ(got[k].step, expected[k].step);
    EXPECT_EQ(std::memcmp(&got[k].x, &expected[k].x, sizeof(double)), 0) << "point " << k;
    EXPECT_EQ(std::memcmp(&got[k].y, &expected[k].y, sizeof(double)), 0) << "point " << k;
  }

  for (Isa isa : testing::isas_to_run())
    for (int threads : {1, 2})
      for (int chains : {1, 4, 8}) {
        Observers o = exact_section(points.size());
        Ensemble e = model->start(points, Start::taylor, plan.escape_bound);
        model->advance(e, plan, Execution{isa, threads, chains}, &o);
        const auto p = o.sections[0].points->all();
        ASSERT_EQ(p.size(), got.size());
        EXPECT_EQ(std::memcmp(p.data(), got.data(), p.size() * sizeof(SectionPoint)), 0)
            << isa_name(isa) << " " << threads << " threads, " << chains << " chains";
        EXPECT_TRUE(std::ranges::equal(o.sections[0].density.counts(), ref.sections[0].density.counts()));
        EXPECT_EQ(o.sections[0].interpolated, 0);
      }
}

}  // namespace
}  // namespace qmaps
