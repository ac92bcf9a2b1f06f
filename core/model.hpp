#pragma once
// A map with its parameters resolved: the run-time face of a kernel, so that the command line,
// the I/O and the tests handle every map alike. ModelOf<Map> (core/model_of.hpp) implements it.
#include <array>
#include <cstddef>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/ensemble.hpp"
#include "core/execution.hpp"
#include "core/isa.hpp"
#include "core/observers/observers.hpp"
#include "core/params.hpp"
#include "core/phase.hpp"
#include "core/potential.hpp"
#include "core/run_plan.hpp"

namespace qmaps {

class Model {
 public:
  virtual ~Model() = default;
  virtual std::string_view name() const = 0;
  virtual std::span<const ParamSpec> param_specs() const = 0;
  virtual std::span<const double> param_values() const = 0;
  virtual std::span<const std::string_view> state_names() const = 0;
  virtual const std::vector<std::string>& invariant_names() const = 0;

  // An ensemble of `orbits` orbits laid out for this map, every orbit still to be started, with
  // the columns of every lane measurement (core/observers/lane_observers.hpp); `asked` names the
  // optional ones the run turns on.
  Ensemble ensemble(std::size_t orbits, std::span<const std::string> asked = {}) const {
    return Ensemble(orbits, state_names().size(), lane_columns(asked));
  }
  virtual std::vector<std::vector<ColumnSpec>> lane_columns(
      std::span<const std::string> asked) const = 0;
  // The configuration tables that turn on its optional lane measurements.
  virtual std::vector<std::string_view> lane_keys() const = 0;
  // Starts orbits [first, first + initial.size()) of `e` at these phase-space points (orbits whose
  // start is already beyond the bound or non-finite are escaped at step 0), with their
  // invariants' initial values. Once every orbit is started, e.fill_padding() completes `e`.
  virtual void start_at(Ensemble& e, std::size_t first, std::span<const Phase> initial, Start rule,
                        double escape_bound) const = 0;
  // The ensemble that starts at these phase-space points.
  Ensemble start(std::span<const Phase> initial, Start rule, double escape_bound) const {
    Ensemble e = ensemble(initial.size());
    start_at(e, 0, initial, rule, escape_bound);
    e.fill_padding();
    return e;
  }
  // Starts every orbit i of `e` in the state (state[0][i], state[1][i], …), components in the
  // order of state_names(), e.g. the /final/state of an earlier run; the same escape test.
  virtual void start_from_state(Ensemble& e, std::span<const std::vector<double>> state,
                                double escape_bound) const = 0;
  // The continuous system the map discretizes: its (A, B, α, β, δ); none for a formula map that
  // names none.
  virtual std::optional<Potential> continuous() const = 0;
  // The keys and texts of a formula map's definition (none for a built-in map).
  virtual std::vector<std::pair<std::string, std::string>> formulas() const = 0;
  // Advances from plan.first to plan.last; the samples of the orbits go into `observers`.
  virtual void advance(Ensemble& e, const RunPlan& plan, const Execution& x,
                       Observers* observers = nullptr) const = 0;
  // The orbits of a block of path x for this map (its chaos record may take fewer chains), and
  // the blocks [first, first + count) advanced on the calling thread alone, count a multiple of
  // the block: what the runner (core/runner.hpp) schedules.
  virtual std::size_t block_orbits(const Execution& x) const = 0;
  virtual void advance_range(Ensemble& e, std::size_t first, std::size_t count,
                             const RunPlan& plan, const Execution& x,
                             Observers* observers) const = 0;

  virtual Phase phase(const Ensemble& e, std::size_t orbit) const = 0;
  // The phase point of one state (components in the order of state_names()).
  virtual Phase phase_of(std::span<const double> state) const = 0;
  virtual std::vector<double> invariants(const Ensemble& e, std::size_t orbit) const = 0;
  // The same for orbits [first, first + count), into out[k][0, count) for each invariant k, on
  // the SIMD path of `isa` (lanes at a time; the same values on every path).
  virtual void invariants_of_orbits(const Ensemble& e, std::size_t first, std::size_t count,
                                    Isa isa, std::span<double* const> out) const = 0;
  // The invariants of one state (components in the order of state_names()).
  virtual std::vector<double> invariants_of(std::span<const double> state) const = 0;
  // Physical time of the orbit's current node (the same for every orbit unless
  // time_per_orbit()).
  virtual double time(const Ensemble& e, std::size_t orbit) const = 0;
  virtual bool time_per_orbit() const = 0;
  // The state components that are no dynamical variable (`qmaps discover` leaves them out): the
  // orbit's clock where time_per_orbit(), and those a map written as formulas leaves as they are
  // (q2, p2 of one degree of freedom).
  virtual std::vector<std::size_t> inert_state() const = 0;
  // Whether the map integrates a flow that carries an orbit to a position plane (a section of
  // mode exact).
  virtual bool flows_to_plane() const = 0;
  // Replaces every orbit's state by the one whose steps retrace it backward.
  virtual void reverse(Ensemble& e) const = 0;
  // The chaos indicators its state records (core/tangent_map.hpp), per orbit; none for a plain
  // map.
  virtual std::vector<std::string> indicator_names() const = 0;
  virtual std::vector<double> indicators(const Ensemble& e, std::size_t orbit) const = 0;
  // Why orbit's chaos record (read back from a file) cannot be one a run wrote; empty when it can,
  // and always for a plain map.
  virtual std::string invalid_record(const Ensemble& e, std::size_t orbit) const = 0;
};

}  // namespace qmaps
