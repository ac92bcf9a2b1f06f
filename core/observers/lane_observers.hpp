#pragma once
// The lane measurements: what a block measures of every orbit at its sampling steps, in
// registers at every width (V = double: the reference path), into named per-orbit columns of the
// ensemble (core/ensemble.hpp). Each is a template over (Map, V) in its own folder, with
//   static columns(coeffs, asked) -> std::vector<ColumnSpec>
//       its columns for this map, none where the run did not ask for it (it is then off);
//       `asked` names the optional measurements the run's configuration turns on
//   static constexpr std::string_view key                   optional: the configuration table
//       ([key]) that turns it on and names it in `asked`; without one it is always on
//   static start(coeffs, State<double> s, columns, orbit)  its values for an orbit starting at s
//   load(columns, orbit, plan, chain)                       the block's chain's lanes from `orbit`
//   sample(coeffs, State<V> x, alive)                       at a sampling step (optional)
//   store(columns, orbit) const
// A measurement that records every step's state up to a step (records_steps = true) also has
//   records_until() const        the last step it records in this call of the runner (0: none)
//   next_stop(n) const           the next step after n where it analyses what it recorded: the
//                                block's chunks end there
//   records_at(step) const       where the record of `step` goes: record_size doubles, a stop's
//                                steps one after the other (so that a chunk writes straight there)
//   static record(coeffs, x, at) the chain's state x (alive or not) as a record, at `at`
//   reached(step, alive)         every chain is at a stop; `alive`: its lanes that have not escaped
// At most one measurement of the list records steps.
// and one line in the list below. The block, the model's start, the run's file, the checkpoint
// and the merge iterate the list, and none of them names a measurement.
#include <algorithm>
#include <cstddef>
#include <span>
#include <string>
#include <string_view>
#include <tuple>
#include <type_traits>
#include <utility>
#include <vector>

#include "core/ensemble.hpp"
#include "core/observers/invariants/invariant_track.hpp"
#include "core/observers/tunes/tunes.hpp"
#include "core/run_plan.hpp"

namespace qmaps {

template <template <class, class> class... M>
struct LaneList {};

template <class M>
concept RecordsSteps = requires { requires M::records_steps; };
template <class M>
concept Samples = requires { &M::sample; };

// The list.
using LaneMeasurements = LaneList<InvariantTrack, Tunes>;

namespace detail {

// The measurements of one V, each a base: default-initialized, their registers' arrays are not
// zeroed (a std::tuple's would be, for every chain of every block).
template <class... M>
struct Each : M... {};

template <class Map, class V, class List>
struct LaneTuple;
template <class Map, class V, template <class, class> class... M>
struct LaneTuple<Map, V, LaneList<M...>> {
  using type = std::tuple<M<Map, V>...>;
  using each = Each<M<Map, V>...>;
};

// The index in a tuple of the measurement that records steps (at most one), its size where none.
template <class Tuple, std::size_t... i>
constexpr std::size_t recorder_index(std::index_sequence<i...>) {
  constexpr bool records[] = {false, RecordsSteps<std::tuple_element_t<i, Tuple>>...};
  static_assert((std::size_t{0} + ... + (records[i + 1] ? 1 : 0)) <= 1,
                "at most one lane measurement records steps");
  for (std::size_t j = 0; j < sizeof...(i); ++j)
    if (records[j + 1]) return j;
  return sizeof...(i);
}

template <template <class, class> class Wanted, template <class, class> class... M>
constexpr std::size_t index_in(LaneList<M...>) {
  constexpr bool same[] = {std::is_same_v<LaneList<Wanted>, LaneList<M>>...};
  for (std::size_t i = 0; i < sizeof...(M); ++i)
    if (same[i]) return i;
  return sizeof...(M);
}

}  // namespace detail

// The place of measurement M in the list: its columns are e.columns_of(lane_index<M>).
template <template <class, class> class M>
inline constexpr std::size_t lane_index = detail::index_in<M>(LaneMeasurements{});
static_assert(lane_index<InvariantTrack> == 0);

// Every lane measurement of one V (a block's chain, or one orbit), each one on where the
// ensemble holds its columns.
template <class Map, class V>
class LaneObservers {
  using Tuple = typename detail::LaneTuple<Map, V, LaneMeasurements>::type;
  using All = typename detail::LaneTuple<Map, V, LaneMeasurements>::each;
  static constexpr std::size_t count = std::tuple_size_v<Tuple>;
  static constexpr std::size_t recorder_at =
      detail::recorder_index<Tuple>(std::make_index_sequence<count>{});
  static constexpr bool has_recorder = recorder_at < count;
  using Recorder = std::tuple_element_t<has_recorder ? recorder_at : 0, Tuple>;

 public:
  // The columns of every measurement for this map, in list order.
  static std::vector<std::vector<ColumnSpec>> columns(const typename Map::Coeffs& c,
                                                      std::span<const std::string> asked) {
    std::vector<std::vector<ColumnSpec>> all;
    each_type([&]<class M>(std::size_t) { all.push_back(M::columns(c, asked)); });
    return all;
  }
  // The keys of the optional measurements.
  static std::vector<std::string_view> keys() {
    std::vector<std::string_view> all;
    each_type([&]<class M>(std::size_t) {
      if constexpr (requires { M::key; }) all.push_back(M::key);
    });
    return all;
  }
  static void start(const typename Map::Coeffs& c, const typename Map::template State<double>& s,
                    Ensemble& e, std::size_t orbit) {
    each_type([&]<class M>(std::size_t m) {
      if (!e.columns_of(m).empty()) M::start(c, s, e.columns_of(m), orbit);
    });
  }

  void load(const Ensemble& e, std::size_t orbit, const RunPlan& plan, std::size_t chain) {
    each([&](auto& m, std::size_t i) {
      on_[i] = !e.columns_of(i).empty();
      if (on_[i]) m.load(e.columns_of(i), orbit, plan, chain);
    });
  }
  void sample(const typename Map::Coeffs& c, const typename Map::template State<V>& x,
              ops::mask_t<V> alive) {
    each([&]<class M>(M& m, std::size_t i) {
      if constexpr (Samples<M>)
        if (on_[i]) m.sample(c, x, alive);
    });
  }
  // The measurement that records steps, where the list has one and the run turned it on: the
  // last step it records (0: none), its next stop after n, where a step's record goes, the state x
  // as that record (record_size doubles), and the stop `step` reached.
  long long records_until() const {
    if constexpr (has_recorder) return on_[recorder_at] ? recorder().records_until() : 0;
    else return 0;
  }
  long long next_stop(long long n) const {
    if constexpr (has_recorder) return recorder().next_stop(n);
    else return n;
  }
  double* records_at(long long step) const {
    if constexpr (has_recorder)
      if (step <= records_until()) return recorder().records_at(step);
    return nullptr;
  }
  static constexpr std::size_t record_size = [] {
    if constexpr (has_recorder) return Recorder::record_size;
    else return std::size_t{0};
  }();
  static void record_at(const typename Map::Coeffs& c, const typename Map::template State<V>& x,
                        double* at) {
    if constexpr (has_recorder) Recorder::record(c, x, at);
  }
  void record(const typename Map::Coeffs& c, long long step,
              const typename Map::template State<V>& x) {
    if (double* at = records_at(step)) record_at(c, x, at);
  }
  void reached(long long step, ops::mask_t<V> alive) {
    if constexpr (has_recorder)
      if (step <= records_until()) recorder().reached(step, alive);
  }
  void store(Ensemble& e, std::size_t orbit) const {
    each([&](const auto& m, std::size_t i) {
      if (on_[i]) m.store(e.columns_of(i), orbit);
    });
  }

 private:
  template <class F>
  static void each_type(F f) {
    [&]<std::size_t... i>(std::index_sequence<i...>) {
      (f.template operator()<std::tuple_element_t<i, Tuple>>(i), ...);
    }(std::make_index_sequence<count>{});
  }
  template <class F>
  void each(F f) {
    [&]<std::size_t... i>(std::index_sequence<i...>) {
      (f(static_cast<std::tuple_element_t<i, Tuple>&>(measures_), i), ...);
    }(std::make_index_sequence<count>{});
  }
  template <class F>
  void each(F f) const {
    [&]<std::size_t... i>(std::index_sequence<i...>) {
      (f(static_cast<const std::tuple_element_t<i, Tuple>&>(measures_), i), ...);
    }(std::make_index_sequence<count>{});
  }

  Recorder& recorder() { return measures_; }
  const Recorder& recorder() const { return measures_; }

  All measures_;
  bool on_[count] = {};
};

}  // namespace qmaps
