// Invariant conservation of every map of kernels/maps.hpp over 10⁵ steps through the SIMD runner (invariants sampled
// every step), from random bounded orbits. Two measures per invariant, printed by the test:
// per orbit relative, max_n |I_n − I_0| / |I_0|; and relative to the ensemble's scale,
// |I_n − I_0| / mean |I_0| (robust where an orbit's I_0 is near 0). Bounds are about ten times
// the largest value measured here.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <utility>
#include <string>
#include <vector>

#include "core/observers/invariants/invariant_columns.hpp"
#include "core/isa.hpp"
#include "ensemble_fixtures.hpp"
#include "kernels/suris.hpp"

namespace qmaps {
namespace {

struct Conservation {
  std::string name;
  std::string map;
  ParamValues params;
  std::size_t orbits;
  double bound;  // max |I_n − I_0| / mean |I_0|, every invariant
};

// Every map of kernels/maps.hpp at its example, with its stated tolerance (the flows' H and
// second integral are conserved to their order, not exactly: their bound says how far), and the
// suris regime its example does not reach.
std::vector<Conservation> conservations() {
  std::vector<Conservation> out;
  for (const MapEntry& m : catalogue()) {
    const std::string id = testing::test_id(m.name);
    out.push_back({id, std::string(m.name), param_values(m.facts->example),
                   m.facts->slow ? 200u : 500u, m.facts->drift_tolerance});
  }
  out.push_back({"suris_A_eq_B", "suris", {{"A", 0.5}, {"B", 0.5}, {"alpha", 0.9}, {"h", 0.1}},
                 500, kernels::Suris::facts.drift_tolerance});
  return out;
}

void PrintTo(const Conservation& c, std::ostream* os) { *os << c.name; }

class Invariants : public ::testing::TestWithParam<Conservation> {};

TEST_P(Invariants, DriftOverHundredThousandStepsStaysWithinTheMapsBound) {
  const Conservation& m = GetParam();
  const auto model = make_model(m.map, m.params);
  RunPlan plan;
  plan.total = plan.last = 100000;
  Ensemble e = model->start(testing::box_points(m.orbits, 0.5, 0.5, 2024), Start::taylor, 1e8);
  model->advance(e, plan, Execution{best_isa(), 2, 4});
  ASSERT_EQ(e.escaped(), 0u);
  const auto& names = model->invariant_names();
  ASSERT_FALSE(names.empty());
  for (std::size_t k = 0; k < names.size(); ++k) {
    double scale = 0;
    for (std::size_t i = 0; i < e.orbits; ++i) scale += std::fabs(invariant_initial(e, k)[i]);
    scale /= static_cast<double>(e.orbits);
    std::vector<double> per_orbit(e.orbits), to_scale(e.orbits);
    for (std::size_t i = 0; i < e.orbits; ++i) {
      per_orbit[i] = invariant_drift(e, k)[i] / std::fabs(invariant_initial(e, k)[i]);
      to_scale[i] = invariant_drift(e, k)[i] / scale;
    }
    std::sort(per_orbit.begin(), per_orbit.end());
    std::sort(to_scale.begin(), to_scale.end());
    const std::size_t n = e.orbits;
    std::printf("[ drift ] %-16s %-3s per orbit: median %.1e p99 %.1e max %.1e | to scale: median "
                "%.1e max %.1e (bound %.1e)\n",
                m.name.c_str(), names[k].c_str(), per_orbit[n / 2], per_orbit[n * 99 / 100],
                per_orbit.back(), to_scale[n / 2], to_scale.back(), m.bound);
    EXPECT_LT(to_scale.back(), m.bound) << names[k];
    EXPECT_GT(to_scale.back(), 0.0) << names[k] << ": zero drift means nothing was tracked";
  }
}

// The invariants of orbit ranges, as the file's /invariants/*/final columns are computed: on
// every path (lanes at a time, from an orbit within a block, up to a range's last orbit), the
// bytes of the reference's one orbit at a time. Some orbits escaped, so frozen states count too.
TEST_P(Invariants, OrbitRangesOnEveryPathEqualTheReferenceByteForByte) {
  const Conservation& m = GetParam();
  const auto model = make_model(m.map, m.params);
  RunPlan plan;
  plan.total = plan.last = 20;
  plan.escape_bound = 0.9;
  Ensemble e = model->start(testing::box_points(37, 0.7, 0.7, 11), Start::taylor, 1e8);
  model->advance(e, plan, Execution{Isa::scalar, 1, 1});
  std::vector<Isa> paths = runnable_isas();
  paths.push_back(Isa::scalar);
  const std::size_t count = model->invariant_names().size();
  for (Isa isa : paths) {
    for (const auto& [first, n] : {std::pair<std::size_t, std::size_t>{0, 37}, {3, 29}, {36, 1}}) {
      std::vector<std::vector<double>> columns(count, std::vector<double>(n));
      std::vector<double*> out;
      for (auto& c : columns) out.push_back(c.data());
      model->invariants_of_orbits(e, first, n, isa, out);
      for (std::size_t i = 0; i < n; ++i) {
        const auto reference = model->invariants(e, first + i);
        for (std::size_t k = 0; k < count; ++k)
          EXPECT_EQ(std::memcmp(&columns[k][i], &reference[k], sizeof(double)), 0)
              << isa_name(isa) << " orbit " << first + i << " invariant " << k << ": "
              << columns[k][i] << " against " << reference[k];
      }
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Maps, Invariants, ::testing::ValuesIn(conservations()),
                         [](const auto& info) { return std::string(info.param.name); });

TEST(Invariants, SurisSumOfI1AndI2EqualsTwoHSquaredTimesHWithinTolerance) {
  const auto model = testing::suris();
  const auto points = testing::box_points(200, 0.5, 0.5, 5);
  RunPlan plan;
  plan.total = plan.last = 1000;
  Ensemble e = model->start(points, Start::taylor, plan.escape_bound);
  model->advance(e, plan, Execution{});
  const double h = 0.1;
  for (std::size_t i = 0; i < e.orbits; ++i) {
    const auto v = model->invariants(e, i);  // H, I1, I2
    EXPECT_NEAR(v[1] + v[2], 2 * h * h * v[0], 1e-16 + 4e-15 * std::fabs(v[0]) * h * h) << i;
  }
}

}  // namespace
}  // namespace qmaps
