// The tunes' parts against independent references: the project's sine and cosine against long
// double, NAFF against signals of known frequencies, and every integrable map's orbits, whose
// diffusion must be that of tori (below −10). The exact references of whole runs
// (Suris' linear map and its McMillan plane) are tests/tunes_test.py's.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "core/isa.hpp"
#include "core/observers/lane_observers.hpp"
#include "core/observers/tunes/naff.hpp"
#include "core/observers/tunes/tunes.hpp"
#include "ensemble_fixtures.hpp"
#include "kernels/catalogue.hpp"

namespace qmaps {
namespace {

// |sin_cos − sinl, cosl| against long double, over the tunes' angles and beyond.
constexpr double sin_cos_vs_long_double = 2.3e-16;  // 1 ulp of 1
// A quasi-periodic signal's NAFF error at N = 2048, order 2, with the components below (the
// nearest other line 25 bins away at a tenth of the amplitude: 1.2e-11).
constexpr double naff_vs_exact_frequency = 1e-10;
constexpr double integrable_diffusion_below = -10;

TEST(Tunes, SinCosAgreesWithLongDoubleToAnUlp) {
  double worst = 0;
  for (int i = -200000; i <= 200000; ++i) {
    const double x = i * 1e-4 * 3.3;  // |x| ≤ 66: the window's and twiddles' angles are within 2π
    double s, c;
    ops::sin_cos(x, s, c);
    const long double xs = x;
    worst = std::max({worst, static_cast<double>(std::fabs(s - std::sin(xs))),
                      static_cast<double>(std::fabs(c - std::cos(xs)))});
  }
  std::cout << "sin_cos against long double, |x| <= 66: max |error| " << worst << '\n';
  EXPECT_LE(worst, sin_cos_vs_long_double);
}

TEST(Tunes, NaffFindsTheFrequenciesOfAQuasiPeriodicSignal) {
  const long long n = 2048;
  const auto& t = naff_tables(n, 2);
  const double two_pi = 2 * std::acos(-1.0);
  for (const double nu1 : {0.0123, 0.1876, 0.2507, 0.4611}) {
    const double nu2 = 0.28 + nu1 / 3;  // each line and its mirror image far apart
    std::vector<double> signal(2 * n);
    for (long long k = 0; k < n; ++k) {
      const double j = static_cast<double>(k + 1);
      signal[2 * k] = std::cos(two_pi * nu1 * j + 0.3) + 0.1 * std::cos(two_pi * nu2 * j);
      signal[2 * k + 1] = 0.5 * std::sin(two_pi * nu2 * j) + 0.05 * std::cos(two_pi * (nu1 + nu2) * j);
    }
    double omega[2];
    naff::search(signal.data(), t, omega);
    bool active[2] = {true, true};
    double power[2] = {0, 0};
    naff::refine(signal.data(), t, omega, active, power);
    EXPECT_FALSE(active[0] || active[1]) << "converged";
    EXPECT_NEAR(omega[0] / two_pi, nu1, naff_vs_exact_frequency) << nu1;
    EXPECT_NEAR(omega[1] / two_pi, nu2, naff_vs_exact_frequency) << nu2;
  }
}

// The tunes' columns of `orbits` started at `points` and advanced over two windows of `window`.
std::span<const AlignedArray<double>> tunes_of(const Model& model, Ensemble& e,
                                               std::span<const Phase> points, long long window) {
  model.start_at(e, 0, points, Start::taylor, 1e8);
  e.fill_padding();
  RunPlan plan;
  plan.total = plan.last = 2 * window;
  plan.tunes.window = window;
  model.advance(e, plan, Execution{best_isa(), 2, 8});
  return e.columns_of(lane_index<Tunes>);
}

// Every map whose invariants hold to round-off (the paper's discretizations) on its invariant
// plane q2 = p2 = 0, where it is a map of one degree of freedom and q1 has one line: the orbits
// lie on invariant curves, so the tunes of two windows agree. Judged: the orbits that stay on the
// plane (q2 exactly 0 at every step, so no tune ν2) with a line resolved by the window (more than
// 16 bins from 0 and from 1/2). The maps that step in physical time (h): case III steps in its
// Levi-Civita time s, where its orbits leave the plane by round-off and q1 (the squares of its
// Levi-Civita coordinates) has its line a few bins from its mean.
TEST(Tunes, EveryIntegrableMapInPhysicalTimeHasTheDiffusionOfToriOnItsPlane) {
  const long long window = 2048;
  for (const MapEntry& m : catalogue()) {
    if (m.facts->drift_tolerance > 1e-9) continue;  // the flows: splittings, not integrable maps
    if (m.facts->step != "h") continue;
    SCOPED_TRACE(m.name);
    const auto model = make_model(m.name, param_values(m.facts->example));
    std::vector<Phase> line;
    for (int i = 0; i < 64; ++i) line.push_back({0.05 + 0.55 * i / 63, 0.0, 0.3 * i / 63, 0.0});
    Ensemble e = model->ensemble(line.size(), std::vector<std::string>{std::string(TuneColumns::key)});
    const auto tunes = tunes_of(*model, e, line, window);
    double worst = -100;
    int resolved = 0;
    for (std::size_t i = 0; i < e.orbits; ++i) {
      const double nu = tunes[TuneColumns::nu1][i];
      const bool on_plane = std::isnan(tunes[TuneColumns::nu2][i]);  // q2 stayed 0 at every step
      if (e.escape_step[i] >= 0 || !on_plane || !(nu > 16.0 / window && nu < 0.5 - 16.0 / window))
        continue;
      ++resolved;
      worst = std::max(worst, tunes[TuneColumns::diffusion][i]);
    }
    std::cout << m.name << ": " << resolved << " of 64 orbits on q2 = p2 = 0 resolved at N = "
              << window << " (on the plane, line resolved), largest diffusion "
              << (resolved ? worst : std::nan("")) << '\n';
    EXPECT_LT(worst, integrable_diffusion_below);
  }
}

// Suris' map in both degrees of freedom, where its two tunes differ (A ≠ B): with a step of 0.5
// (tunes about 0.1) every orbit of the box is on a torus.
TEST(Tunes, SurisOrbitsInBothDegreesOfFreedomHaveTheDiffusionOfTori) {
  const auto model = make_model("suris", {{"A", 0.7}, {"B", 0.3}, {"alpha", 0.9}, {"h", 0.5}});
  Ensemble e = model->ensemble(200, std::vector<std::string>{std::string(TuneColumns::key)});
  const auto tunes = tunes_of(*model, e, testing::box_points(200, 0.5, 0.5), 4096);
  double worst = -100;
  for (std::size_t i = 0; i < e.orbits; ++i) {
    ASSERT_LT(e.escape_step[i], 0) << "orbit " << i;
    worst = std::max(worst, tunes[TuneColumns::diffusion][i]);
  }
  std::cout << "suris, h = 0.5: largest diffusion of 200 orbits at N = 4096: " << worst << '\n';
  EXPECT_LT(worst, integrable_diffusion_below);
}

}  // namespace
}  // namespace qmaps
