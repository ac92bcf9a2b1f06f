// Reversibility of every map through the engine: N steps forward, reverse every orbit's state,
// N steps back, reverse again: the orbits return to their start within a stated tolerance (the
// round-off accumulated over 2N steps). case3 retraces its u; its time t keeps advancing.
#include <gtest/gtest.h>

#include <cmath>

#include "core/isa.hpp"
#include "ensemble_fixtures.hpp"

namespace qmaps {
namespace {

struct Reversal {
  const char* name;
  const char* map;
  ParamValues params;
  std::size_t compared;  // leading state components that must return
  double tolerance;
};

const Reversal maps[] = {
    {"suris", "suris", {{"A", 0.7}, {"B", 0.3}, {"alpha", 0.9}, {"h", 0.1}}, 4, 1e-11},
    {"case2", "case2", {{"A", 0.7}, {"alpha", 0.9}, {"h", 0.1}}, 4, 1e-11},
    {"case2_staggered", "case2-staggered", {{"A", 0.7}, {"alpha", 0.9}, {"h", 0.1}}, 4, 1e-11},
    {"case2_hky", "case2-hky", {{"A", 0.7}, {"alpha", 0.9}, {"h", 0.1}, {"gamma11", 0.6}, {"gamma21", 0.3}}, 4, 1e-11},
    {"case3", "case3", {{"A", 0.7}, {"alpha", 0.9}, {"ds", 0.1}}, 4, 1e-10},  // measured 1.9e-11
    {"flow", "flow", {{"A", 0.7}, {"B", 2.8}, {"alpha", 0.9}, {"beta", 7.2}, {"delta", 5.4}, {"h", 0.05}}, 4, 1e-11},
    {"leapfrog", "leapfrog", {{"A", 0.7}, {"B", 0.3}, {"alpha", 0.9}, {"beta", 0.9}, {"delta", 1.8}, {"h", 0.05}}, 4, 1e-11},
};

void PrintTo(const Reversal& r, std::ostream* os) { *os << r.name; }

class Reversibility : public ::testing::TestWithParam<Reversal> {};

TEST_P(Reversibility, ForwardThenBackwardReturnsToStartWithinTolerance) {
  const Reversal& r = GetParam();
  const auto model = make_model(r.map, r.params);
  const Ensemble start = model->start(testing::box_points(64, 0.5, 0.5, 11), Start::taylor, 1e8);
  Ensemble e = model->start(testing::box_points(64, 0.5, 0.5, 11), Start::taylor, 1e8);
  RunPlan plan;
  plan.total = plan.last = 1000;
  plan.track_invariants = false;
  model->advance(e, plan, Execution{best_isa(), 1, 4});
  model->reverse(e);
  model->advance(e, plan, Execution{best_isa(), 1, 4});
  model->reverse(e);
  double worst = 0;
  for (std::size_t k = 0; k < r.compared; ++k)
    for (std::size_t i = 0; i < e.orbits; ++i)
      worst = std::max(worst, std::fabs(e.state[k][i] - start.state[k][i]));
  std::printf("[ reversal ] %-16s 1000 + 1000 steps: max |error| %.2e\n", r.name, worst);
  EXPECT_LT(worst, r.tolerance);
}

INSTANTIATE_TEST_SUITE_P(Maps, Reversibility, ::testing::ValuesIn(maps),
                         [](const auto& info) { return std::string(info.param.name); });

}  // namespace
}  // namespace qmaps
