#pragma once
// The tunes, a lane measurement (core/observers/lane_observers.hpp) that records its window's
// states: each orbit's frequencies ν1, ν2 in cycles per step, of the real signals q1(n) and
// q2(n), by NAFF (naff.hpp), over the steps 1 .. N and again over N + 1 .. 2N, and its diffusion
//   D = log10 ‖ν(second) − ν(first)‖   (the norm over the degrees of freedom that have a tune),
// at least log10 2⁻⁵³ (round-off: the two windows agree to the last bit of a tune in [1/4, 1/2)).
// docs/tunes.md. A block's chain records q1, q2 of each step into its thread's scratch (N × 2
// lanes), and the window is analysed when the block reaches its end (reached): the first's line
// searched and refined (naff.hpp), the second's refined from the first's (and searched afresh
// where it is not found within half a bin of it with at least half its amplitude).
// An orbit that escapes within the 2N steps has NaN for all five; a degree of freedom whose
// signal is 0 has no tune (NaN). The windows are never split: a run's segments end outside them.
#include <algorithm>
#include <cstddef>
#include <limits>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/ensemble.hpp"
#include "core/observers/tunes/naff.hpp"
#include "core/observers/tunes/naff_tables.hpp"
#include "core/ops.hpp"
#include "core/run_plan.hpp"

namespace qmaps {

// log10 2⁻⁵³ as every path computes it: the diffusion of an orbit whose tunes did not change.
template <class V = double>
inline V diffusion_floor() {
  return ops::log(V(0x1p-53)) * V(0.434294481903251827651128918916605082);
}

// The configuration table that turns the tunes on, and their columns in order.
struct TuneColumns {
  static constexpr std::string_view key = "tunes";
  enum : std::size_t { nu1, nu2, nu1_second, nu2_second, diffusion, count };
};

template <class Map, class V>
struct Tunes : TuneColumns {
  using Columns = std::span<AlignedArray<double>>;
  using Read = std::span<const AlignedArray<double>>;
  using Mask = ops::mask_t<V>;
  using State = typename Map::template State<V>;
  static constexpr bool records_steps = true;
  static constexpr std::size_t W = ops::lanes<V>;

  static std::vector<ColumnSpec> columns(const typename Map::Coeffs&,
                                         std::span<const std::string> asked) {
    if (std::find(asked.begin(), asked.end(), key) == asked.end()) return {};
    std::vector<ColumnSpec> specs;
    for (const char* name : {"nu1", "nu2", "nu1_second", "nu2_second"})
      specs.push_back({std::string("tunes/") + name, 0.0, true});
    specs.push_back({"tunes/diffusion", diffusion_floor(), true});
    return specs;
  }
  static void start(const typename Map::Coeffs&, const typename Map::template State<double>&,
                    Columns columns, std::size_t orbit) {
    for (auto& column : columns) column[orbit] = std::numeric_limits<double>::quiet_NaN();
  }

  void load(Read columns, std::size_t orbit, const RunPlan& plan, std::size_t chain) {
    for (std::size_t c = 0; c < count; ++c) value[c] = ops::load<V>(&columns[c][orbit]);
    window_ = plan.tunes.window;
    order_ = plan.tunes.order;
    signal_ = window_ > 0 && plan.first < 2 * window_
                  ? naff_scratch(chain, 2 * static_cast<std::size_t>(window_) * W)
                  : nullptr;
  }
  // The last step recorded (0: none), and where a chunk from step n must end.
  long long records_until() const { return signal_ ? 2 * window_ : 0; }
  long long next_stop(long long n) const { return n < window_ ? window_ : 2 * window_; }
  // A step's record: q1, q2 of the lanes, at records_at(step); a window's steps follow each other.
  static constexpr std::size_t record_size = 2 * W;
  double* records_at(long long step) const {
    return signal_ + static_cast<std::size_t>((step - 1) & (window_ - 1)) * record_size;
  }
  static void record(const typename Map::Coeffs& c, const State& x, double* at) {
    const auto q = Map::position(c, x);
    ops::store(at, q[0]);
    ops::store(at + W, q[1]);
  }
  // Every chain of the block is at `step`; its lanes `alive` have not escaped.
  void reached(long long step, Mask alive) {
    if (step == window_ && ops::any(alive)) first_window();
    if (step != 2 * window_) return;
    if (ops::any(alive)) second_window();
    const V nan(std::numeric_limits<double>::quiet_NaN());
    for (V& v : value) v = ops::select(alive, v, nan);
  }
  void store(Columns columns, std::size_t orbit) const {
    for (std::size_t c = 0; c < count; ++c) ops::store(&columns[c][orbit], value[c]);
  }

  V value[count];

 private:
  static constexpr double per_turn = 0.159154943091895335768883763372514362;  // 1/2π
  static Mask finite(V a) { return a == a; }

  void first_window() {
    const auto& t = naff_tables(window_, order_);
    naff::search(signal_, t, omega_);
    Mask active[2] = {finite(omega_[0]), finite(omega_[1])};
    power_[0] = power_[1] = V(0.0);
    naff::refine<naff::Reading::windowing_in_place>(signal_, t, omega_, active, power_);
    value[nu1] = omega_[0] * V(per_turn);
    value[nu2] = omega_[1] * V(per_turn);
  }
  void second_window() {
    const auto& t = naff_tables(window_, order_);
    V omega[2] = {omega_[0], omega_[1]}, power[2] = {V(0.0), V(0.0)};
    Mask active[2] = {finite(omega[0]), finite(omega[1])};
    naff::refine(signal_, t, omega, active, power);
    const V half_bin(naff::pi / static_cast<double>(window_));
    Mask lost[2];
    for (int d = 0; d < 2; ++d) {
      const Mask none_first = ops::negate(finite(omega_[d]));
      const Mask moved = ops::abs(omega[d] - omega_[d]) > half_bin;
      const Mask fainter = V(4.0) * power[d] < power_[d];
      lost[d] = active[d] | none_first | moved | fainter;
    }
    if (ops::any(lost[0] | lost[1])) {
      V fresh[2], fresh_power[2] = {V(0.0), V(0.0)};
      naff::search(signal_, t, fresh);
      Mask again[2];
      for (int d = 0; d < 2; ++d) again[d] = lost[d] & finite(fresh[d]);
      naff::refine(signal_, t, fresh, again, fresh_power);
      for (int d = 0; d < 2; ++d) omega[d] = ops::select(lost[d], fresh[d], omega[d]);
    }
    value[nu1_second] = omega[0] * V(per_turn);
    value[nu2_second] = omega[1] * V(per_turn);
    const V d1 = value[nu1_second] - value[nu1], d2 = value[nu2_second] - value[nu2];
    const Mask has1 = finite(d1), has2 = finite(d2);
    const V squares = ops::select(has1, d1 * d1, V(0.0)) + ops::select(has2, d2 * d2, V(0.0));
    const V floor(0x1p-53);
    const V change = ops::max(ops::sqrt(squares), floor);
    const V nan(std::numeric_limits<double>::quiet_NaN());
    value[diffusion] = ops::select(has1 | has2,
                                   ops::log(change) * V(0.434294481903251827651128918916605082), nan);
  }

  long long window_ = 0;
  int order_ = 2;
  double* signal_ = nullptr;
  V omega_[2], power_[2];  // the first window's lines, while the second is recorded
};

}  // namespace qmaps
