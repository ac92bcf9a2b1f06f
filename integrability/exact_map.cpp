#include "integrability/exact_map.hpp"

#include <algorithm>
#include <random>
#include <string_view>

#include "core/error.hpp"
#include "kernels/maps.hpp"  // after field.hpp: the kernels see the exact types' fma and fms

namespace qmaps::exact {
namespace {

using formula::Code;
using formula::Formulas;
using formula::Lowering;
using formula::Program;

// ---- a built-in map: its kernel over V ------------------------------------------------------

template <class Map, class V>
void fill_one(ExactMap& m, const std::shared_ptr<const typename Map::Coeffs>& c) {
  std::get<ExactMap::Step<V>>(m.steps_) = [c](State<V>& s) { Map::step(*c, s); };
  std::get<ExactMap::Invariants<V>>(m.invariants_) = [c](const State<V>& s, V* out) {
    Map::invariants(*c, s, out);
  };
}

template <class Map>
ExactMap built_in(const ParamValues& given) {
  ExactMap m;
  m.name = std::string(Map::name);
  m.evaluated_by = "its kernel, the template over the value type that every path runs";
  const auto values = resolve_params(Map::name, Map::params, given);
  const auto c = std::make_shared<const typename Map::Coeffs>(Map::coefficients(values));
  for (std::size_t k = 0; k < 4; ++k) m.state_names[k] = std::string(Map::state_names[k]);
  m.invariant_names = Map::invariant_names(*c);
  fill_one<Map, Residue>(m, c);
  fill_one<Map, FunctionOfT>(m, c);
  fill_one<Map, Rational>(m, c);
  fill_one<Map, Lanes>(m, c);
  return m;
}

// ---- a formula map: its formulas lowered with the parameters as inputs ------------------------

template <class V>
void run(const Program& p, const V* state, std::size_t n, const std::vector<double>& parameters,
         std::vector<V>& r) {
  if (r.size() < p.registers()) r.resize(p.registers());
  std::copy_n(state, n, r.begin());
  for (std::size_t k = 0; k < parameters.size(); ++k) r[n + k] = V(parameters[k]);
  for (std::size_t k = 0; k < p.constants.size(); ++k) r[p.inputs + k] = V(p.constants[k]);
  for (const formula::Instruction& i : p.code) {
    V& out = r[i.out];
    switch (i.code) {
      case Code::add: out = r[i.a] + r[i.b]; break;
      case Code::sub: out = r[i.a] - r[i.b]; break;
      case Code::mul: out = r[i.a] * r[i.b]; break;
      case Code::div: out = r[i.a] / r[i.b]; break;
      case Code::neg: out = V(0.0) - r[i.a]; break;
      case Code::fma: out = r[i.a] * r[i.b] + r[i.c]; break;
      case Code::fms: out = r[i.a] * r[i.b] - r[i.c]; break;
      default: throw std::logic_error("a transcendental instruction in an exact program");
    }
  }
}

// The first node of f that is a function other than fma: such a map is not rational.
void refuse_transcendentals(const Formulas& f, const std::string& key) {
  for (const formula::Node& node : f.nodes) {
    std::string_view function;
    switch (node.op) {
      case formula::Op::sqrt: function = "sqrt"; break;
      case formula::Op::sin: function = "sin"; break;
      case formula::Op::cos: function = "cos"; break;
      case formula::Op::exp: function = "exp"; break;
      case formula::Op::log: function = "log"; break;
      default: continue;
    }
    throw formula::DefinitionError(
        key, "line " + std::to_string(node.at.line) + ", column " + std::to_string(node.at.column) +
                 ": " + std::string(function) +
                 " makes the map not a rational function of its state: the integrability tests "
                 "evaluate it exactly (over F_p, F_p(t) and Q) and take only + - * / and integer "
                 "powers");
  }
}

struct FormulaPrograms {
  Program step, invariants;
  std::size_t step_inputs = 4;  // 6 for equations: q_{n+1} are unknowns
  formula::Form form;
  std::vector<double> parameters;
};

std::vector<std::string> with(std::vector<std::string> names, const std::vector<std::string>& more) {
  names.insert(names.end(), more.begin(), more.end());
  return names;
}

FormulaPrograms lower_exactly(const formula::Definition& d, const std::vector<double>& values) {
  const formula::MapText& t = d.text();
  std::vector<std::string> parameters;
  for (const ParamSpec& s : d.params()) parameters.emplace_back(s.name);
  FormulaPrograms out;
  out.form = d.form();
  out.parameters = values;
  const bool solves = !t.equations.empty();
  const std::string key = solves ? "equations" : "step";
  const Formulas step = formula::parse_assignments(solves ? t.equations : t.step);
  refuse_transcendentals(step, key);
  try {
    if (d.form() == formula::Form::phase) {
      Lowering l(step, with({"p1", "p2", "q1", "q2"}, parameters), {});
      l.assign_all();
      std::vector<std::uint16_t> outputs;
      for (const char* name : {"p1", "p2", "q1", "q2"}) outputs.push_back(l.value_of(name, {}));
      out.step = l.finish(outputs);
    } else if (!solves) {
      Lowering l(step, with({"q1_prev", "q2_prev", "q1", "q2"}, parameters), {});
      l.assign_all();
      out.step = l.finish({l.value_of("q1_next", {}), l.value_of("q2_next", {})});
    } else {
      Lowering l(step, with({"q1_prev", "q2_prev", "q1", "q2", "q1_next", "q2_next"}, parameters), {});
      l.assign_all();
      std::uint16_t determinant = 0;
      const auto solution = l.solve_linear({l.value_of("eq1", {}), l.value_of("eq2", {})}, {4, 5},
                                           "q1_next, q2_next", step.assignments.back().at,
                                           determinant);
      out.step = l.finish({solution[0], solution[1]});
      out.step_inputs = 6;
    }
    if (!t.invariants.empty()) {
      const Formulas invariants = formula::parse_assignments(t.invariants);
      refuse_transcendentals(invariants, "invariants");
      const std::vector<std::string> state =
          d.form() == formula::Form::phase ? std::vector<std::string>{"p1", "p2", "q1", "q2"}
                                           : std::vector<std::string>{"q1", "q2", "q1_next", "q2_next"};
      Lowering l(invariants, with(state, parameters), {});
      l.assign_all();
      std::vector<std::uint16_t> outputs;
      for (const auto& name : d.invariant_names()) outputs.push_back(l.value_of(name, {}));
      out.invariants = l.finish(outputs);
    }
  } catch (const formula::FormulaError& e) {
    throw formula::DefinitionError(key, e.what());
  }
  return out;
}

template <class V>
void fill_formula(ExactMap& m, const std::shared_ptr<const FormulaPrograms>& f) {
  std::get<ExactMap::Step<V>>(m.steps_) = [f](State<V>& s) {
    thread_local std::vector<V> r;
    if (f->form == formula::Form::phase) {
      run(f->step, s.data(), 4, f->parameters, r);
      for (std::size_t k = 0; k < 4; ++k) s[k] = r[f->step.outputs[k]];
      return;
    }
    std::array<V, 6> in = {s[0], s[1], s[2], s[3], V(0.0), V(0.0)};
    run(f->step, in.data(), f->step_inputs, f->parameters, r);
    s = {s[2], s[3], r[f->step.outputs[0]], r[f->step.outputs[1]]};
  };
  std::get<ExactMap::Invariants<V>>(m.invariants_) = [f](const State<V>& s, V* out) {
    thread_local std::vector<V> r;
    run(f->invariants, s.data(), 4, f->parameters, r);
    for (std::size_t k = 0; k < f->invariants.outputs.size(); ++k) out[k] = r[f->invariants.outputs[k]];
  };
}

// Which coordinates the step changes, and whether the invariants are exactly invariant: at three
// random points where the step is defined over F_p, p = 2^61 − 1 (a polynomial identity that fails fails at a random point
// with probability at most its degree over p).
void measure(ExactMap& m) {
  PrimeField field((1ULL << 61) - 1);
  std::mt19937_64 random(20261128);
  std::vector<bool> varies(4, false);
  bool exact = !m.invariant_names.empty();
  const std::size_t ni = m.invariant_names.size();
  int defined = 0;
  for (int trial = 0; trial < 64 && defined < 3; ++trial) {
    State<Residue> x;
    for (auto& v : x) v = Residue::of(random() % field.mod().n);
    State<Residue> y = x;
    try {
      m.step(y);
      for (std::size_t k = 0; k < 4; ++k) varies[k] = varies[k] || !(y[k] == x[k]);
      if (ni) {
        std::vector<Residue> before(ni), after(ni);
        m.invariants(x, before.data());
        m.invariants(y, after.data());
        exact = exact && before == after;
      }
      ++defined;
    } catch (const DivisionByZero&) {  // a point where the map is not defined: another one
    }
  }
  if (defined < 3)
    throw usage_error(m.name + ": the step divides by zero at " + std::to_string(64 - defined) +
                      " of 64 random points over F_p, p = 2^61 - 1: it is defined almost nowhere");
  for (std::size_t k = 0; k < 4; ++k)
    if (varies[k]) m.varying.push_back(k);
  m.invariants_exact = exact;
}

}  // namespace

ExactMap exact_map(const std::string& name, const ParamValues& params) {
  std::optional<ExactMap> found;
  kernels::for_each_map([&](auto map) {
    using Map = decltype(map);
    if (Map::name != name) return;
    if constexpr (std::is_same_v<Map, kernels::Case3>)
      throw usage_error("case3: its step solves a quartic equation by Halley's iteration "
                        "(kernels/case3.hpp), so it is not a rational function of the state and "
                        "cannot be evaluated exactly; the integrability tests take rational maps");
    else
      found = built_in<Map>(params);
  });
  if (!found) throw usage_error("'" + name + "' is not a built-in map (qmaps list), nor a .toml file");
  measure(*found);
  return std::move(*found);
}

ExactMap exact_map(const std::shared_ptr<const formula::Definition>& definition,
                   const std::vector<double>& values) {
  const auto f = std::make_shared<const FormulaPrograms>(lower_exactly(*definition, values));
  ExactMap m;
  m.name = definition->text().name;
  m.evaluated_by = "its formulas, with its parameters as exact rationals";
  for (std::size_t k = 0; k < 4; ++k) m.state_names[k] = std::string(definition->state_names()[k]);
  m.invariant_names = definition->invariant_names();
  fill_formula<Residue>(m, f);
  fill_formula<FunctionOfT>(m, f);
  fill_formula<Rational>(m, f);
  fill_formula<Lanes>(m, f);
  measure(m);
  return m;
}

}  // namespace qmaps::exact
