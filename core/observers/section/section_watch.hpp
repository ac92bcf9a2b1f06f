#pragma once
// The sections as a block observes them (core/block.hpp). Inside a chunk, while the chains step in
// registers, each section's plane coordinate is evaluated after every step, and a crossing by an
// alive lane is kept (the chain, the step, the state after it, and the state before it only where
// a section interpolates) to be recorded once the chunk proves clean. At most `max_watched`
// sections are watched so; with more, the block checks them step by step (check_sections).
//
// A watch is the chunk loop's per-step hooks, its type chosen once per chunk, outside the loop:
//   start(w)            the chains' states before the chunk
//   before(k, x)        chain k's state x before its step
//   after(k, j, x)      chain k's state x after the chunk's step j (from 0)
//   after_chains(j, w)  after every chain's step j
//   kept                the crossings (lane dense: lanes) kept so far
// NoWatch has none. The usual watch, one section on a position plane whose point is the
// iterate's, is lane dense (DenseWatch): the lanes that cross are packed as they cross and their
// points computed a whole batch at a time.
#include <array>
#include <cstddef>
#include <tuple>
#include <type_traits>
#include <vector>

#include "core/aligned_array.hpp"
#include "core/observers/observers.hpp"
#include "core/observers/section/section_lanes.hpp"

namespace qmaps {

namespace detail {

inline constexpr std::size_t max_watched = 4;

template <class Map, class V>
struct Crossing {
  typename Map::template State<V> before, after;  // before: only where a section needs it
  ops::mask_t<V> lanes;
  long long step;
  int chain;
  int section;
};

struct NoWatch {
  static constexpr bool idle = true;
  std::size_t kept = 0;
};

// One section on a position plane, the iterate's point: its plane, value and direction in locals,
// so that nothing is reloaded from memory between steps. The plane coordinate is picked by a
// select, not an index (node_value's value), and the direction is a constant of the loop. No lane
// mask is needed: a lane that is not alive idles at the origin, whose plane coordinate never
// changes and so never crosses (on AVX2, the 8 masks freed from the 16 registers: +12-20%).
// One branch per step for all the chains (a crossing is rare for each lane but common among
// all), then each chain that crossed packs its crossing lanes, each state coordinate i from
// staged + i · room and then each lane's id from staged + size · room (its step in the chunk ·
// K·W + its chain · W + its lane): a branch per chain there, rather than every chain packing
// none (AVX-512 +10-20%, AVX2 within noise).
template <class Map, class V, int K, int direction>
struct DenseWatch {
  using State = typename Map::template State<V>;
  static constexpr bool idle = false;
  static constexpr std::size_t W = ops::lanes<V>, size = std::tuple_size_v<State>;
  const typename Map::Coeffs* c;
  ops::mask_t<V> second;  // the plane is q2's
  V value;
  double* staged;
  std::size_t room;
  std::size_t kept = 0;
  V previous[K] = {};
  ops::mask_t<V> crossing[K] = {};

  V plane(const State& x) const {
    const auto q = Map::position(*c, x);
    return ops::select(second, q[1], q[0]);
  }
  void start(const State (&w)[K]) {
    for (int k = 0; k < K; ++k) previous[k] = plane(w[k]);
  }
  void before(int, const State&) {}
  void after(int k, long long, const State& x) {
    const V now = plane(x);
    crossing[k] = crosses(value, direction, previous[k], now);
    previous[k] = now;
  }
  void after_chains(long long j, const State (&w)[K]) {
    ops::mask_t<V> any = crossing[0];
    for (int k = 1; k < K; ++k) any = any | crossing[k];
    if (!ops::any(any)) return;
    const V step_id(static_cast<double>((j + 1) * K * static_cast<long long>(W)));
    const V lane = ops::lane_index<V>();
#pragma GCC unroll 8
    for (int k = 0; k < K; ++k) {
      if (!ops::any(crossing[k])) continue;
      double* at = staged + kept;
      for (std::size_t i = 0; i < size; ++i) ops::compress(at + i * room, crossing[k], w[k][i]);
      kept += ops::compress(at + size * room, crossing[k],
                            step_id + V(static_cast<double>(k * static_cast<int>(W))) + lane);
    }
  }
};

// Sections whose crossings are kept one by one (Crossing), from `first`, the chunk's first step:
// one on a position plane that interpolates (the plane by a select, as DenseWatch's), or several,
// or one on a momentum or time plane (each plane from node_value).
template <class Map, class V, int K>
struct KeptCrossings {
  using State = typename Map::template State<V>;
  const typename Map::Coeffs* c;
  Crossing<Map, V>* crossings;
  long long first;
  std::size_t kept = 0;

  void keep(ops::mask_t<V> lanes, const State& before, const State& after, int k, long long j,
            int section, bool keep_before) {
    auto& x = crossings[kept++];
    if (keep_before) x.before = before;
    x.after = after;
    x.lanes = lanes;
    x.step = first + j + 1;
    x.chain = k;
    x.section = section;
  }
};

template <class Map, class V, int K, int direction>
struct PositionWatch : KeptCrossings<Map, V, K> {
  using State = typename Map::template State<V>;
  static constexpr bool idle = false;
  ops::mask_t<V> second;
  V value;
  V previous[K] = {};
  State before_step{};

  V plane(const State& x) const {
    const auto q = Map::position(*this->c, x);
    return ops::select(second, q[1], q[0]);
  }
  void start(const State (&w)[K]) {
    for (int k = 0; k < K; ++k) previous[k] = plane(w[k]);
  }
  void before(int, const State& x) { before_step = x; }
  void after(int k, long long j, const State& x) {
    const V now = plane(x);
    const ops::mask_t<V> crossing = crosses(value, direction, previous[k], now);
    if (ops::any(crossing)) [[unlikely]]
      this->keep(crossing, before_step, x, k, j, 0, true);
    previous[k] = now;
  }
  void after_chains(long long, const State (&)[K]) {}
};

template <class Map, class V, int K, bool keep_before>
struct PlanesWatch : KeptCrossings<Map, V, K> {
  using State = typename Map::template State<V>;
  static constexpr bool idle = false;
  const Section* const* sections;
  std::size_t count;
  const ops::mask_t<V>* alive;  // [K]
  V previous[K][max_watched] = {};
  State before_step{};

  void start(const State (&w)[K]) {
    for (int k = 0; k < K; ++k)
      for (std::size_t i = 0; i < count; ++i)
        previous[k][i] = node_value<Map>(*this->c, w[k], sections[i]->plane);
  }
  void before(int, const State& x) {
    if constexpr (keep_before) before_step = x;
  }
  void after(int k, long long j, const State& x) {
    for (std::size_t i = 0; i < count; ++i) {
      const V now = node_value<Map>(*this->c, x, sections[i]->plane);
      const ops::mask_t<V> crossing = crosses(*sections[i], previous[k][i], now) & alive[k];
      if (ops::any(crossing)) [[unlikely]]
        this->keep(crossing, before_step, x, k, j, static_cast<int>(i), keep_before);
      previous[k][i] = now;
    }
  }
  void after_chains(long long, const State (&)[K]) {}
};

}  // namespace detail

// The sections of a block of K chains from orbit `first`: watched inside its chunks (up to
// detail::max_watched) or checked step by step. Each chunk's crossings go to one buffer per
// thread, kept across blocks and sized for the most a chunk of `chunk_steps` can have: it grows
// only on a thread's first blocks.
template <class Map, class V, int K>
class BlockSections {
  using State = typename Map::template State<V>;
  using Mask = ops::mask_t<V>;
  static constexpr std::size_t W = ops::lanes<V>, size = std::tuple_size_v<State>;

 public:
  BlockSections(const typename Map::Coeffs& c, Observers* observers, std::size_t first,
                long long chunk_steps)
      : c_(c),
        sections_(observers ? &observers->sections : nullptr),
        first_(first),
        momentum_(observers && observers->sections_need_momentum()) {
    if (!sections_ || sections_->empty()) sections_ = nullptr;
    before_stale_ = sections_ != nullptr;
    if (!sections_ || sections_->size() > detail::max_watched) return;
    for (const auto& section : *sections_) {
      watched_[count_++] = &section;
      keep_before_ = keep_before_ || section.needs_before();
    }
    const auto steps = static_cast<std::size_t>(chunk_steps);
    if (lane_dense()) {
      room_ = (steps * K + 1) * W;  // every lane of every step of a chunk, and a batch more
      auto& staged = buffers().staged;
      if (staged.size() < room_ * (size + 1)) staged = AlignedArray<double>(room_ * (size + 1));
      staged_ = staged.data();
    } else {
      auto& crossings = buffers().crossings;
      if (crossings.size() < steps * K * count_) crossings.resize(steps * K * count_);
      crossings_ = crossings.data();
    }
  }

  // Whether the sections must be checked step by step: too many to watch in a chunk.
  bool step_by_step() const { return sections_ && count_ == 0; }
  // Whether a chunk watches them (through watching()).
  bool watched() const { return count_ > 0; }

  // Calls f(watch) with the chunk's watch from step `chunk_first`, and keeps its crossings' count.
  template <class F>
  [[gnu::always_inline]] bool watching(const Mask (&alive)[K], long long chunk_first, F&& f) {
    if (count_ == 0) {
      detail::NoWatch none;
      return f(none);
    }
    const Section& section = *watched_[0];
    const Mask second = V(section.plane == Coordinate::q2 ? 1.0 : 0.0) != V(0.0);
    const V value(section.value);
    const auto by_direction = [&]<template <class, class, int, int> class Watch>(auto... fields) {
      const auto run = [&]<int direction>() {
        Watch<Map, V, K, direction> watch{fields...};
        const bool suspect = f(watch);
        crossed_ = watch.kept;
        return suspect;
      };
      if (section.direction > 0) return run.template operator()<1>();
      if (section.direction < 0) return run.template operator()<-1>();
      return run.template operator()<0>();
    };
    if (lane_dense())
      return by_direction.template operator()<detail::DenseWatch>(&c_, second, value, staged_,
                                                                  room_);
    const detail::KeptCrossings<Map, V, K> kept{&c_, crossings_, chunk_first};
    if (count_ == 1 && is_position(section.plane))
      return by_direction.template operator()<detail::PositionWatch>(kept, second, value);
    const auto planes = [&]<bool keep_before>() {
      detail::PlanesWatch<Map, V, K, keep_before> watch{kept, watched_, count_, alive};
      const bool suspect = f(watch);
      crossed_ = watch.kept;
      return suspect;
    };
    return keep_before_ ? planes.template operator()<true>() : planes.template operator()<false>();
  }

  // The crossings a clean chunk from step `chunk_first` kept, recorded as check_sections records
  // them.
  [[gnu::flatten]] void record(long long chunk_first) {
    if (count_ == 0) return;
    before_stale_ = true;
    if (lane_dense())
      record_dense(chunk_first);
    else
      record_kept();
  }

  // Step by step: the sections crossed by chain k from its node before to node n (its state s).
  [[gnu::flatten]] void check(int k, const State& s, Mask alive, long long n) {
    if (sections_)
      check_sections<Map>(c_, s, alive, *sections_, momentum_, first_ + k * W, n, before_[k]);
  }
  // The chains' nodes before the next step checked step by step, from their states s: computed
  // only when such a step comes (a watched chunk needs none, and with p each is a reversed step).
  [[gnu::flatten]] void refresh_before(const State (&s)[K]) {
    if (!before_stale_) return;
    for (int k = 0; k < K; ++k) before_[k] = node_values<Map>(c_, s[k], momentum_);
    before_stale_ = false;
  }

 private:
  struct Buffers {
    std::vector<detail::Crossing<Map, V>> crossings;
    AlignedArray<double> staged;
    std::vector<CrossingLanes<V>> prepared;  // record_kept's first pass, one per crossing
  };
  static Buffers& buffers() {
    thread_local Buffers buffers;
    return buffers;
  }
  bool lane_dense() const {
    return count_ == 1 && !keep_before_ && is_position(watched_[0]->plane);
  }

  // A batch of packed lanes at a time; the last batch's first lanes.
  void record_dense(long long chunk_first) {
    Section& section = (*sections_)[0];
    constexpr std::size_t chunk_lanes = K * W;
    for (std::size_t i = 0; i < crossed_; i += W) {
      State after;
      for (std::size_t k = 0; k < size; ++k) after[k] = ops::load<V>(staged_ + k * room_ + i);
      const Mask lanes = ops::lane_index<V>() < V(static_cast<double>(crossed_ - i));
      const auto values = node_values<Map>(c_, after, momentum_);
      const auto id = ops::integer_lanes(ops::load<V>(staged_ + size * room_ + i));
      const auto orbit_of = [&](std::size_t l) { return first_ + id[l] % chunk_lanes; };
      const auto step_of = [&](std::size_t l) {
        return chunk_first + static_cast<long long>(id[l] / chunk_lanes);
      };
      keep_lanes(section, crossing_lanes<Map>(c_, section, lanes, values, values), orbit_of,
                 step_of);
    }
  }
  // First every crossing's points and slots in V, then the lanes one by one (two passes, so that
  // the lanes' scalar reads do not wait on the stores just made of them).
  void record_kept() {
    auto& prepared = buffers().prepared;
    if (prepared.size() < crossed_) prepared.resize(crossed_);
    for (std::size_t i = 0; i < crossed_; ++i) {
      const auto& x = crossings_[i];
      Section& section = (*sections_)[static_cast<std::size_t>(x.section)];
      const auto after = node_values<Map>(c_, x.after, momentum_);
      prepared[i] = crossing_lanes<Map>(
          c_, section, x.lanes,
          section.needs_before() ? node_values<Map>(c_, x.before, momentum_) : after, after);
    }
    for (std::size_t i = 0; i < crossed_; ++i) {
      const auto& x = crossings_[i];
      keep_lanes((*sections_)[static_cast<std::size_t>(x.section)], prepared[i],
                 first_ + x.chain * W, x.step);
    }
  }

  const typename Map::Coeffs& c_;
  std::vector<Section>* sections_;
  std::size_t first_;
  bool momentum_;  // any section reads p
  std::size_t count_ = 0;  // watched in chunks (0: none, or step by step)
  const Section* watched_[detail::max_watched] = {};
  bool keep_before_ = false;  // a section's point needs the state before the crossing too
  detail::Crossing<Map, V>* crossings_ = nullptr;
  double* staged_ = nullptr;
  std::size_t room_ = 0;
  std::size_t crossed_ = 0;  // in the last chunk
  std::array<V, 5> before_[K];
  bool before_stale_;
};

}  // namespace qmaps
