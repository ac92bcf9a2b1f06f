#pragma once
// The SIMD path for one block of K × W orbits (W lanes, K chains interleaved to hide the latency
// of division). The block stays in registers for a chunk of steps (temporal blocking); the only
// per-step extra is one addition: acc += |newest q|², a conservative escape test. When a chunk ends
// with acc beyond the bound or non-finite in an alive lane, the chunk is replayed from its start
// step by step, freezing each lane exactly where the reference path stops it. So every lane
// computes exactly what the reference path computes for its orbit. A map whose step solves an
// equation adds its lanes' fault codes to a second sum, with the same replay when one is not 0.
// The samples (invariants, densities) are taken inside the chunk at the multiples of the stride,
// each only where the test holds up to it (the chains' states held there and observed one chain
// per step after it, overlapping the next steps' divisions); a chunk that trips there stops, and
// its replay takes only the samples not yet taken. The lanes that cross the usual watched section
// (one position plane, iterate points) are packed as they cross, and their points computed a
// whole batch at a time once the chunk proves clean.
//
// The scalar reference path is the same code at V = double, one orbit per block, one checked step
// at a time (advance_range in core/runner.hpp): the reference and every ISA share one implementation of
// stepping, escapes and observers. Each SIMD instantiation lives in its ISA's translation unit
// (core/simd_unit.cpp.in, through core/simd_blocks.hpp).
#include <algorithm>
#include <array>
#include <cstddef>
#include <type_traits>
#include <vector>

#include "core/aligned_array.hpp"
#include "core/ensemble.hpp"
#include "core/ops.hpp"
#include "core/run_plan.hpp"
#include "core/observers/density_lanes.hpp"
#include "core/observers/invariant_track.hpp"
#include "core/observers/observers.hpp"
#include "core/observers/section_lanes.hpp"

namespace qmaps {

namespace detail {

inline constexpr long long max_chunk = 256;

// One step in place; returns the lanes' fault codes (0: none; always 0 for explicit maps).
template <class Map, class V>
V step_reporting_faults(const typename Map::Coeffs& c, typename Map::template State<V>& s) {
  if constexpr (Map::reports_faults) {
    return Map::step(c, s);
  } else {
    Map::step(c, s);
    return V(0.0);
  }
}

template <class Map, class V>
struct Lanes {
  using State = typename Map::template State<V>;
  using Mask = ops::mask_t<V>;
  static constexpr std::size_t W = ops::lanes<V>;

  static State load(const Ensemble& e, std::size_t orbit) {
    State s;
    for (std::size_t k = 0; k < s.size(); ++k) s[k] = ops::load<V>(&e.state[k][orbit]);
    return s;
  }
  static void store(Ensemble& e, std::size_t orbit, const State& s) {
    for (std::size_t k = 0; k < s.size(); ++k) ops::store(&e.state[k][orbit], s[k]);
  }
  // The lanes that hold a real orbit that has not escaped (padding lanes count as escaped).
  static Mask alive(const Ensemble& e, std::size_t orbit) {
    alignas(64) std::array<double, W> flags;
    for (std::size_t l = 0; l < W; ++l)
      flags[l] = orbit + l < e.orbits && e.escape_step[orbit + l] < 0 ? 1.0 : 0.0;
    return ops::load<V>(flags.data()) != V(0.0);
  }
  static State select(Mask m, const State& a, const State& b) {
    State s;
    for (std::size_t k = 0; k < s.size(); ++k) s[k] = ops::select(m, a[k], b[k]);
    return s;
  }
  // Records the escape at step n of the lanes in `fresh`, whose escaped state is `t` and whose
  // solver fault codes are `fault`.
  static void record(Ensemble& e, std::size_t orbit, long long n, Mask fresh, const State& t,
                     V fault) {
    const auto lanes = ops::lanes_of(fresh);
    const auto faults = ops::lanes_of(fault);
    std::array<std::array<double, W>, std::tuple_size_v<State>> values;
    for (std::size_t k = 0; k < t.size(); ++k) values[k] = ops::lanes_of(t[k]);
    for (std::size_t l = 0; l < W; ++l) {
      if (!lanes[l]) continue;
      std::array<double, std::tuple_size_v<State>> lane;
      for (std::size_t k = 0; k < t.size(); ++k) lane[k] = values[k][l];
      e.escape_step[orbit + l] = n;
      e.escape_reason[orbit + l] = escape_reason(faults[l], lane);
    }
  }
};

// The planes of the sections a chunk watches in registers: each section's plane coordinate is
// evaluated after every step, and a crossing by an alive lane is kept (the chain, the step, the
// state after it, and the state before it only where a section interpolates) to be recorded
// once the chunk proves clean. At most `max_watched` sections are watched so; more are checked
// step by step.
inline constexpr std::size_t max_watched = 4;

template <class Map, class V>
struct Crossing {
  typename Map::template State<V> before, after;  // before: only where a section needs it
  ops::mask_t<V> lanes;
  long long step;
  int chain;
  int section;
};

template <class Map, class V>
struct Watch {
  std::size_t count = 0;  // 0: no section is watched
  const Section* sections[max_watched];
  bool keep_before = false;  // a section's point needs the state before the crossing too
  // Room for every crossing a chunk can have (its steps × K chains × count): filled from 0.
  Crossing<Map, V>* crossings = nullptr;
  // The usual watch, one section on a position plane whose point is the iterate's, is lane
  // dense: the lanes that cross are packed as they cross, each state coordinate i from
  // staged + i · room and then each lane's id from staged + size · room (its step in the chunk
  // · K·W + its chain · W + its lane), so that the points are computed a whole batch at a time.
  // room: every lane of every step of a chunk, and a batch more.
  double* staged = nullptr;
  std::size_t room = 0;
  bool lane_dense() const {
    return count == 1 && !keep_before && is_position(sections[0]->plane);
  }

  // The section's plane coordinate at the state's node: the same value node_values gives.
  static V plane(const typename Map::Coeffs& c, const typename Map::template State<V>& s,
                 Coordinate coordinate) {
    const auto k = static_cast<std::size_t>(coordinate);
    if (coordinate == Coordinate::t) {
      if constexpr (Map::time_per_orbit) return Map::clock(s);
      return V(0.0);
    }
    if (is_momentum(coordinate)) return Map::phase(c, s)[k];
    return Map::position(c, s)[k];
  }
};

// The samples a chunk takes while its chains are in registers: after its steps at, at + stride,
// ... (counted from 1), each only where the escape test holds up to it, so that a sample taken is
// one the reference takes. `through`: the chunk's last step sampled.
struct ChunkSamples {
  long long at, stride, through = 0;
};

// Steps the K chains of s `steps` times from step `first`, unchecked, and tells whether any lane
// may have escaped or faulted on the way: one sum of the escape measures, conservative (it
// exceeds the bound or is not finite if any term does; idle lanes add 0), and one sum of the fault
// codes, serve all the chains. The chains are stepped in a local copy whose address never
// escapes, so that the compiler can keep it in registers. The watched sections' crossings by the
// `alive` lanes go to watch.crossings (lane dense: watch.staged), in step order; `crossed` tells
// how many (lane dense: lanes). At the sampling
// steps, sample(k, x) observes each chain k at its state x there; where the test trips there, the
// chunk stops, suspect.
template <class Map, class V, int K, bool keep_before, class Sample>
[[gnu::always_inline]] inline bool step_chunk(const typename Map::Coeffs& c,
                                                typename Map::template State<V> (&s)[K],
                                                long long first, long long steps, V bound2,
                                                const Watch<Map, V>& watch,
                                                const ops::mask_t<V> (&alive)[K],
                                                std::size_t& crossed, ChunkSamples& samples,
                                                Sample& sample) {
  constexpr std::size_t W = ops::lanes<V>;
  typename Map::template State<V> w[K];
  std::size_t n = 0;  // crossings (lane dense: lanes) so far
  for (int k = 0; k < K; ++k) w[k] = s[k];
  V acc(0.0), faults(0.0);
  bool clean = true;  // false: the test tripped at a sampling step
  // The chains' states at the last sampling step, observed one chain per step after it: the
  // observing then overlaps the next steps' divisions rather than stalling the divider for all
  // chains at once. The order of the samples changes nothing (counts, maxima).
  typename Map::template State<V> held[K];
  int unobserved = K;  // held[unobserved..K) are still to be observed
  const auto observe_one = [&] {
    if (unobserved < K) {
      sample(unobserved, held[unobserved]);
      ++unobserved;
    }
  };
  const auto observe_all = [&] {
    while (unobserved < K) observe_one();
  };
  // After step j: whether the samples due there were taken (false: the test trips there).
  const auto samples_taken = [&](long long j) {
    if (j + 1 != samples.at) return true;
    V reach = acc;
    for (int k = 0; k < K; ++k) reach = reach + Map::escape_measure(w[k]);
    if (ops::any(ops::negate(reach <= bound2) | (faults != V(0.0)))) [[unlikely]]
      return clean = false;
    observe_all();  // a stride shorter than the chains
    for (int k = 0; k < K; ++k) held[k] = w[k];
    unobserved = 0;
    samples.through = j + 1;
    samples.at += samples.stride;
    return true;
  };
  const auto advance = [&](int k) {  // one step of chain k, its escape measure summed before it
    acc = acc + Map::escape_measure(w[k]);
    if constexpr (Map::reports_faults)
      faults = faults + Map::step(c, w[k]);
    else
      Map::step(c, w[k]);
  };
  // Keeps the crossing of `section` by chain k's `lanes` at step j of the chunk.
  const auto keep = [&](ops::mask_t<V> lanes, const typename Map::template State<V>& before,
                        int k, long long j, int section) {
    auto& x = watch.crossings[n++];
    if constexpr (keep_before) x.before = before;
    x.after = w[k];
    x.lanes = lanes;
    x.step = first + j + 1;
    x.chain = k;
    x.section = section;
  };
  if (!keep_before && watch.count == 0) {  // (keep_before implies a watched section)
    // Two steps per iteration: the state's shift (q_n ← q_{n+1}) renames registers instead of
    // moving them (Suris, 8 chains, AVX-512: +2–7%).
#pragma GCC unroll 2
    for (long long j = 0; j < steps; ++j) {
      for (int k = 0; k < K; ++k) advance(k);
      observe_one();
      if (!samples_taken(j)) break;
    }
  } else if (watch.count == 1 && is_position(watch.sections[0]->plane)) {
    // One section on a position plane, the usual case: its plane, value and direction in locals,
    // so that nothing is reloaded from memory between steps. The plane coordinate is picked by a
    // select, not an index, and the direction is a constant of the loop (crosses() at a known
    // direction). No lane mask is needed: a lane that is not alive idles at the origin, whose
    // plane coordinate never changes and so never crosses (on AVX2, the 8 masks freed from the
    // 16 registers: +12-20%).
    const Section& section = *watch.sections[0];
    const ops::mask_t<V> second = V(section.plane == Coordinate::q2 ? 1.0 : 0.0) != V(0.0);
    const V value(section.value);
    const auto plane = [&](const typename Map::template State<V>& x) {
      const auto q = Map::position(c, x);
      return ops::select(second, q[1], q[0]);
    };
    const auto watch_one = [&](auto direction) {
      const auto crossing_of = [&](V a, V b) { return crosses(value, direction(), a, b); };
      V previous[K];
      for (int k = 0; k < K; ++k) previous[k] = plane(w[k]);
      if constexpr (!keep_before) {
        // Lane dense (Watch::staged): one branch per step for all the chains (a crossing is rare
        // for each lane but common among all), then each chain that crossed packs its crossing
        // lanes (a branch per chain there, rather than every chain packing none: AVX-512 +10-20%,
        // AVX2 within noise).
        constexpr std::size_t size = std::tuple_size_v<typename Map::template State<V>>;
        const V lane = ops::lane_index<V>();
        for (long long j = 0; j < steps; ++j) {
          ops::mask_t<V> crossing[K];
#pragma GCC unroll 8
          for (int k = 0; k < K; ++k) {
            advance(k);
            const V now = plane(w[k]);
            crossing[k] = crossing_of(previous[k], now);
            previous[k] = now;
          }
          ops::mask_t<V> any = crossing[0];
          for (int k = 1; k < K; ++k) any = any | crossing[k];
          if (ops::any(any)) {
            const V step_id(static_cast<double>((j + 1) * K * static_cast<long long>(W)));
#pragma GCC unroll 8
            for (int k = 0; k < K; ++k) {
              if (!ops::any(crossing[k])) continue;
              double* at = watch.staged + n;
              for (std::size_t i = 0; i < size; ++i)
                ops::compress(at + i * watch.room, crossing[k], w[k][i]);
              n += ops::compress(at + size * watch.room, crossing[k],
                                 step_id + V(static_cast<double>(k * static_cast<int>(W))) + lane);
            }
          }
          observe_one();
          if (!samples_taken(j)) break;
        }
      } else {
        for (long long j = 0; j < steps; ++j) {
#pragma GCC unroll 8
          for (int k = 0; k < K; ++k) {
            const typename Map::template State<V> before = w[k];
            advance(k);
            const V now = plane(w[k]);
            const ops::mask_t<V> crossing = crossing_of(previous[k], now);
            if (ops::any(crossing)) [[unlikely]]
              keep(crossing, before, k, j, 0);
            previous[k] = now;
          }
          observe_one();
          if (!samples_taken(j)) break;
        }
      }
    };
    if (section.direction > 0)
      watch_one(std::integral_constant<int, 1>{});
    else if (section.direction < 0)
      watch_one(std::integral_constant<int, -1>{});
    else
      watch_one(std::integral_constant<int, 0>{});
  } else {
    // Several sections (or one on a momentum or time plane): each plane from node_values' index.
    V previous[K][max_watched];
    for (int k = 0; k < K; ++k)
      for (std::size_t i = 0; i < watch.count; ++i)
        previous[k][i] = Watch<Map, V>::plane(c, w[k], watch.sections[i]->plane);
    for (long long j = 0; j < steps; ++j) {
#pragma GCC unroll 8  // the chains in registers, as in the unwatched loop
      for (int k = 0; k < K; ++k) {
        typename Map::template State<V> before;
        if constexpr (keep_before) before = w[k];
        advance(k);
        for (std::size_t i = 0; i < watch.count; ++i) {
          const V now = Watch<Map, V>::plane(c, w[k], watch.sections[i]->plane);
          const ops::mask_t<V> crossing = crosses(*watch.sections[i], previous[k][i], now) & alive[k];
          if (ops::any(crossing)) [[unlikely]]
            keep(crossing, before, k, j, static_cast<int>(i));
          previous[k][i] = now;
        }
      }
      observe_one();
      if (!samples_taken(j)) break;
    }
  }
  observe_all();
  crossed = n;
  if (!clean) return true;
  for (int k = 0; k < K; ++k) {
    s[k] = w[k];
    acc = acc + Map::escape_measure(w[k]);
  }
  return ops::any(ops::negate(acc <= bound2) | (faults != V(0.0)));
}

// The same, out of line, for blocks of 8 chains: their states alone fill the 32 registers, and a
// loop allocated apart from advance_block's many live values spills less (measured: 5.1e9 against
// 4.4e9 particle-steps/s for Suris on AVX-512). Blocks of up to 4 chains fit in registers inline.
template <class Map, class V, int K, bool keep_before, class Sample>
[[gnu::noinline, gnu::flatten]] bool step_chunk_apart(const typename Map::Coeffs& c,
                                                      typename Map::template State<V> (&s)[K],
                                                      long long first, long long steps, V bound2,
                                                      const Watch<Map, V>& watch,
                                                      const ops::mask_t<V> (&alive)[K],
                                                      std::size_t& crossed, ChunkSamples& samples,
                                                      Sample& sample) {
  return step_chunk<Map, V, K, keep_before>(c, s, first, steps, bound2, watch, alive, crossed,
                                            samples, sample);
}

// The chunk, with the states before crossings kept only where a watched section needs them.
template <class Map, class V, int K, class Sample>
[[gnu::always_inline]] inline bool step_any_chunk(const typename Map::Coeffs& c,
                                                  typename Map::template State<V> (&s)[K],
                                                  long long first, long long steps, V bound2,
                                                  const Watch<Map, V>& watch,
                                                  const ops::mask_t<V> (&alive)[K],
                                                  std::size_t& crossed, ChunkSamples& samples,
                                                  Sample& sample) {
  if constexpr (K == 8) {
    if (watch.keep_before)
      return step_chunk_apart<Map, V, K, true>(c, s, first, steps, bound2, watch, alive, crossed,
                                               samples, sample);
    return step_chunk_apart<Map, V, K, false>(c, s, first, steps, bound2, watch, alive, crossed,
                                              samples, sample);
  } else {
    if (watch.keep_before)
      return step_chunk<Map, V, K, true>(c, s, first, steps, bound2, watch, alive, crossed,
                                         samples, sample);
    return step_chunk<Map, V, K, false>(c, s, first, steps, bound2, watch, alive, crossed,
                                        samples, sample);
  }
}

}  // namespace detail

// How a block advances: in chunks kept in registers (each chunk replayed step by step where its
// escape test trips), or one checked step at a time (the reference).
enum class Stepping { chunks, single_steps };

// flatten: the map's step is inlined into the chains' loop whatever its size, so that the K
// chains interleave (an out-of-line step serializes them through memory).
template <class Map, class V, int K>
[[gnu::flatten]] void advance_block(const typename Map::Coeffs& c, Ensemble& e, std::size_t first,
                                    const RunPlan& plan, Observers* observers, Stepping stepping) {
  using L = detail::Lanes<Map, V>;
  using State = typename L::State;
  using Mask = typename L::Mask;
  constexpr std::size_t W = L::W;

  // Escaped lanes keep their frozen state aside and idle at the origin, a fixed point of every
  // map, so that they cost no solver iterations and raise no alarms.
  State s[K], frozen[K];
  Mask alive[K];
  State parked;
  parked.fill(V(0.0));
  for (int k = 0; k < K; ++k) {
    frozen[k] = L::load(e, first + k * W);
    alive[k] = L::alive(e, first + k * W);
    s[k] = L::select(alive[k], frozen[k], parked);
  }
  // A block whose every orbit has escaped has nothing left to step or observe.
  const auto any_alive = [&] {
    bool any = false;
    for (int k = 0; k < K; ++k) any = any || ops::any(alive[k]);
    return any;
  };
  if (!any_alive()) return;
  InvariantTrack<Map, V> track[K];
  for (int k = 0; k < K; ++k) track[k].load(e, first + k * W);
  const V bound2(plan.escape_bound2());
  // Decided once for the block: what is sampled, and which coordinates the observers read.
  const bool sections = observers && !observers->sections.empty();
  const bool densities = observers && !observers->densities.empty();
  const bool density_momentum = densities && observers->densities_need_momentum();
  const bool section_momentum = sections && observers->sections_need_momentum();
  for (int k = 0; k < K; ++k)
    if (densities && plan.first == 0)
      sample_densities<Map>(c, s[k], alive[k], observers->densities, density_momentum);
  // The chains' nodes before the next step, for the sections checked step by step: computed only
  // when such a step comes (a watched chunk needs none, and with p each is a reversed step).
  std::array<V, 5> before[K];
  bool before_stale = sections;
  const auto refresh_before = [&] {
    if (!before_stale) return;
    for (int k = 0; k < K; ++k) before[k] = node_values<Map>(c, s[k], section_momentum);
    before_stale = false;
  };
  // Up to max_watched sections are watched inside the chunks; more are checked step by step.
  // Each chunk's crossings go to one buffer per thread, kept across blocks and sized for the most
  // a chunk can have: it grows only on a thread's first blocks.
  thread_local std::vector<detail::Crossing<Map, V>> crossings;
  thread_local AlignedArray<double> staged;  // lane dense (detail::Watch::staged)
  std::size_t crossed = 0;  // in the last chunk
  detail::Watch<Map, V> watch;
  if (sections && observers->sections.size() <= detail::max_watched) {
    for (const auto& section : observers->sections) {
      watch.sections[watch.count++] = &section;
      watch.keep_before = watch.keep_before || section.needs_before();
    }
    if (watch.lane_dense()) {
      watch.room = (static_cast<std::size_t>(detail::max_chunk) * K + 1) * W;
      const std::size_t values = watch.room * (std::tuple_size_v<State> + 1);
      if (staged.size() < values) staged = AlignedArray<double>(values);
      watch.staged = staged.data();
    } else {
      const std::size_t room = static_cast<std::size_t>(detail::max_chunk) * K * watch.count;
      if (crossings.size() < room) crossings.resize(room);
      watch.crossings = crossings.data();
    }
  }
  const bool sampling = plan.track_invariants || densities;
  // The next multiple of the stride (plan.samples_at without a division per single step).
  long long next_multiple = (plan.first / plan.stride + 1) * plan.stride;

  // One step of chain k to node j, checked: the lanes that escape or fault there are recorded and
  // frozen, as the reference path stops each orbit.
  // Steps in place, the previous node copied value by value (a copy of the whole State compiles to
  // a memory-to-memory move).
  const auto checked_step = [&](int k, long long j) {
    V previous[std::tuple_size_v<State>];
    for (std::size_t i = 0; i < std::size(previous); ++i) previous[i] = s[k][i];
    const V fault = detail::step_reporting_faults<Map>(c, s[k]);
    const Mask ok = (Map::escape_measure(s[k]) <= bound2) & (fault == V(0.0));
    const Mask fresh = alive[k] & ops::negate(ok);
    if (ops::any(fresh)) [[unlikely]] {
      State before_step;
      for (std::size_t i = 0; i < std::size(previous); ++i) before_step[i] = previous[i];
      L::record(e, first + k * W, j, fresh, s[k], fault);
      frozen[k] = L::select(fresh, before_step, frozen[k]);
      alive[k] = alive[k] & ok;
      s[k] = L::select(alive[k], s[k], parked);
    }  // else the idle lanes stay at the origin
  };
  // The sections crossed by chain k from its node before (`before[k]`) to node n.
  const auto check = [&](int k, long long n) {
    if (sections)
      check_sections<Map>(c, s[k], alive[k], observers->sections, section_momentum, first + k * W,
                          n, before[k]);
  };
  // The samples of chain k at its node x.
  const auto sample = [&](int k, const State& x) {
    if (plan.track_invariants) track[k].sample(c, x, alive[k]);
    if (densities) sample_densities<Map>(c, x, alive[k], observers->densities, density_momentum);
  };
  const auto sample_chains = [&](const State (&x)[K]) {
    for (int k = 0; k < K; ++k) sample(k, x[k]);
  };
  // The crossings a clean chunk kept, recorded as check_sections records them: first every
  // crossing's points and slots in V, then the lanes one by one (two passes, so that the lanes'
  // scalar reads do not wait on the stores just made of them).
  thread_local std::vector<CrossingLanes<V>> prepared;  // the first pass's, one per crossing
  if (prepared.size() < crossings.size()) prepared.resize(crossings.size());
  const auto record_crossings = [&](long long chunk_first) {
    if (watch.lane_dense()) {  // a batch of packed lanes at a time; the last batch's first lanes
      Section& section = observers->sections[0];
      constexpr std::size_t size = std::tuple_size_v<State>, chunk_lanes = K * W;
      for (std::size_t i = 0; i < crossed; i += W) {
        State after;
        for (std::size_t k = 0; k < size; ++k)
          after[k] = ops::load<V>(watch.staged + k * watch.room + i);
        const Mask lanes = ops::lane_index<V>() < V(static_cast<double>(crossed - i));
        const auto values = node_values<Map>(c, after, section_momentum);
        const auto id = ops::integer_lanes(ops::load<V>(watch.staged + size * watch.room + i));
        const auto orbit_of = [&](std::size_t l) { return first + id[l] % chunk_lanes; };
        const auto step_of = [&](std::size_t l) {
          return chunk_first + static_cast<long long>(id[l] / chunk_lanes);
        };
        keep_lanes(section, crossing_lanes<Map>(c, section, lanes, values, values), orbit_of,
                   step_of);
      }
      return;
    }
    for (std::size_t i = 0; i < crossed; ++i) {
      const auto& x = crossings[i];
      Section& section = observers->sections[static_cast<std::size_t>(x.section)];
      const auto after = node_values<Map>(c, x.after, section_momentum);
      prepared[i] = crossing_lanes<Map>(
          c, section, x.lanes,
          section.needs_before() ? node_values<Map>(c, x.before, section_momentum) : after, after);
    }
    for (std::size_t i = 0; i < crossed; ++i) {
      const auto& x = crossings[i];
      keep_lanes(observers->sections[static_cast<std::size_t>(x.section)], prepared[i],
                 first + x.chain * W, x.step);
    }
  };

  for (long long n = plan.first; n < plan.last;) {
    long long next = std::min(plan.last, n + detail::max_chunk);
    if (stepping == Stepping::single_steps || (sections && watch.count == 0))
      next = n + 1;  // the reference, or many sections: checked step by step

    if (next == n + 1) {  // a single step is checked as it goes, and observed while in registers
      const bool at_multiple = next == next_multiple;
      if (at_multiple) next_multiple += plan.stride;
      const bool sampled = sampling && (at_multiple || next == plan.total);
      refresh_before();
#pragma GCC unroll 8
      for (int k = 0; k < K; ++k) {
        checked_step(k, next);
        check(k, next);
        if (sampled) sample(k, s[k]);
      }
      n = next;
      if (!any_alive()) break;
      continue;
    }

    // The chunk samples the multiples of the stride in it; the run's last step, if no multiple,
    // is sampled after it.
    detail::ChunkSamples samples{sampling ? next_multiple - n : next - n + 1, plan.stride};
    State start[K];
    for (int k = 0; k < K; ++k) start[k] = s[k];
    const bool suspect = detail::step_any_chunk<Map, V, K>(c, s, n, next - n, bound2, watch,
                                                           alive, crossed, samples, sample);
    if (suspect) {  // replay the chunk step by step, its crossings and samples checked as they come
      for (int k = 0; k < K; ++k) s[k] = start[k];
      refresh_before();
      for (long long j = n + 1; j <= next; ++j) {
        for (int k = 0; k < K; ++k) {
          checked_step(k, j);
          check(k, j);
        }
        if (sampling && j > n + samples.through && plan.samples_at(j)) sample_chains(s);
      }
    } else {
      if (watch.count > 0) {
        record_crossings(n);
        before_stale = true;
      }
      if (sampling && next == plan.total && next % plan.stride != 0) sample_chains(s);
    }
    n = next;
    next_multiple = (n / plan.stride + 1) * plan.stride;
    if (suspect && !any_alive()) break;
  }
  for (int k = 0; k < K; ++k) {
    L::store(e, first + k * W, L::select(alive[k], s[k], frozen[k]));
    track[k].store(e, first + k * W);
  }
}

}  // namespace qmaps
