// Bit-level agreement: every SIMD ISA compiled and supported here, 1 and 2 threads, every block
// size (chains), and runs cut into segments (resume) reproduce the scalar reference path byte for
// byte: final states (with their chaos records where a run keeps one), escape steps and reasons,
// invariant drift, and the tunes (over two windows of 128 steps, through escapes within them).
// Every map of the list, and the maps written as formulas of the presets.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cinttypes>
#include <cstdio>
#include <cstring>
#include <set>
#include <sstream>
#include <utility>

#include "core/isa.hpp"
#include "core/observers/lane_observers.hpp"
#include "core/observers/tunes/tunes.hpp"
#include "ensemble_fixtures.hpp"
#include "ensembles/config/config.hpp"
#include "ensembles/config/map_config.hpp"
#include "isas_run.hpp"

namespace qmaps {
namespace {

struct Scenario {
  std::string name;
  std::string map;
  ParamValues params;
  double q, p, escape_bound;
  bool escapes = false;   // the scenario must exercise escapes (and keep some orbits)
  long long steps = 400;
  bool on_plane = false;  // state (q2_n, q2_n+1) = (+0, −0)
  std::size_t deviations = 0;  // with a chaos record of 1 or 9 deviations (core/tangent_map.hpp)
  long long tune_window = 0;   // with the tunes over two windows of this many steps
  std::shared_ptr<const formula::Definition> formulas = {};  // a map written as formulas
};

// The formulas of preset `name` (ensembles/presets/<name>.toml).
std::shared_ptr<const formula::Definition> formulas_of(const std::string& name) {
  return definition_of(Config::load(QMAPS_SOURCE_DIR "/ensembles/presets/" + name + ".toml"));
}

// Three per map of kernels/maps.hpp, from its example: bounded orbits; orbits escaping over the
// barrier of an attractive quartic (α < 0); orbits in the invariant plane q2 = p2 = 0, with the
// one pair of zeros whose step −0·x + −(+0) tells an exact negation from 0 − x (zeros merge after
// one step). Then the regimes a map's example does not reach.
std::vector<Scenario> scenarios() {
  std::vector<Scenario> out;
  for (const MapEntry& m : catalogue()) {
    const std::string id = testing::test_id(m.name);
    const ParamValues example = param_values(m.facts->example);
    out.push_back({id, std::string(m.name), example, 0.5, 0.5, 1e8});
    out.push_back({id + "_escaping", std::string(m.name), param_values(m.facts->escaping), 1.2,
                   1.0, 10, true});
    out.push_back({id + "_plane", std::string(m.name), example, 0.5, 0.5, 1e8, false, 1, true});
    // The chaos records: their deviations, sums and orthonormalizations (every 3 steps), also
    // through escapes.
    out.push_back({id + "_lyapunov", std::string(m.name), example, 0.5, 0.5, 1e8, false, 400,
                   false, 1});
    out.push_back({id + "_spectrum", std::string(m.name), example, 0.5, 0.5, 1e8, false, 400,
                   false, 9});
    out.push_back({id + "_escaping_spectrum", std::string(m.name),
                   param_values(m.facts->escaping), 1.2, 1.0, 10, true, 400, false, 9});
    // The tunes: recorded in chunks and step by step, analysed at the windows' ends, with the
    // chaos record, and through escapes inside the windows.
    out.push_back({id + "_tunes", std::string(m.name), example, 0.5, 0.5, 1e8, false, 400, false,
                   0, 128});
    out.push_back({id + "_escaping_tunes", std::string(m.name), param_values(m.facts->escaping),
                   1.2, 1.0, 10, true, 400, false, 1, 128});
  }
  // The formula maps of the presets: two-step (Suris as formulas, and kicked, also escaping over
  // the barrier of α < 0) and phase maps with transcendentals and one degree of freedom.
  const ParamValues attractive = {{"alpha", -0.4}};
  for (const char* name : {"suris-formulas", "suris-kicked", "froeschle", "mcmillan", "henon-heiles"}) {
    const auto formulas = formulas_of(name);
    const std::string id = testing::test_id(name);
    const bool two_step = formulas->form() == formula::Form::two_step;
    out.push_back({id, name, {}, 0.3, 0.3, 1e8, false, 400, false, 0, 0, formulas});
    out.push_back({id + "_lyapunov", name, {}, 0.3, 0.3, 1e8, false, 400, false, 1, 0, formulas});
    out.push_back({id + "_spectrum", name, {}, 0.3, 0.3, 1e8, false, 400, false, 9, 0, formulas});
    out.push_back({id + "_tunes", name, {}, 0.3, 0.3, 1e8, false, 400, false, 0, 128, formulas});
    if (two_step)
      out.push_back({id + "_escaping_spectrum", name, attractive, 1.2, 1.0, 10, true, 400, false,
                     9, 0, formulas});
  }
  out.push_back({"suris_A_eq_B", "suris", {{"A", 0.5}, {"B", 0.5}, {"alpha", 0.9}, {"h", 0.1}}, 0.5, 0.5, 1e8});
  out.push_back({"case2_hky_c", "case2-hky", {{"A", 0.7}, {"alpha", 0.9}, {"h", 0.1}, {"c11", 0.37}, {"c12", 0.41}, {"c21", 0.77}, {"c22", 0.19}}, 0.5, 0.5, 1e8});
  out.push_back({"case3_left", "case3", {{"A", 0.7}, {"alpha", 0.9}, {"ds", 0.1}, {"t_order", 1}}, 0.5, 0.5, 1e8});
  out.push_back({"flow_case4", "flow", {{"A", 0.7}, {"B", 2.8}, {"alpha", 0.9}, {"beta", 7.2}, {"delta", 5.4}, {"h", 0.05}}, 0.5, 0.5, 1e8});
  return out;
}

// Suris runs every ensemble size of the backbone's contract; every other map the three smaller.
std::vector<std::tuple<Scenario, std::size_t>> cases() {
  std::vector<std::tuple<Scenario, std::size_t>> out;
  for (const auto& s : scenarios())
    for (std::size_t n : {1, 7, 1001, 65537})
      if ((n < 65537 || s.map == "suris") &&
          ((s.deviations == 0 && s.tune_window == 0) || (n > 1 && n < 65537)))
        out.emplace_back(s, n);
  return out;
}

void PrintTo(const Scenario& s, std::ostream* os) { *os << s.name; }

Ensemble start(const Model& model, const Scenario& s, std::size_t orbits, double bound) {
  std::vector<std::string> measured;
  if (s.tune_window > 0) measured.emplace_back(TuneColumns::key);
  Ensemble e = model.ensemble(orbits, measured);
  model.start_at(e, 0, testing::box_points(orbits, s.q, s.p), Start::taylor, bound);
  e.fill_padding();
  if (s.on_plane) {
    for (std::size_t i = 0; i < e.padded; ++i) {
      e.state[1][i] = 0.0;
      e.state[3][i] = -0.0;
    }
  }
  return e;
}

std::string hex(double x) {
  std::uint64_t bits;
  std::memcpy(&bits, &x, sizeof bits);
  char text[64];
  std::snprintf(text, sizeof text, "%a (0x%016" PRIx64 ")", x, bits);
  return text;
}

// Empty when a and b agree byte for byte on the real orbits; else the first difference.
std::string first_difference(const Ensemble& ref, const Ensemble& e, std::size_t lanes) {
  std::ostringstream out;
  const auto where = [&](const char* what, std::size_t k, std::size_t i) {
    out << what << '[' << k << "] orbit " << i << " lane " << i % lanes << ": ";
  };
  for (std::size_t i = 0; i < ref.orbits; ++i) {
    for (std::size_t k = 0; k < ref.state.size(); ++k)
      if (std::memcmp(&ref.state[k][i], &e.state[k][i], sizeof(double)) != 0) {
        where("state", k, i);
        out << "reference " << hex(ref.state[k][i]) << " vs " << hex(e.state[k][i]);
        return out.str();
      }
    for (std::size_t k = 0; k < ref.columns.size(); ++k)
      if (std::memcmp(&ref.columns[k][i], &e.columns[k][i], sizeof(double)) != 0) {
        where(ref.column_specs[k].path.c_str(), k, i);
        out << "reference " << hex(ref.columns[k][i]) << " vs " << hex(e.columns[k][i]);
        return out.str();
      }
    if (ref.escape_step[i] != e.escape_step[i] || ref.escape_reason[i] != e.escape_reason[i]) {
      where("escape", 0, i);
      out << "reference step " << ref.escape_step[i] << " reason " << int(ref.escape_reason[i])
          << " vs step " << e.escape_step[i] << " reason " << int(e.escape_reason[i]);
      return out.str();
    }
  }
  return {};
}

class Agreement : public ::testing::TestWithParam<std::tuple<Scenario, std::size_t>> {
 protected:
  const Scenario scenario = std::get<0>(GetParam());
  const std::size_t orbits = std::get<1>(GetParam());
  const std::unique_ptr<Model> model = [this] {
    const ChaosOptions chaos{scenario.deviations == 9, 3};
    if (scenario.formulas)
      return scenario.deviations == 0 ? make_model(scenario.formulas, scenario.params)
                                      : make_model(scenario.formulas, scenario.params, chaos);
    return scenario.deviations == 0 ? make_model(scenario.map, scenario.params)
                                    : make_model(scenario.map, scenario.params, chaos);
  }();
  const RunPlan plan = [this] {
    RunPlan p;
    p.total = p.last = scenario.steps;
    p.stride = 7;
    p.escape_bound = scenario.escape_bound;
    p.tunes.window = scenario.tune_window;
    return p;
  }();

  Ensemble fresh() const { return start(*model, scenario, orbits, plan.escape_bound); }
  Ensemble reference() const {
    Ensemble e = fresh();
    model->advance(e, plan, Execution{Isa::scalar, 1, 1});
    return e;
  }
};

TEST_P(Agreement, EveryIsaThreadCountAndBlockSizeIsBitIdenticalToScalarReference) {
  const Ensemble ref = reference();
  if (scenario.escapes && orbits > 100) {
    const std::size_t escaped = ref.escaped();
    EXPECT_GT(escaped, orbits / 10) << "the escaping scenario must exercise escapes";
    EXPECT_LT(escaped, orbits) << "and keep some orbits bounded";
  }
  if (scenario.tune_window > 0 && (!scenario.escapes || orbits > 100)) {
    // tunes to compare: of the bounded orbits, in (0, 1/2)
    const auto tunes = ref.columns_of(lane_index<Tunes>);
    ASSERT_EQ(tunes.size(), std::size_t{TuneColumns::count});
    std::size_t with_tunes = 0;
    for (std::size_t i = 0; i < ref.orbits; ++i)
      with_tunes += tunes[TuneColumns::nu1][i] > 0 && tunes[TuneColumns::nu1][i] < 0.5;
    EXPECT_GT(with_tunes, scenario.escapes ? 0 : ref.orbits - ref.escaped() - 1);
  }

  const auto isas = testing::isas_to_run();
  ASSERT_FALSE(isas.empty());
  for (Isa isa : isas) {
    // Each block size on one thread, and the orbits split between two threads in blocks of either
    // size. A map runs only the chains compiled for it (ChainRange: 4 and 8, 1 with deviations, 8
    // for formulas), so the pairs that come to the same block are run once.
    std::set<std::pair<int, std::size_t>> ran;
    for (const auto& [threads, chains] :
         std::array<std::pair<int, int>, 5>{{{1, 1}, {1, 4}, {1, 8}, {2, 4}, {2, 8}}}) {
      if (!ran.emplace(threads, model->block_orbits(Execution{isa, threads, chains})).second)
        continue;
      Ensemble e = fresh();
      model->advance(e, plan, Execution{isa, threads, chains});
      EXPECT_EQ(first_difference(ref, e, isa_lanes(isa)), "")
          << "ISA " << isa_name(isa) << ", " << threads << " threads, " << chains << " chains";
    }
  }
}

TEST_P(Agreement, RunCutIntoSegmentsOnOtherPathsIsBitIdenticalToUninterruptedRun) {
  const Ensemble whole = reference();

  const auto isas = testing::isas_to_run();
  Ensemble cut = fresh();
  const long long n = scenario.steps;
  std::set<long long> cuts = {0, std::min(1LL, n), n / 3, n / 3 + 1, n * 5 / 6, n};
  if (plan.tunes.window > 0) {  // never inside the tunes' windows: at their end instead
    std::erase_if(cuts, [&](long long c) { return plan.tunes.inside(c); });
    cuts.insert(plan.tunes.end());
  }
  const std::vector<long long> bounds(cuts.begin(), cuts.end());
  for (std::size_t s = 0; s + 1 < bounds.size(); ++s) {
    RunPlan segment = plan;
    segment.first = bounds[s];
    segment.last = std::min(n, bounds[s + 1]);
    const Isa isa = s % 2 == 0 || isas.empty() ? Isa::scalar : isas[s % isas.size()];
    model->advance(cut, segment, Execution{isa, 1 + static_cast<int>(s % 2), 4});
  }
  EXPECT_EQ(first_difference(whole, cut, 1), "");
}

INSTANTIATE_TEST_SUITE_P(
    Maps, Agreement,
    ::testing::ValuesIn(cases()),
    [](const auto& info) {
      return std::string(std::get<0>(info.param).name) + "_" +
             std::to_string(std::get<1>(info.param));
    });

}  // namespace
}  // namespace qmaps
