// Convergence of every map of kernels/maps.hpp to the continuous flow it discretizes, at t = 1, against `flow`
// (order 8 at a step of 1/1024): the measured order log2(e(h)/e(h/2)) is 2 ± 0.1 with the taylor
// start, 1 ± 0.1 with the euler start; case3 in q at its own physical time t_N: 2 ± 0.1 with the
// trapezoid rule, 1 ± 0.1 with the left-point rule. Tolerance checks against a reference.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "ensemble_fixtures.hpp"

namespace qmaps {
namespace {

const Phase start_point{0.3, -0.2, 0.1, 0.4};

// The continuous flow's phase point at time T, by `flow` at order 8 with about 1024 steps per unit.
Phase exact(const ParamValues& flow_params, double T) {
  const long long steps = std::max(1LL, std::llround(T * 1024));
  ParamValues p = flow_params;
  p["h"] = T / static_cast<double>(steps);
  p["order"] = 8;
  const auto flow = make_model("flow", p);
  Ensemble e = flow->start(std::span(&start_point, 1), Start::taylor, 1e8);
  RunPlan plan;
  plan.total = plan.last = steps;
  plan.measure_orbits = false;
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
  plan.measure_orbits = false;
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

// The flow's parameters for the continuous system `model` discretizes.
ParamValues flow_of(const Model& model) {
  const Potential v = model.continuous().value();
  return {{"A", v.A}, {"B", v.B}, {"alpha", v.alpha}, {"beta", v.beta}, {"delta", v.delta}};
}

// Every map of kernels/maps.hpp that discretizes the flow (order > 0), at its example's
// parameters, converges at its stated order with the taylor start.
std::vector<std::string> discretizations() {
  std::vector<std::string> out;
  for (const MapEntry& m : catalogue())
    if (m.facts->order > 0) out.emplace_back(m.name);
  return out;
}

class Convergence : public ::testing::TestWithParam<std::string> {};

TEST_P(Convergence, ConvergesToTheFlowAtItsStatedOrderWithTaylorStartWithinTolerance) {
  const MapEntry& m = *std::find_if(catalogue().begin(), catalogue().end(),
                                    [&](const MapEntry& e) { return e.name == GetParam(); });
  const ParamValues example = param_values(m.facts->example);
  const auto flow = flow_of(*make_model(m.name, example));
  ParamValues p = example;
  p.erase(std::string(m.facts->step));
  EXPECT_NEAR(measured_order(GetParam(), p, std::string(m.facts->step).c_str(), Start::taylor,
                             flow),
              m.facts->order, 0.1);
}

INSTANTIATE_TEST_SUITE_P(Maps, Convergence, ::testing::ValuesIn(discretizations()),
                         [](const auto& info) { return testing::test_id(info.param); });

TEST(ConvergenceOfStarts, SurisIsFirstOrderWithEulerStartWithinTolerance) {
  const ParamValues p{{"A", 0.7}, {"B", 0.3}, {"alpha", 0.9}};
  EXPECT_NEAR(measured_order("suris", p, "h", Start::euler, flow_of(*testing::suris())), 1.0,
              0.1);
}

TEST(ConvergenceOfStarts, CaseThreeIsFirstOrderInTimeWithLeftRuleWithinTolerance) {
  const ParamValues p{{"A", 0.7}, {"alpha", 0.9}, {"t_order", 1}};
  const auto flow = flow_of(*make_model("case3", {{"A", 0.7}, {"alpha", 0.9}, {"ds", 0.1}}));
  EXPECT_NEAR(measured_order("case3", p, "ds", Start::taylor, flow), 1.0, 0.1);
}

}  // namespace
}  // namespace qmaps
