#pragma once
// ModelOf<Map>: the adapter that hides a map's type behind Model. It resolves the parameters once,
// starts orbits, converts states, and hands runs to the runner (core/runner.hpp).
#include <algorithm>
#include <stdexcept>
#include <string>

#include "core/error.hpp"
#include "core/map_concept.hpp"
#include "core/model.hpp"
#include "core/observers/lane_observers.hpp"
#include "core/runner.hpp"

namespace qmaps {

template <KernelMap Map>
class ModelOf final : public Model {
 public:
  // `extra`: what Map::coefficients takes beyond the parameters (a Tangent's orthonormalization,
  // a formula map's definition).
  template <class... Extra>
  explicit ModelOf(const ParamValues& given, Extra... extra)
      : identity_(identity_of<Map>(extra...)),
        state_views_(identity_.state_names.begin(), identity_.state_names.end()),
        values_(resolve_params(identity_.name, identity_.params, given)),
        c_(Map::coefficients(values_, extra...)),
        invariant_names_(Map::invariant_names(c_)) {}

  std::string_view name() const override { return identity_.name; }
  std::span<const ParamSpec> param_specs() const override { return identity_.params; }
  std::span<const double> param_values() const override { return values_; }
  std::span<const std::string_view> state_names() const override { return state_views_; }
  std::vector<std::pair<std::string, std::string>> formulas() const override {
    if constexpr (requires { Map::formulas(c_); })
      return Map::formulas(c_);
    else
      return {};
  }
  const std::vector<std::string>& invariant_names() const override { return invariant_names_; }
  std::vector<std::vector<ColumnSpec>> lane_columns(
      std::span<const std::string> asked) const override {
    return LaneObservers<Map, double>::columns(c_, asked);
  }
  std::vector<std::string_view> lane_keys() const override {
    return LaneObservers<Map, double>::keys();
  }
  const typename Map::Coeffs& coeffs() const { return c_; }

  void start_at(Ensemble& e, std::size_t first, std::span<const Phase> initial, Start rule,
                double escape_bound) const override {
    start_orbits(e, first, initial.size(), escape_bound,
                 [&](std::size_t j) { return Map::from_phase_space(c_, initial[j], rule); });
  }

  void start_from_state(Ensemble& e, std::span<const std::vector<double>> state,
                        double escape_bound) const override {
    if (state.size() != Map::state_names.size())
      throw usage_error(identity_.name + ": a state has " +
                        std::to_string(Map::state_names.size()) + " components, not " +
                        std::to_string(state.size()));
    start_orbits(e, 0, state.front().size(), escape_bound, [&](std::size_t i) {
      typename Map::template State<double> s;
      for (std::size_t k = 0; k < s.size(); ++k) s[k] = state[k][i];
      return s;
    });
  }

  std::optional<Potential> continuous() const override { return Map::continuous(c_); }

  void advance(Ensemble& e, const RunPlan& plan, const Execution& x,
               Observers* observers) const override {
    const RunPart part{this, &e, observers};
    advance_parts(std::span(&part, 1), plan, x);
  }
  std::size_t block_orbits(const Execution& x) const override {
    return qmaps::block_orbits(within(x));
  }
  void advance_range(Ensemble& e, std::size_t first, std::size_t count, const RunPlan& plan,
                     const Execution& x, Observers* observers) const override {
    qmaps::advance_range<Map>(c_, e, first, count, plan, within(x), observers);
  }

  Phase phase(const Ensemble& e, std::size_t orbit) const override {
    return Map::to_phase_space(c_, state_of(e, orbit));
  }
  Phase phase_of(std::span<const double> state) const override {
    typename Map::template State<double> s;
    if (state.size() != s.size()) throw usage_error("a state of the wrong size");
    std::copy(state.begin(), state.end(), s.begin());
    return Map::to_phase_space(c_, s);
  }
  std::vector<double> invariants(const Ensemble& e, std::size_t orbit) const override {
    double values[Map::max_invariants] = {};
    Map::invariants(c_, state_of(e, orbit), values);
    return {values, values + invariant_names_.size()};
  }
  void invariants_of_orbits(const Ensemble& e, std::size_t first, std::size_t count, Isa isa,
                            std::span<double* const> out) const override {
    if (out.size() != invariant_names_.size()) throw usage_error("a column per invariant");
    if (isa != Isa::scalar) return simd_path<Map>(isa).invariants(c_, e, first, count, out);
    for (std::size_t i = 0; i < count; ++i) {
      double values[Map::max_invariants] = {};
      Map::invariants(c_, state_of(e, first + i), values);
      for (std::size_t k = 0; k < out.size(); ++k) out[k][i] = values[k];
    }
  }
  std::vector<double> invariants_of(std::span<const double> state) const override {
    typename Map::template State<double> s;
    if (state.size() != s.size()) throw usage_error("a state of the wrong size");
    std::copy(state.begin(), state.end(), s.begin());
    double values[Map::max_invariants] = {};
    Map::invariants(c_, s, values);
    return {values, values + invariant_names_.size()};
  }
  double time(const Ensemble& e, std::size_t orbit) const override {
    return Map::time(c_, e.step, state_of(e, orbit));
  }
  bool time_per_orbit() const override { return Map::time_per_orbit; }
  std::vector<std::size_t> inert_state() const override {
    if constexpr (Map::time_per_orbit)
      return {Map::clock_state.begin(), Map::clock_state.end()};
    else if constexpr (requires { Map::inert_state(c_); })
      return Map::inert_state(c_);
    else
      return {};
  }
  bool flows_to_plane() const override { return FlowsToPlane<Map>; }
  void reverse(Ensemble& e) const override {
    for (std::size_t i = 0; i < e.padded; ++i) {
      const auto s = Map::reversed(c_, state_of(e, i));
      for (std::size_t k = 0; k < s.size(); ++k) e.state[k][i] = s[k];
    }
  }

  std::vector<std::string> indicator_names() const override {
    if constexpr (requires { Map::indicator_names(); })
      return Map::indicator_names();
    else
      return {};
  }
  std::string invalid_record(const Ensemble& e, std::size_t orbit) const override {
    if constexpr (requires { Map::invalid(c_, state_of(e, orbit)); }) {
      const char* why = Map::invalid(c_, state_of(e, orbit));
      return why ? why : "";
    } else {
      return {};
    }
  }
  std::vector<double> indicators(const Ensemble& e, std::size_t orbit) const override {
    if constexpr (requires { Map::indicator_names(); }) {
      std::vector<double> out(Map::indicator_names().size());
      Map::indicators(c_, state_of(e, orbit), out.data());
      return out;
    } else {
      return {};
    }
  }

 private:
  // Starts orbits [first, first + n) of e in the states state_at(0 … n − 1), in parallel:
  // escaped at step 0 where already beyond the bound or non-finite, with their invariants'
  // initial values.
  template <class StateAt>
  void start_orbits(Ensemble& e, std::size_t first, std::size_t n, double escape_bound,
                    StateAt state_at) const {
    if (first + n > e.orbits)
      throw usage_error("orbits [" + std::to_string(first) + ", " + std::to_string(first + n) +
                        ") are not in the ensemble");
    const long long count = static_cast<long long>(n);
#pragma omp parallel for schedule(static)
    for (long long j = 0; j < count; ++j) {
      const std::size_t i = first + static_cast<std::size_t>(j);
      const auto s = state_at(static_cast<std::size_t>(j));
      for (std::size_t k = 0; k < s.size(); ++k) e.state[k][i] = s[k];
      if (!(Map::escape_measure(s) <= escape_bound * escape_bound)) {
        e.escape_step[i] = 0;
        e.escape_reason[i] = escape_reason(0, s);
      }
      LaneObservers<Map, double>::start(c_, s, e, i);
    }
  }

  // x as this map runs it: its chains within those compiled for it (ChainRange).
  static Execution within(Execution x) {
    x.chains = ChainRange<Map>::clamp(x.chains);
    return x;
  }

  static typename Map::template State<double> state_of(const Ensemble& e, std::size_t orbit) {
    typename Map::template State<double> s;
    for (std::size_t k = 0; k < s.size(); ++k) s[k] = e.state[k][orbit];
    return s;
  }

  MapIdentity identity_;
  std::vector<std::string_view> state_views_;  // of identity_.state_names
  std::vector<double> values_;
  typename Map::Coeffs c_;
  std::vector<std::string> invariant_names_;
};

}  // namespace qmaps
