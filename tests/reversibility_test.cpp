// Reversibility of every map through the engine: N steps forward, reverse every orbit's state,
// N steps back, reverse again: the orbits return to their start within a stated tolerance (the
// round-off accumulated over 2N steps). case3 retraces its u; its time t keeps advancing.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/isa.hpp"
#include "ensemble_fixtures.hpp"

namespace qmaps {
namespace {

struct Reversal {
  std::string name;
  std::string map;
  ParamValues params;
  std::size_t compared;  // leading state components that must return
  double tolerance;
};

// Every map of kernels/maps.hpp at its example, with its stated tolerance.
std::vector<Reversal> reversals() {
  std::vector<Reversal> out;
  for (const MapEntry& m : catalogue()) {
    const std::string id = testing::test_id(m.name);
    out.push_back({id, std::string(m.name), param_values(m.facts->example), 4,
                   m.facts->reversal_tolerance});
  }
  return out;
}

void PrintTo(const Reversal& r, std::ostream* os) { *os << r.name; }

class Reversibility : public ::testing::TestWithParam<Reversal> {};

TEST_P(Reversibility, ForwardThenBackwardReturnsToStartWithinTolerance) {
  const Reversal& r = GetParam();
  const auto model = make_model(r.map, r.params);
  const Ensemble start = model->start(testing::box_points(64, 0.5, 0.5, 11), Start::taylor, 1e8);
  Ensemble e = model->start(testing::box_points(64, 0.5, 0.5, 11), Start::taylor, 1e8);
  RunPlan plan;
  plan.total = plan.last = 1000;
  plan.measure_orbits = false;
  model->advance(e, plan, Execution{best_isa(), 1, 4});
  model->reverse(e);
  model->advance(e, plan, Execution{best_isa(), 1, 4});
  model->reverse(e);
  double worst = 0;
  for (std::size_t k = 0; k < r.compared; ++k)
    for (std::size_t i = 0; i < e.orbits; ++i)
      worst = std::max(worst, std::fabs(e.state[k][i] - start.state[k][i]));
  std::printf("[ reversal ] %-16s 1000 + 1000 steps: max |error| %.2e (bound %.0e)\n",
              r.name.c_str(), worst, r.tolerance);
  EXPECT_LT(worst, r.tolerance);
}

INSTANTIATE_TEST_SUITE_P(Maps, Reversibility, ::testing::ValuesIn(reversals()),
                         [](const auto& info) { return std::string(info.param.name); });

}  // namespace
}  // namespace qmaps
