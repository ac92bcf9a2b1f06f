#pragma once
// Lanes residues mod p, p < 2^26, in one value: the finite-field orbits' type (orbits.cpp), on
// which a map's step runs over many orbits at once. Each residue is an exact integer held in a
// double, so that the loops below compile to the processor's vector instructions:
//   a·b < 2^52 is exact, q = a·b/p rounded to nearest (by adding and subtracting 2^52) is the
//   quotient or one more, and a·b − q·p, exact, lies in (−p, p): one p added where it is negative.
// A lane whose denominator vanished is NaN and stays NaN through every later operation: the orbit
// met a point where the map is not defined. Inverses come from a table (p ≤ 2^20) or as a^(p−2).
// A correction is the select of a constant (0 or p) added, so that no operation that may raise a
// floating-point exception is executed conditionally, and the loops vectorize.
#include <array>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "core/ops.hpp"
#include "integrability/field.hpp"

namespace qmaps::exact {

inline constexpr std::uint64_t max_lane_prime = (1ULL << 26) - 1;

// The thread's prime for ResidueLanes while in scope (with its PrimeField, for the constants).
class LaneField {
 public:
  explicit LaneField(std::uint64_t p);
  ~LaneField();
  LaneField(const LaneField&) = delete;
  LaneField& operator=(const LaneField&) = delete;
  static const LaneField& get() { return *current_; }
  double p, inverse_p;
  std::vector<double> inverses;  // of 0 … p − 1 (0's: NaN), where p ≤ 2^20
  double constant(double x) const;      // x's residue (a cached PrimeField::reduce)

 private:
  PrimeField field_;
  mutable std::array<std::uint64_t, 64> cached_bits_;
  mutable std::array<double, 64> cached_;
  const LaneField* outer_;
  static thread_local const LaneField* current_;
};

template <std::size_t W>
struct ResidueLanes {
  static constexpr std::size_t lanes = W;
  alignas(64) std::array<double, W> v;

  ResidueLanes() = default;
  explicit ResidueLanes(double x) { v.fill(LaneField::get().constant(x)); }

  friend ResidueLanes operator+(const ResidueLanes& a, const ResidueLanes& b) {
    const double p = LaneField::get().p;
    ResidueLanes r;
    for (std::size_t i = 0; i < W; ++i) {
      const double s = a.v[i] + b.v[i];
      r.v[i] = s - (s >= p ? p : 0.0);
    }
    return r;
  }
  friend ResidueLanes operator-(const ResidueLanes& a, const ResidueLanes& b) {
    const double p = LaneField::get().p;
    ResidueLanes r;
    for (std::size_t i = 0; i < W; ++i) {
      const double s = a.v[i] - b.v[i];
      r.v[i] = s + (s < 0 ? p : 0.0);
    }
    return r;
  }
  friend ResidueLanes operator*(const ResidueLanes& a, const ResidueLanes& b) {
    const LaneField& f = LaneField::get();
    ResidueLanes r;
    for (std::size_t i = 0; i < W; ++i) r.v[i] = times(a.v[i], b.v[i], f.p, f.inverse_p);
    return r;
  }
  friend ResidueLanes operator/(const ResidueLanes& a, const ResidueLanes& b) {
    const LaneField& f = LaneField::get();
    ResidueLanes r;
    if (!f.inverses.empty()) {  // the table, whose entry 0 is NaN: a NaN lane reads it too
      for (std::size_t i = 0; i < W; ++i) {
        const double d = b.v[i] == b.v[i] ? b.v[i] : 0.0;
        r.v[i] = times(a.v[i], f.inverses[static_cast<std::size_t>(d)], f.p, f.inverse_p);
      }
      return r;
    }
    for (std::size_t i = 0; i < W; ++i) {  // b^(p−2)
      double inverse = b.v[i] > 0 ? 1.0 : std::numeric_limits<double>::quiet_NaN(), base = b.v[i];
      for (std::uint64_t e = static_cast<std::uint64_t>(f.p) - 2; e; e >>= 1) {
        if (e & 1) inverse = times(inverse, base, f.p, f.inverse_p);
        base = times(base, base, f.p, f.inverse_p);
      }
      r.v[i] = times(a.v[i], inverse, f.p, f.inverse_p);
    }
    return r;
  }

  static double times(double a, double b, double p, double inverse_p) {
    constexpr double round = 0x1p52;
    const double x = a * b, q = (x * inverse_p + round) - round, r = x - q * p;
    return r + (r < 0 ? p : 0.0);
  }
};

}  // namespace qmaps::exact

namespace qmaps::ops {
template <std::size_t W>
inline exact::ResidueLanes<W> fma(const exact::ResidueLanes<W>& a, const exact::ResidueLanes<W>& b,
                                  const exact::ResidueLanes<W>& c) {
  return a * b + c;
}
template <std::size_t W>
inline exact::ResidueLanes<W> fms(const exact::ResidueLanes<W>& a, const exact::ResidueLanes<W>& b,
                                  const exact::ResidueLanes<W>& c) {
  return a * b - c;
}
}  // namespace qmaps::ops
