#pragma once
// Tangent<Map, D>: a map together with D deviation vectors and their chaos sums (core/chaos.hpp),
// as one map whose state is the whole record:
//
//   [ state (S) | deviation 0 (S) | … | deviation D−1 (S) | base, Σ L, FLI, Σ Y, n | D = 9:
//     Σ ln r_1 … Σ ln r_4, steps left to the next orthonormalization ]
//
// D = 1: λ, FLI and MEGNO; D = 9: also the spectrum (deviations 1–4) and GALI_2, GALI_4
// (deviations 5–8). Its step is the map's own step on Dual values, then the sums' update. Since
// it is a map like the others, the runner advances it on every path with the same escapes,
// sections, densities and invariants, checkpoints hold its record, and the scalar reference and
// every ISA give the same bits. Everything of the orbit itself (position, phase, invariants,
// escape measure, time) is the map's, of the state part.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <limits>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

#include "core/chaos.hpp"
#include "core/error.hpp"
#include "core/map_concept.hpp"

namespace qmaps {

// The longest a run may wait between orthonormalizations of the spectrum's deviations.
inline constexpr long long max_orthonormalize_every = 1000;

// GALI_k of the four vectors (4 components each) normalized: the product of the k largest
// singular values of the matrix of the first k (Eigen's SVD; core/gali.cpp).
double gali(const std::array<std::array<double, 4>, 4>& vectors, int k);

// A formula map's Definition, which its tangent takes too.
template <class Map, bool = DefinedAtRunTime<Map>>
struct DefinitionOf {};
template <class Map>
struct DefinitionOf<Map, true> {
  using Definition = typename Map::Definition;
};

template <class Map, std::size_t D>
struct Tangent : DefinitionOf<Map> {
  static_assert(D == 1 || D == 9, "one deviation (lambda, FLI, MEGNO) or nine (all)");
  static constexpr std::size_t S = Map::state_names.size();
  static constexpr std::size_t sums_at = S * (1 + D);
  static constexpr std::size_t size = sums_at + (D == 1 ? 5 : 10);
  static constexpr bool spectrum = D == 9;

  static constexpr auto name = Map::name;
  static constexpr auto summary = Map::summary;
  static constexpr auto equations = Map::equations;
  static constexpr auto invariant_summary = Map::invariant_summary;
  static constexpr auto params = Map::params;
  static constexpr std::size_t max_invariants = Map::max_invariants;
  static constexpr bool time_per_orbit = Map::time_per_orbit;
  static constexpr auto clock_state = [] {  // the base state's components come first
    if constexpr (Map::time_per_orbit)
      return Map::clock_state;
    else
      return std::array<std::size_t, 0>{};
  }();
  static constexpr bool reports_faults = Map::reports_faults;
  static constexpr MapFacts facts = Map::facts;
  // Its record fills the registers: blocks of one chain (the runner clamps). More spill (measured:
  // Suris, one deviation, AVX-512, 2 threads, 8.3–8.9e8 particle-steps/s with 1 chain against
  // 7.4–7.5e8 with 2) and multiply the build's time.
  static constexpr int max_chains = 1;

  template <class V>
  using State = std::array<V, size>;
  template <class V>
  using Base = typename Map::template State<V>;

  struct Coeffs {
    typename Map::Coeffs map;
    double every;  // steps between orthonormalizations of the spectrum's deviations
  };
  // `extra`: what the map's own coefficients take (a formula map's definition).
  template <class... Extra>
  static Coeffs coefficients(std::span<const double> values, long long every = 10,
                             const Extra&... extra) {
    if (every < 1 || every > max_orthonormalize_every)
      throw usage_error("[chaos] orthonormalize_every: " + std::to_string(every) +
                        " is not in 1 … " + std::to_string(max_orthonormalize_every));
    return {Map::coefficients(values, extra...), static_cast<double>(every)};
  }
  template <class... Extra>
  static MapIdentity identity(long long, const Extra&... extra)
    requires DefinedAtRunTime<Map>
  {
    MapIdentity id = Map::identity(extra...);
    id.state_names = record_names(id.state_names);
    return id;
  }
  static auto formulas(const Coeffs& c)
    requires requires { Map::formulas(c.map); }
  {
    return Map::formulas(c.map);
  }
  static auto continuous(const Coeffs& c) { return Map::continuous(c.map); }
  static std::vector<std::string> invariant_names(const Coeffs& c) {
    return Map::invariant_names(c.map);
  }

  // The state's names, then "w<j>.<name>" for each deviation, then the sums'.
  static std::vector<std::string> record_names(const std::vector<std::string>& base) {
    std::vector<std::string> text(size);
    for (std::size_t k = 0; k < S; ++k) {
      text[k] = base[k];
      for (std::size_t j = 0; j < D; ++j) {
        char name[80];
        std::snprintf(name, sizeof name, "w%zu.%.64s", j, base[k].c_str());
        text[S * (1 + j) + k] = name;
      }
    }
    const char* sums[] = {"chaos.log_base",       "chaos.log_sum",        "chaos.fli",
                          "chaos.megno_sum",      "chaos.steps",          "chaos.spectrum_log_1",
                          "chaos.spectrum_log_2", "chaos.spectrum_log_3", "chaos.spectrum_log_4",
                          "chaos.steps_to_orthonormalize"};
    for (std::size_t k = sums_at; k < size; ++k) text[k] = sums[k - sums_at];
    return text;
  }
  static const std::array<std::string_view, size>& names() {
    static const auto storage = record_names({Map::state_names.begin(), Map::state_names.end()});
    static const auto views = [] {
      std::array<std::string_view, size> v;
      for (std::size_t k = 0; k < size; ++k) v[k] = storage[k];
      return v;
    }();
    return views;
  }
  static inline const std::array<std::string_view, size>& state_names = names();

  // The indicators this record gives, in the order indicators() writes them.
  static std::vector<std::string> indicator_names() {
    std::vector<std::string> out = {"lyapunov", "fli", "megno"};
    if constexpr (spectrum)
      out.insert(out.end(), {"lyapunov_1", "lyapunov_2", "lyapunov_3", "lyapunov_4", "gali_2",
                             "gali_4"});
    return out;
  }

  // One step. Nine deviations' step is compiled once, out of line: inlined into each of the
  // runner's loops it would multiply the build's time for no measurable gain.
  template <class V>
  static auto step(const Coeffs& c, State<V>& s) {
    if constexpr (spectrum) {
      const V fault = step_apart(c, s);
      if constexpr (reports_faults) return fault;
    } else {
      const V fault = step_inline(c, s);
      if constexpr (reports_faults) return fault;
    }
  }

 private:
  template <class V>
  [[gnu::noinline]] static V step_apart(const Coeffs& c, State<V>& s) { return step_inline(c, s); }
  template <class V>
  [[gnu::always_inline]] static V step_inline(const Coeffs& c, State<V>& s) {
    Base<V> x;
    std::array<Base<V>, D> w;
    unpack(s, x, w);
    const V fault = tangent_step<Map, D>(c.map, x, w);
    Growth<V> growth = growth_of(s);
    growth.add_step(w[0]);
    if constexpr (spectrum) {
      V& left = s[sums_at + 9];
      left = left - V(1.0);
      const auto due = left == V(0.0);  // lanes parked at 0 go negative and never come due
      if (ops::any(due)) {
        std::array<Base<V>, 4> vectors;
        std::copy(w.begin() + 1, w.begin() + 5, vectors.begin());
        std::array<V, 4> norms;
        gram_schmidt(vectors, norms, due);
        for (std::size_t i = 0; i < 4; ++i) {
          w[1 + i] = vectors[i];
          V& log_sum = s[sums_at + 5 + i];
          log_sum = ops::select(due, log_sum + ops::log(norms[i]), log_sum);
          normalize(w[5 + i], due);
        }
        left = ops::select(due, V(c.every), left);
      }
    }
    pack(x, w, growth, s);
    return fault;
  }

 public:

  template <class V>
  static V escape_measure(const State<V>& s) { return Map::escape_measure(base(s)); }
  template <class V>
  static void invariants(const Coeffs& c, const State<V>& s, V* out) {
    Map::invariants(c.map, base(s), out);
  }
  template <class V>
  static std::array<V, 2> position(const Coeffs& c, const State<V>& s) {
    return Map::position(c.map, base(s));
  }
  template <class V>
  static std::array<V, 4> phase(const Coeffs& c, const State<V>& s) {
    return Map::phase(c.map, base(s));
  }
  static Phase to_phase_space(const Coeffs& c, const State<double>& s) {
    return Map::to_phase_space(c.map, base(s));
  }
  static double time(const Coeffs& c, long long n, const State<double>& s) {
    return Map::time(c.map, n, base(s));
  }
  template <class V>
  static V clock(const State<V>& s)
    requires Map::time_per_orbit
  {
    return Map::clock(base(s));
  }
  template <class V>
  static std::array<V, 4> to_plane(const Coeffs& c, const std::array<V, 4>& x, std::size_t k, V ds)
    requires FlowsToPlane<Map>
  {
    return Map::to_plane(c.map, x, k, ds);
  }
  // The state reversed; the deviations and sums stay as they are.
  template <class V>
  static State<V> reversed(const Coeffs& c, const State<V>& s) {
    State<V> r = s;
    const auto x = Map::reversed(c.map, base(s));
    std::copy(x.begin(), x.end(), r.begin());
    return r;
  }

  // The record that starts at x: w_0 = (1, 1, 1, 1)/2 on the phase-space part, the spectrum's and
  // GALIs' deviations the unit vectors; no step yet.
  static State<double> from_phase_space(const Coeffs& c, const Phase& x, Start start) {
    State<double> s{};
    const auto b = Map::from_phase_space(c.map, x, start);
    std::copy(b.begin(), b.end(), s.begin());
    for (std::size_t k = 0; k < 4; ++k) {
      s[S + k] = 0.5;
      if constexpr (spectrum) s[S * (2 + k) + k] = s[S * (6 + k) + k] = 1.0;
    }
    if constexpr (spectrum) s[sums_at + 9] = c.every;
    return s;
  }

  // Why a record read back (a checkpoint's, a file's final state) cannot be one this map wrote,
  // or nullptr: n a whole number ≥ 0, deviations of positive finite norm, the steps left to the
  // next orthonormalization a whole number in 1 … every.
  static const char* invalid(const Coeffs& c, const State<double>& s) {
    const double steps = s[sums_at + 4];
    if (!(steps >= 0 && steps <= 0x1p53 && steps == std::floor(steps)))
      return "its chaos record's step count is not a whole number >= 0";
    Base<double> x;
    std::array<Base<double>, D> w;
    unpack(s, x, w);
    for (const auto& v : w)
      if (const double r2 = phase_dot(v, v); !(r2 > 0 && r2 < HUGE_VAL))
        return "a deviation vector of its chaos record has norm 0 or not finite";
    if constexpr (spectrum) {
      const double left = s[sums_at + 9];
      if (!(left >= 1 && left <= c.every && left == std::floor(left)))
        return "its chaos record's steps to the next orthonormalization are not in 1 ... every";
    }
    return nullptr;
  }

  // The indicators of one record, as indicator_names() lists them (λ's per step).
  static void indicators(const Coeffs&, const State<double>& s, double* out) {
    Base<double> x;
    std::array<Base<double>, D> w;
    unpack(s, x, w);
    const Growth<double> growth = growth_of(s);
    out[0] = growth.lyapunov(growth.log_growth(w[0]));
    out[1] = growth.fli;
    out[2] = growth.megno();
    if constexpr (spectrum) {
      std::array<Base<double>, 4> vectors;
      std::copy(w.begin() + 1, w.begin() + 5, vectors.begin());
      std::array<double, 4> norms;
      gram_schmidt(vectors, norms, true);
      for (std::size_t i = 0; i < 4; ++i)
        out[3 + i] = (s[sums_at + 5 + i] + ops::log(norms[i])) / growth.steps;
      std::array<std::array<double, 4>, 4> unit;
      for (std::size_t i = 0; i < 4; ++i) {
        auto v = w[5 + i];
        normalize(v, true);
        std::copy(v.begin(), v.begin() + 4, unit[i].begin());
      }
      out[7] = gali(unit, 2);
      out[8] = gali(unit, 4);
    }
    if (growth.steps == 0)  // before the first step the rates are not defined
      for (std::size_t k : {0, 2, 3, 4, 5, 6})
        if (k < indicator_names().size()) out[k] = std::numeric_limits<double>::quiet_NaN();
  }

 private:
  template <class V>
  static Base<V> base(const State<V>& s) {
    Base<V> x;
    std::copy(s.begin(), s.begin() + S, x.begin());
    return x;
  }
  template <class V>
  static void unpack(const State<V>& s, Base<V>& x, std::array<Base<V>, D>& w) {
    std::copy(s.begin(), s.begin() + S, x.begin());
    for (std::size_t j = 0; j < D; ++j)
      std::copy(s.begin() + S * (1 + j), s.begin() + S * (2 + j), w[j].begin());
  }
  template <class V>
  static Growth<V> growth_of(const State<V>& s) {
    return {s[sums_at], s[sums_at + 1], s[sums_at + 2], s[sums_at + 3], s[sums_at + 4]};
  }
  template <class V>
  static void pack(const Base<V>& x, const std::array<Base<V>, D>& w, const Growth<V>& g,
                   State<V>& s) {
    std::copy(x.begin(), x.end(), s.begin());
    for (std::size_t j = 0; j < D; ++j) std::copy(w[j].begin(), w[j].end(), s.begin() + S * (1 + j));
    s[sums_at] = g.base;
    s[sums_at + 1] = g.sum;
    s[sums_at + 2] = g.fli;
    s[sums_at + 3] = g.megno_sum;
    s[sums_at + 4] = g.steps;
  }
};

// The map with D deviations; D = 0: the map alone.
template <class Map, std::size_t D>
using WithDeviations = std::conditional_t<D == 0, Map, Tangent<Map, D>>;

}  // namespace qmaps
