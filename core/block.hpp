#pragma once
// One block of K × W orbits (W lanes, K chains interleaved to hide the latency of division),
// kept in registers for a chunk of steps whose only per-step extra is acc += |newest q|², a
// conservative escape test (and a sum of fault codes for a map that solves an equation). A chunk
// whose test trips is replayed step by step, freezing each lane exactly where the reference path
// stops it, so every lane computes what the reference computes for its orbit. The samples are
// taken inside the chunk where the test holds up to them (core/sample_schedule.hpp), observed one
// chain per step after it to overlap the next divisions; the sections are watched through their
// per-step hooks (core/observers/section/section_watch.hpp), chosen once per chunk outside its loop;
// so are the steps a lane measurement records (the tunes' windows: RecordWatch), where no section
// is watched (else those steps are taken one at a time).
// A map that steps the K chains together (StepsChains: a formula map) is stepped so, up to each
// sampling step at once, its watch called chain by chain as if they had been stepped one by one.
// The scalar reference path is this code at V = double, one orbit, one checked step at a time
// (core/runner.hpp); each SIMD instantiation lives in its ISA's unit (core/simd_unit.cpp.in).
#include <algorithm>
#include <concepts>
#include <cstddef>
#include <tuple>

#include "core/ensemble.hpp"
#include "core/lanes.hpp"
#include "core/ops.hpp"
#include "core/observers/density/density_lanes.hpp"
#include "core/observers/lane_observers.hpp"
#include "core/observers/observers.hpp"
#include "core/observers/section/section_watch.hpp"
#include "core/run_plan.hpp"
#include "core/sample_schedule.hpp"

namespace qmaps {
namespace detail {

inline constexpr long long max_chunk = 256;

// A map that steps a block's K chains together, several steps at once (a formula map: its
// program decoded once for all of them, the state kept in its registers), summing each step's
// escape measures into `escape` and returning the sum of the fault codes.
template <class Map, class V, int K>
concept StepsChains = requires(const typename Map::Coeffs& c,
                               typename Map::template State<V> (&s)[K], V& escape) {
  { Map::template step_chains<V, K>(c, s, 1LL, escape) } -> std::same_as<V>;
};

// What a chunk steps: chains from step `first`, `steps` steps, with the escape test's bound² and
// the samples it takes.
template <class Map, class V>
struct Chunk {
  const typename Map::Coeffs& c;
  long long first, steps;
  V bound2;
  ChunkSamples& samples;
};

// Steps the K chains of s the chunk's steps, unchecked, and tells whether any lane may have
// escaped or faulted on the way: one sum of the escape measures, conservative (it exceeds the
// bound or is not finite if any term does; idle lanes add 0), and one sum of the fault codes,
// serve all the chains. The chains are stepped in a local copy whose address never escapes, so
// that the compiler can keep it in registers; so is the watch. At the sampling steps, sample(k, x)
// observes each chain k at its state x there; where the test trips there, the chunk stops,
// suspect.
template <class Map, class V, int K, class Watch, class Sample>
[[gnu::always_inline]] inline bool step_chunk(const Chunk<Map, V>& chunk,
                                              typename Map::template State<V> (&s)[K],
                                              Watch& watching, Sample& sample) {
  using State = typename Map::template State<V>;
  // The chunk's fields in locals, which no store in the loop can alias.
  const auto& c = chunk.c;
  const long long steps = chunk.steps;
  const V bound2 = chunk.bound2;
  ChunkSamples samples = chunk.samples;
  State w[K];
  for (int k = 0; k < K; ++k) w[k] = s[k];
  Watch watch = watching;
  V acc(0.0), faults(0.0);
  bool clean = true;  // false: the test tripped at a sampling step
  // The chains' states at the last sampling step, observed one chain per step after it: the
  // observing then overlaps the next steps' divisions rather than stalling the divider for all
  // chains at once. The order of the samples changes nothing (counts, maxima).
  State held[K];
  int unobserved = K;  // held[unobserved..K) are still to be observed
  const auto observe_one = [&] {
    if (unobserved < K) {
      sample(unobserved, held[unobserved]);
      ++unobserved;
    }
  };
  // After step j: whether the samples due there were taken (false: the test trips there).
  const auto samples_taken = [&](long long j) {
    if (j + 1 != samples.at) return true;
    V reach = acc;
    for (int k = 0; k < K; ++k) reach = reach + Map::escape_measure(w[k]);
    if (ops::any(ops::negate(reach <= bound2) | (faults != V(0.0)))) [[unlikely]]
      return clean = false;
    while (unobserved < K) observe_one();  // a stride shorter than the chains
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
  if constexpr (StepsChains<Map, V, K>) {
    if constexpr (Watch::idle) {
      // the steps up to each sampling step at once
      for (long long j = 0; j < steps;) {
        const long long taking = std::min(steps, samples.at) - j;
        faults = faults + Map::template step_chains<V, K>(c, w, taking, acc);
        j += taking;
        if (!samples_taken(j - 1)) break;
      }
    } else {  // step by step, watched chain by chain as if stepped one by one
      watch.start(w);
      for (long long j = 0; j < steps; ++j) {
        State before[K];
        for (int k = 0; k < K; ++k) before[k] = w[k];
        faults = faults + Map::template step_chains<V, K>(c, w, 1, acc);
        for (int k = 0; k < K; ++k) {
          watch.before(k, before[k]);
          watch.after(k, j, w[k]);
        }
        watch.after_chains(j, w);
        observe_one();
        if (!samples_taken(j)) break;
      }
    }
  } else if constexpr (Watch::idle) {
    // Two steps per iteration: the state's shift (q_n ← q_{n+1}) renames registers instead of
    // moving them (Suris, 8 chains, AVX-512: +2–7%).
#pragma GCC unroll 2
    for (long long j = 0; j < steps; ++j) {
      for (int k = 0; k < K; ++k) advance(k);
      observe_one();
      if (!samples_taken(j)) break;
    }
  } else {
    watch.start(w);
    for (long long j = 0; j < steps; ++j) {
#pragma GCC unroll 8
      for (int k = 0; k < K; ++k) {
        watch.before(k, w[k]);
        advance(k);
        watch.after(k, j, w[k]);
      }
      watch.after_chains(j, w);
      observe_one();
      if (!samples_taken(j)) break;
    }
  }
  while (unobserved < K) observe_one();
  watching.kept = watch.kept;
  chunk.samples = samples;
  if (!clean) return true;
  for (int k = 0; k < K; ++k) {
    s[k] = w[k];
    acc = acc + Map::escape_measure(w[k]);
  }
  return ops::any(ops::negate(acc <= bound2) | (faults != V(0.0)));
}

// The same, out of line and flattened: the map's step is inlined into the chains' loop whatever
// its size, so that the K chains interleave (an out-of-line step serializes them through memory),
// and the loop is allocated apart from the block's many live values (8 chains' states alone fill
// the 32 registers: 5.1e9 against 4.4e9 particle-steps/s for Suris on AVX-512 inlined in the
// block). Only the loops, the per-sample and per-crossing work and the checked step are flattened,
// not the whole block: its unit compiles in a third of the time (Suris, AVX2: 38 s → 13 s) at the
// same speed.
template <class Map, class V, int K, class Watch, class Sample>
[[gnu::noinline, gnu::flatten]] bool step_chunk_apart(const Chunk<Map, V>& chunk,
                                                      typename Map::template State<V> (&s)[K],
                                                      Watch& watch, Sample& sample) {
  return step_chunk<Map, V, K>(chunk, s, watch, sample);
}

// The watch of a chunk whose steps a lane measurement records (the tunes' windows): each chain's
// state after the chunk's step j into its record, at[k] + j records on.
template <class Map, class V, int K>
struct RecordWatch {
  using State = typename Map::template State<V>;
  using Measures = LaneObservers<Map, V>;
  static constexpr bool idle = false;
  const typename Map::Coeffs* c;
  double* at[K];  // each chain's record of the chunk's first step
  std::size_t kept = 0;

  void start(const State (&)[K]) {}
  void before(int, const State&) {}
  void after(int k, long long j, const State& x) {
    Measures::record_at(*c, x, at[k] + static_cast<std::size_t>(j) * Measures::record_size);
  }
  void after_chains(long long, const State (&)[K]) {}
};

}  // namespace detail

// How a block advances: in chunks kept in registers (each chunk replayed step by step where its
// escape test trips), or one checked step at a time (the reference).
enum class Stepping { chunks, single_steps };

// A block of K chains of W lanes from orbit `first`, loaded from the ensemble, advanced and stored
// back. Escaped lanes keep their frozen state aside and idle at the origin, a fixed point of every
// map, so that they cost no solver iterations and raise no alarms.
template <class Map, class V, int K>
class Block {
  using L = detail::Lanes<Map, V>;
  using State = typename L::State;
  using Mask = typename L::Mask;
  static constexpr std::size_t W = L::W;

 public:
  Block(const typename Map::Coeffs& c, Ensemble& e, std::size_t first, const RunPlan& plan,
        Observers* observers)
      : c_(c), e_(e), first_(first), plan_(plan), observers_(observers),
        densities_(observers && !observers->densities.empty()),
        density_momentum_(densities_ && observers->densities_need_momentum()),
        schedule_(plan, plan.measure_orbits || densities_),
        sections_(c, observers, first, detail::max_chunk), bound2_(plan.escape_bound2()) {
    parked_.fill(V(0.0));
    for (int k = 0; k < K; ++k) {
      frozen_[k] = L::load(e, first + k * W);
      alive_[k] = L::alive(e, first + k * W);
      s_[k] = L::select(alive_[k], frozen_[k], parked_);
    }
  }

  bool any_alive() const {
    return std::any_of(alive_, alive_ + K, [](Mask m) { return ops::any(m); });
  }

  // Advances the block from plan.first to plan.last and stores it. Stepping one checked step at a
  // time (the scalar reference) compiles no chunk.
  template <Stepping stepping>
  void advance() {
    for (int k = 0; k < K; ++k)
      measures_[k].load(e_, first_ + k * W, plan_, static_cast<std::size_t>(k));
    if (densities_ && plan_.first == 0)
      for (int k = 0; k < K; ++k) count_densities(k, s_[k]);
    // the steps 1 .. until whose states the lane measurements record, up to each stop
    const long long until = plan_.measure_orbits ? measures_[0].records_until() : 0;
    long long n = plan_.first;
    while (n < plan_.last) {
      long long next = std::min(plan_.last, n + detail::max_chunk);
      const bool recording = n < until;
      const long long stop = recording ? measures_[0].next_stop(n) : 0;
      if (recording) next = std::min(next, stop);
      if (stepping == Stepping::single_steps || sections_.step_by_step() ||
          (recording && sections_.watched()))
        next = n + 1;
      bool checked;
      if constexpr (stepping == Stepping::single_steps)
        checked = single_step(next, recording);
      else
        checked = next == n + 1 ? single_step(next, recording) : chunk(n, next, recording);
      if (next > n + 1) schedule_.reach(next);
      n = next;
      if (recording && n == stop)
        for (int k = 0; k < K; ++k) measures_[k].reached(n, alive_[k]);
      if (checked && !any_alive()) break;  // lanes may have escaped
    }
    if (n < until)  // every lane escaped before the end of the windows
      for (int k = 0; k < K; ++k) measures_[k].reached(until, alive_[k]);
    for (int k = 0; k < K; ++k) {
      L::store(e_, first_ + k * W, L::select(alive_[k], s_[k], frozen_[k]));
      measures_[k].store(e_, first_ + k * W);
    }
  }

 private:
  // One step of chain k to node j, checked: the lanes that escape or fault there are recorded and
  // frozen, as the reference path stops each orbit. Steps in place, the previous node copied value
  // by value (a copy of the whole State compiles to a memory-to-memory move).
  [[gnu::flatten]] void checked_step(int k, long long j) {
    V previous[std::tuple_size_v<State>];
    for (std::size_t i = 0; i < std::size(previous); ++i) previous[i] = s_[k][i];
    const V fault = detail::step_reporting_faults<Map>(c_, s_[k]);
    const Mask ok = (Map::escape_measure(s_[k]) <= bound2_) & (fault == V(0.0));
    const Mask fresh = alive_[k] & ops::negate(ok);
    if (ops::any(fresh)) [[unlikely]] {
      State before_step;
      for (std::size_t i = 0; i < std::size(previous); ++i) before_step[i] = previous[i];
      L::record(e_, first_ + k * W, j, fresh, s_[k], fault);
      frozen_[k] = L::select(fresh, before_step, frozen_[k]);
      alive_[k] = alive_[k] & ok;
      s_[k] = L::select(alive_[k], s_[k], parked_);
    }  // else the idle lanes stay at the origin
  }
  void count_densities(int k, const State& x) {
    qmaps::sample_densities<Map>(c_, x, alive_[k], observers_->densities, density_momentum_);
  }
  // The samples of chain k at its node x.
  [[gnu::flatten]] void sample(int k, const State& x) {
    if (plan_.measure_orbits) measures_[k].sample(c_, x, alive_[k]);
    if (densities_) count_densities(k, x);
  }
  void sample_chains() {
    for (int k = 0; k < K; ++k) sample(k, s_[k]);
  }
  // A single step, checked as it goes and observed in registers; it was checked (true).
  bool single_step(long long next, bool recording) {
    const bool sampled = schedule_.single_step(next);
    sections_.refresh_before(s_);
#pragma GCC unroll 8
    for (int k = 0; k < K; ++k) {
      checked_step(k, next);
      sections_.check(k, s_[k], alive_[k], next);
      if (recording) measures_[k].record(c_, next, s_[k]);
      if (sampled) sample(k, s_[k]);
    }
    return true;
  }
  // The chunk of steps n + 1 .. next in registers, replayed step by step where it is suspect;
  // whether it was.
  bool chunk(long long n, long long next, bool recording) {
    ChunkSamples samples = schedule_.chunk(n, next);
    State start[K];
    for (int k = 0; k < K; ++k) start[k] = s_[k];
    const detail::Chunk<Map, V> args{c_, n, next - n, bound2_, samples};
    const auto sample = [this](int k, const State& x) { this->sample(k, x); };
    const auto steps = [&](auto& watch) {
      return detail::step_chunk_apart<Map, V, K>(args, s_, watch, sample);
    };
    detail::RecordWatch<Map, V, K> records{&c_, {}};
    if (recording)
      for (int k = 0; k < K; ++k) records.at[k] = measures_[k].records_at(n + 1);
    const bool suspect = recording ? steps(records) : sections_.watching(alive_, n, steps);
    if (!suspect) {
      sections_.record(n);
      if (schedule_.after_chunk(next)) sample_chains();
      return false;
    }
    // replayed step by step, its crossings and samples checked as they come
    for (int k = 0; k < K; ++k) s_[k] = start[k];
    sections_.refresh_before(s_);
    for (long long j = n + 1; j <= next; ++j) {
      for (int k = 0; k < K; ++k) {
        checked_step(k, j);
        sections_.check(k, s_[k], alive_[k], j);
        if (recording) measures_[k].record(c_, j, s_[k]);
      }
      if (schedule_.in_replay(j, n, samples)) sample_chains();
    }
    return true;
  }

  const typename Map::Coeffs& c_;
  Ensemble& e_;
  std::size_t first_;
  const RunPlan& plan_;
  Observers* observers_;
  bool densities_, density_momentum_;  // density_momentum_: any density reads p
  SampleSchedule schedule_;
  BlockSections<Map, V, K> sections_;
  V bound2_;
  State s_[K], frozen_[K], parked_;
  Mask alive_[K];
  LaneObservers<Map, V> measures_[K];
};

template <class Map, class V, int K, Stepping stepping>
void advance_block(const typename Map::Coeffs& c, Ensemble& e, std::size_t first,
                   const RunPlan& plan, Observers* observers) {
  Block<Map, V, K> block(c, e, first, plan, observers);
  // else nothing is left to step or observe
  if (block.any_alive()) block.template advance<stepping>();
}

}  // namespace qmaps
