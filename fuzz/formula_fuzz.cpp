// libFuzzer target: a map's formulas as `[map]` gives them. The input is the text of the
// assignments over q1, q2, p1, p2 with parameters a, b and zero = 0. Parsing and lowering must
// either succeed or throw qmaps::formula::FormulaError; a program made must run on any state
// (its values may be anything, never a crash), and each expression printed back must parse to
// the same text. The same text is then a two-step map's step and its equations (linear in
// q_{n+1}, solved): defined, or refused with a DefinitionError, and a map defined steps any
// state, chains stepped together as single steps; and evaluated exactly (integrability/), a few
// steps over F_p(t), F_p and Q, or refused as not rational. Any other exception, a crash or a sanitizer report is a finding.
#include <bit>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "kernels/formula/definition.hpp"
#include "kernels/formula/evaluate.hpp"
#include "kernels/formula_map.hpp"
#include "kernels/formula/expression.hpp"
#include "kernels/formula/program.hpp"
#include "core/error.hpp"
#include "integrability/degree_growth.hpp"
#include "integrability/finite_field_orbits.hpp"
#include "integrability/height_growth.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace qmaps::formula;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const Formulas f = parse_assignments(text);
    for (const Assignment& a : f.assignments) {
      const std::string printed = to_text(f, a.root);
      const Formulas again = parse_expression(printed);
      if (to_text(again, again.assignments[0].root) != printed)
        throw std::logic_error("printed back differently: " + printed);
    }
    const std::vector<std::string> inputs = {"q1", "q2", "p1", "p2"};
    Lowering lowering(f, inputs, {{"a", 0.5}, {"b", -3.0}, {"zero", 0.0}});
    lowering.assign_all();
    std::vector<std::uint16_t> outputs;
    for (const auto& name : inputs) outputs.push_back(lowering.value_of(name, {}));
    const Program p = lowering.finish(outputs);
    std::vector<double> r(p.registers());
    for (const double x : {0.0, 0.25, -1e300, 1e-310}) {
      for (std::size_t k = 0; k < inputs.size(); ++k) r[k] = x * static_cast<double>(k + 1);
      load_constants(p, r.data(), 1);
      run<double, 1>(p, r.data());
    }
  } catch (const FormulaError&) {
  }
  for (const char* key : {"step", "equations"}) {
    MapText t;
    t.name = "fuzz";
    t.form = "two_step";
    t.parameters = "h = 0.125";
    text_of(t, key) = std::string(text);
    try {
      const auto d = Definition::parse(t);
      const double h = 0.125;
      using qmaps::kernels::Formula;
      const Formula::Coeffs c = Formula::coefficients(std::span(&h, 1), d);
      for (const double x : {0.0, 0.5, -1e300}) {
        Formula::State<double> s = {x, -x, 2 * x, 0.25};
        // two chains three steps at once (the state resident where it can be) are three steps
        Formula::State<double> chains[2] = {s, {0.25, x, -x, 2 * x}};
        double escape = 0;
        Formula::step_chains<double, 2>(c, chains, 3, escape);
        for (int n = 0; n < 3; ++n) Formula::step(c, s);
        for (std::size_t i = 0; i < 4; ++i)
          if (std::bit_cast<std::uint64_t>(chains[0][i]) != std::bit_cast<std::uint64_t>(s[i]))
            throw std::logic_error("chains stepped together differ from single steps");
        Formula::invariants(c, s, static_cast<double*>(nullptr));  // no invariants given
        (void)Formula::phase(c, s);
      }
      try {
        const auto m = qmaps::exact::exact_map(d, {h});
        (void)qmaps::exact::degree_sequence(m, (1ULL << 61) - 1, 0, 3, 256, 1);
        (void)qmaps::exact::finite_field_orbits(m, 101, 64, 512, 1);
        (void)qmaps::exact::height_test(m, 3, 4096, 1);
      } catch (const DefinitionError&) {  // not rational
      } catch (const qmaps::exact::DivisionByZero&) {  // 101 divides a coefficient's denominator
      } catch (const qmaps::Error& e) {   // defined almost nowhere
        if (e.code() != qmaps::ExitCode::usage) throw;
      }
    } catch (const DefinitionError&) {
    }
  }
  return 0;
}
