#pragma once
// What a map (kernels/) provides. One struct per map; every function that computes on orbits is
// a template over the value type V (double, long double or an xsimd batch) and uses core/ops
// only, so the scalar reference and every SIMD path compute the same bits.
//
//   name, summary                 its `--map` name and a one-line description
//   equations, invariant_summary  the paper's equation labels it implements; its invariants
//   params                        std::array<ParamSpec, N>: names, meanings, defaults
//   state_names                   std::array<std::string_view, S>: the state components
//   State<V>                      std::array<V, S>
//   max_invariants                the most invariants it reports
//   Coeffs coefficients(values)   validated coefficients, computed once (throws usage_error)
//   continuous(c)                 the Potential (A, B, α, β, δ) of the system it discretizes
//   invariant_names(c)            the invariants these parameters have
//   step<V>(c, s)                 advances the state one step in place; a map that solves an
//                                 equation returns a V: 0 where it succeeded, else an
//                                 EscapeReason code per lane
//   escape_measure<V>(s)          |newest configuration|², the runner's escape test
//   invariants<V>(c, s, out)      writes invariant_names(c).size() values
//   from_phase_space(c, x, start) the state that starts at phase-space point x
//   position<V>(c, s)             (q1, q2) at the state's node n
//   phase<V>(c, s)                (q1, q2, p1, p2) at the state's node n
//   to_phase_space(c, s)          the same for a double state, as a Phase
//   time(c, n, s)                 physical time of node n
//   reversed<V>(c, s)             the state whose steps retrace s backward
//   time_per_orbit                true when each orbit keeps its own clock in its state; then
//   clock<V>(s)                   the orbit's physical time, and
//   clock_state                   the state components that hold it (std::array of indices)
//   reports_faults                true when step solves an equation and returns fault codes
//   to_plane<V>(c, x, k, ds)      optional, for a map that integrates a flow: the phase point x
//                                 carried by that flow until q_k has moved by ds (Hénon's
//                                 method), what a section of mode `exact` records
//   facts                         MapFacts: its example parameters, tolerances and preset
//   min_chains, max_chains        optional: the chains per block it runs in (ChainRange)
// A map defined at run time (a formula map: DefinedAtRunTime) also has a Definition, which its
// coefficients take after the values, and says by identity(definition) what the others say by
// name, params and state_names; formulas(c) gives the text that defines it.
#include <array>
#include <concepts>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include "core/params.hpp"
#include "core/phase.hpp"
#include "core/potential.hpp"

namespace qmaps {

// A parameter's value by name, as a map states its examples.
struct NamedValue {
  std::string_view name;
  double value;
};
using ExampleParams = std::array<NamedValue, 8>;  // entries without a name are unused

// The example as ParamValues.
inline ParamValues param_values(const ExampleParams& example) {
  ParamValues out;
  for (const auto& [name, value] : example)
    if (!name.empty()) out.emplace(name, value);
  return out;
}

// What a map states about itself once, for its tests, benchmarks, `qmaps check` and docs.
struct MapFacts {
  ExampleParams example;      // bounded orbits from [−0.5, 0.5]⁴; check's defaults, benchmarks
  ExampleParams escaping;     // an attractive quartic: orbits from [−1.2, 1.2]² × [−1, 1]² leave |q| ≤ 10
  std::string_view step;      // the step parameter ("h", "ds")
  int order;                  // convergence order to the flow (taylor start); 0: it is the reference
  double reversal_tolerance;  // max |error| after 1000 steps forward and 1000 back
  double drift_tolerance;     // max |I_n − I_0| / mean |I_0| over 10⁵ steps, every invariant
  std::string_view preset;    // ensembles/presets/<preset>.toml
  bool slow;                  // solves an equation or evaluates many forces per step
  bool volume_preserving;     // det J = 1: its Lyapunov spectrum sums to 0 (docs/chaos.md)
  int forces_per_step;        // a splitting's force evaluations per step; 0: not a splitting
  double speed_budget;        // the least rate against Suris' (same ISA, 2 threads); 0: none
};

template <class M>
concept KernelMap = requires(const typename M::Coeffs& c, typename M::template State<double> s,
                             const Phase& x, std::span<const double> values, double* out) {
  { M::name } -> std::convertible_to<std::string_view>;
  { M::summary } -> std::convertible_to<std::string_view>;
  { M::equations } -> std::convertible_to<std::string_view>;
  { M::invariant_summary } -> std::convertible_to<std::string_view>;
  { M::params.size() } -> std::convertible_to<std::size_t>;
  { M::state_names.size() } -> std::convertible_to<std::size_t>;
  { M::max_invariants } -> std::convertible_to<std::size_t>;
  { M::coefficients(values) } -> std::same_as<typename M::Coeffs>;
  { M::continuous(c) } -> std::convertible_to<std::optional<Potential>>;
  { M::invariant_names(c) } -> std::same_as<std::vector<std::string>>;
  M::step(c, s);
  { M::escape_measure(s) } -> std::same_as<double>;
  M::invariants(c, s, out);
  { M::from_phase_space(c, x, Start::taylor) } -> std::same_as<typename M::template State<double>>;
  { M::position(c, s) } -> std::same_as<std::array<double, 2>>;
  { M::phase(c, s) } -> std::same_as<std::array<double, 4>>;
  { M::to_phase_space(c, s) } -> std::same_as<Phase>;
  { M::time(c, 0LL, s) } -> std::same_as<double>;
  { M::reversed(c, s) } -> std::same_as<typename M::template State<double>>;
  { M::time_per_orbit } -> std::convertible_to<bool>;
  { M::reports_faults } -> std::convertible_to<bool>;
  { M::facts } -> std::convertible_to<MapFacts>;
} && (M::reports_faults == !std::is_void_v<decltype(M::step(
                               std::declval<const typename M::Coeffs&>(),
                               std::declval<typename M::template State<double>&>()))>) &&
    (!M::time_per_orbit || requires(typename M::template State<double> s) {
      { M::clock(s) } -> std::same_as<double>;
      { M::clock_state.size() } -> std::convertible_to<std::size_t>;
    });

// A map's name, parameters and state components: a built-in map's static members, a formula
// map's definition's (whose storage its coefficients keep).
struct MapIdentity {
  std::string name;
  std::vector<ParamSpec> params;
  std::vector<std::string> state_names;
};

template <class M>
concept DefinedAtRunTime = requires { typename M::Definition; };

// The identity of M made with these extra arguments (a definition, after a tangent's).
template <class M, class... Extra>
MapIdentity identity_of(const Extra&... extra) {
  if constexpr (DefinedAtRunTime<M>) {
    return M::identity(extra...);
  } else {
    return {std::string(M::name), {M::params.begin(), M::params.end()},
            {M::state_names.begin(), M::state_names.end()}};
  }
}

// Whether the map integrates a flow that carries a phase point to a position plane.
template <class M>
concept FlowsToPlane = requires(const typename M::Coeffs& c, std::array<double, 4> x) {
  { M::to_plane(c, x, std::size_t{0}, 0.0) } -> std::same_as<std::array<double, 4>>;
};

// The chains per SIMD block a map runs in, the only counts compiled for it: 4 and 8 by default
// (fewer only slow a block: Suris, AVX-512, 1 thread, 5.7e8 particle-steps/s in blocks of 1
// chain, 9.5e8 of 2, 1.4e9 of 4 and of 8), or its own Map::min_chains .. Map::max_chains (a
// record that fills the registers takes fewer, a formula map's interpreter more). A run's
// `[run] chains` is clamped into them: the bytes are the same for every count.
template <class M>
struct ChainRange {
  static constexpr int most = [] {
    if constexpr (requires { M::max_chains; }) return M::max_chains;
    return 8;
  }();
  static constexpr int least = [] {
    if constexpr (requires { M::min_chains; }) return M::min_chains;
    return most < 4 ? most : 4;
  }();
  static constexpr int clamp(int chains) {
    return chains < least ? least : chains > most ? most : chains;
  }
};

}  // namespace qmaps
