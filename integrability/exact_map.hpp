#pragma once
// A map evaluated exactly (docs/integrability.md): its step and invariants over the exact number
// types of field.hpp and residue_lanes.hpp. A built-in map's step is its kernel's template,
// instantiated over the exact type with the kernel's coefficients as the rationals field.hpp reads
// a double as; a formula map's is its formulas, lowered with its parameters as inputs (so nothing
// of them is rounded) and run over the exact type. Refused, with the reason: a map whose step is
// not a rational function of the state (case3 solves an equation by iteration; a formula with
// sqrt, sin, cos, exp or log).
#include <array>
#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <tuple>
#include <vector>

#include "core/params.hpp"
#include "integrability/field.hpp"
#include "integrability/residue_lanes.hpp"
#include "kernels/formula/definition.hpp"

namespace qmaps::exact {

using Lanes = ResidueLanes<64>;

template <class V>
using State = std::array<V, 4>;

class ExactMap {
 public:
  std::string name;
  std::string evaluated_by;                // "its kernel (kernels/suris.hpp)", "its formulas"
  std::array<std::string, 4> state_names;  // the state's coordinates, in order
  std::vector<std::string> invariant_names;
  bool invariants_exact = false;  // formulas with rational coefficients: exactly invariant
  // The coordinates its step changes (a one-degree-of-freedom formula map keeps q2, p2),
  // found over F_p at random points.
  std::vector<std::size_t> varying;

  template <class V>
  void step(State<V>& s) const { std::get<Step<V>>(steps_)(s); }
  template <class V>
  void invariants(const State<V>& s, V* out) const { std::get<Invariants<V>>(invariants_)(s, out); }

  template <class V>
  using Step = std::function<void(State<V>&)>;
  template <class V>
  using Invariants = std::function<void(const State<V>&, V*)>;
  std::tuple<Step<Residue>, Step<FunctionOfT>, Step<Rational>, Step<Lanes>> steps_;
  std::tuple<Invariants<Residue>, Invariants<FunctionOfT>, Invariants<Rational>, Invariants<Lanes>>
      invariants_;
};

// A built-in map by name, its parameters resolved as a run resolves them.
ExactMap exact_map(const std::string& name, const ParamValues& params);
// A formula map with its parameters' values (in the order of definition->params()).
ExactMap exact_map(const std::shared_ptr<const formula::Definition>& definition,
                   const std::vector<double>& values);

}  // namespace qmaps::exact
