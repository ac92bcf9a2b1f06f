// Convergence of every map to the continuous flow it discretizes, at t = 1, against `flow`
// (order 8 at a step of 1/1024): the measured order log2(e(h)/e(h/2)) is 2 ± 0.1 with the taylor
// start, 1 ± 0.1 with the euler start; case3 in q at its own physical time t_N: 2 ± 0.1 with the
// trapezoid rule, 1 ± 0.1 with the left-point rule. Tolerance checks against a reference.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "ensemble_fixtures.hpp"

namespace qmaps {
namespace {

const Phase start_point{0.3, -0.2, 0.1, 0.4};

// The continuous flow's phase point at time T, by `flow` at order 8 with about 1024 steps per unit.
Phase exact(const ParamValues& flow_params, double T) {
  const long long steps = std::max(1LL, std::llround(T * 1024));
  ParamValues p = flow_params;
  p["h"] = T / static_cast<double>(steps);
  const auto flow = make_model("flow", p);
  Ensemble e = flow->start(std::span(&start_point, 1), Start::taylor, 1e8);
  RunPlan plan;
  plan.total = plan.last = steps;
  plan.track_invariants = false;
  flow->advance(e, plan, Execution{});
  return flow->phase(e, 0);
}

struct Result {
  double error, time;
};

// The map's configuration error at node N = 1/step against the flow at the node's time.
Result error_at_one(const std::string& map, ParamValues params, const char* step_name,
                    double step, Start rule, const ParamValues& flow_params) {
  params[step_name] = step;
  const auto model = make_model(map, params);
  Ensemble e = model->start(std::span(&start_point, 1), rule, 1e8);
  RunPlan plan;
  plan.total = plan.last = std::llround(1 / step);
  plan.track_invariants = false;
  model->advance(e, plan, Execution{});
  const double T = model->time(e, 0);
  const Phase x = model->phase(e, 0), ref = exact(flow_params, T);
  return {std::hypot(x.q1 - ref.q1, x.q2 - ref.q2), T};
}

double measured_order(const std::string& map, const ParamValues& params, const char* step_name,
                      Start rule, const ParamValues& flow_params) {
  const Result coarse = error_at_one(map, params, step_name, 0.1 / 8, rule, flow_params);
  const Result fine = error_at_one(map, params, step_name, 0.1 / 16, rule, flow_params);
  const double order = std::log2(coarse.error / fine.error);
  std::printf("[ order ] %-16s %-6s %s: e(%.4f) = %.3e, e(%.5f) = %.3e, order %.3f\n", map.c_str(),
              std::string(start_name(rule)).c_str(), step_name, 0.1 / 8, coarse.error, 0.1 / 16,
              fine.error, order);
  return order;
}

const ParamValues case1_flow{{"A", 0.7}, {"B", 0.3}, {"alpha", 0.9}, {"beta", 0.9}, {"delta", 1.8}};
const ParamValues case2_flow{{"A", 0.7}, {"B", 0.7}, {"alpha", 0.9}, {"beta", 0.9}, {"delta", 5.4}};
const ParamValues case3_flow{{"A", 0.7}, {"B", 2.8}, {"alpha", 0.9}, {"beta", 14.4}, {"delta", 10.8}};

TEST(Convergence, SurisIsSecondOrderWithTaylorStartAndFirstWithEulerWithinTolerance) {
  const ParamValues p{{"A", 0.7}, {"B", 0.3}, {"alpha", 0.9}};
  EXPECT_NEAR(measured_order("suris", p, "h", Start::taylor, case1_flow), 2.0, 0.1);
  EXPECT_NEAR(measured_order("suris", p, "h", Start::euler, case1_flow), 1.0, 0.1);
}

TEST(Convergence, CaseTwoMapsAreSecondOrderWithinTolerance) {
  const ParamValues p{{"A", 0.7}, {"alpha", 0.9}};
  EXPECT_NEAR(measured_order("case2", p, "h", Start::taylor, case2_flow), 2.0, 0.1);
  EXPECT_NEAR(measured_order("case2-staggered", p, "h", Start::taylor, case2_flow), 2.0, 0.1);
  ParamValues hky = p;
  hky["gamma11"] = 0.6;
  hky["gamma21"] = 0.3;
  EXPECT_NEAR(measured_order("case2-hky", hky, "h", Start::taylor, case2_flow), 2.0, 0.1);
}

TEST(Convergence, CaseThreeIsSecondOrderInTimeWithTrapezoidAndFirstWithLeftRuleWithinTolerance) {
  const ParamValues p{{"A", 0.7}, {"alpha", 0.9}};
  EXPECT_NEAR(measured_order("case3", p, "ds", Start::taylor, case3_flow), 2.0, 0.1);
  ParamValues left = p;
  left["t_order"] = 1;
  EXPECT_NEAR(measured_order("case3", left, "ds", Start::taylor, case3_flow), 1.0, 0.1);
}

TEST(Convergence, LeapfrogIsSecondOrderWithinTolerance) {
  ParamValues p = case1_flow;
  EXPECT_NEAR(measured_order("leapfrog", p, "h", Start::taylor, case1_flow), 2.0, 0.1);
}

}  // namespace
}  // namespace qmaps
