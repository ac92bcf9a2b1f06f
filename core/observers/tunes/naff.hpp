#pragma once
// NAFF (Laskar's numerical analysis of fundamental frequencies) of two real signals x_d(n),
// n = 0 .. N − 1, d = 1, 2, one orbit per lane: with the Hann window of order p (naff_tables.hpp)
//   y_n = w_n x_n,   F(ω) = Σ_n y_n e^{−iωn},
// an orbit's frequency is the ω in [0, π] where |F(ω)|² is largest: the tune ν = ω/2π in [0, 1/2]
// (a real signal's spectrum is even, so ν and −ν are one line). Per lane:
//   search   the line, on the window's first M steps (M = N/4, at least 64) with their own window
//            of order p: the FFT of y_1 + i y_2 (both signals at once), whose bin k holds
//            X_1 = (Z_k + conj Z_{M−k})/2 and X_2 = (Z_k − conj Z_{M−k})/2i; the largest |X_d| over
//            k = 1 .. M/2 − 1, and the ratio r of its larger neighbour to it, which places a pure
//            tone at k ± δ bins, δ = ((p + 1) r − p)/(1 + r) (to O(M⁻²): |X(u)| ∝
//            |sin πu / (u Π_{j≤p} (j² − u²))| at u bins from the tone);
//   refine   Newton's method on g = |F|² over the whole window (windowed in place at its first
//            pass where nothing else reads the signals, the same products): with m = n − (N − 1)/2,
//            the sums F and S1 = Σ m y_n e^{−iωn} by Goertzel's recurrence
//              s_n = 2 cos ω s_{n−1} + (y_n − s_{n−2})
//            (Σ y_n e^{iω(N−1−n)} = s_{N−1} − e^{−iω} s_{N−2}: a phase common to both, which
//            cancels), and g″ as a pure tone's, −2|F|²κ:
//              ω ← ω + (Re F · Im S1 − Im F · Re S1)/(|F|² κ),
//            a step of at most half a bin, folded into [0, π], until the step is below 1e-7 bins.
// Every lane takes its own steps and stops by itself (a select), so that its result is the same on
// every path, whatever lanes share its batch.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>

#include "core/observers/tunes/naff_tables.hpp"
#include "core/ops.hpp"

namespace qmaps::naff {

inline constexpr double pi = 3.14159265358979323846264338327950288;
inline constexpr int most_steps = 24;

// The signals: signal[(2n + d) W + l] is x_{d+1}(n) of lane l. omega: each line, NaN where its
// signal is 0 over the search.
template <class V>
void search(const double* signal, const NaffTables& t, V (&omega)[2]) {
  constexpr std::size_t W = ops::lanes<V>;
  const std::size_t n = t.m;
  double* z = naff_scratch(fft_slot, 2 * n * W);  // Z_k: re at 2kW, im at (2k + 1)W
  V energy[2] = {V(0.0), V(0.0)};
  // radix 2, decimation in time: a ± b·e^{−2πi j/(2 half)}, stage by stage, two stages per pass
  // over z where they can (each pass a load and a store of every point; the same operations in
  // the same order as one stage per pass)
  const auto butterfly = [&](V& ar, V& ai, V& br, V& bi, std::size_t twiddle) {
    const V c(t.cos_twiddle[twiddle]), s(t.sin_twiddle[twiddle]);
    const V tr = ops::fma(br, c, bi * s), ti = ops::fms(bi, c, br * s);
    br = ar - tr;
    bi = ai - ti;
    ar = ar + tr;
    ai = ai + ti;
  };
  // the first two stages (twiddles 1 and −i) straight from the windowed signal: z's point p is
  // input reversed[p] (the bit reversal is its own inverse)
  for (std::size_t i = 0; i < n; i += 4) {
    V re[4], im[4];
    for (std::size_t q = 0; q < 4; ++q) {
      const std::size_t r = t.reversed[i + q];
      const V w(t.search_weight[r]);
      re[q] = w * ops::load<V>(signal + 2 * r * W);
      im[q] = w * ops::load<V>(signal + (2 * r + 1) * W);
      energy[0] = energy[0] + re[q] * re[q];
      energy[1] = energy[1] + im[q] * im[q];
    }
    const V s0r = re[0] + re[1], s0i = im[0] + im[1];
    const V d0r = re[0] - re[1], d0i = im[0] - im[1];
    const V s1r = re[2] + re[3], s1i = im[2] + im[3];
    const V d1r = re[2] - re[3], d1i = im[2] - im[3];  // times −i: (d1i, −d1r)
    double* at = z + 2 * i * W;
    ops::store(at, s0r + s1r);
    ops::store(at + W, s0i + s1i);
    ops::store(at + 4 * W, s0r - s1r);
    ops::store(at + 5 * W, s0i - s1i);
    ops::store(at + 2 * W, d0r + d1i);
    ops::store(at + 3 * W, d0i - d1r);
    ops::store(at + 6 * W, d0r - d1i);
    ops::store(at + 7 * W, d0i + d1r);
  }
  std::size_t half = 4;
  for (; 2 * half < n; half *= 4) {  // the stages half and 2·half in one pass
    const std::size_t first = n / (2 * half), second = n / (4 * half);  // their twiddles' strides
    for (std::size_t i = 0; i < n; i += 4 * half)
      for (std::size_t j = 0; j < half; ++j) {
        double* at[4];
        V re[4], im[4];
        for (std::size_t q = 0; q < 4; ++q) {
          at[q] = z + 2 * (i + j + q * half) * W;
          re[q] = ops::load<V>(at[q]);
          im[q] = ops::load<V>(at[q] + W);
        }
        butterfly(re[0], im[0], re[1], im[1], j * first);
        butterfly(re[2], im[2], re[3], im[3], j * first);
        butterfly(re[0], im[0], re[2], im[2], j * second);
        butterfly(re[1], im[1], re[3], im[3], (j + half) * second);
        for (std::size_t q = 0; q < 4; ++q) {
          ops::store(at[q], re[q]);
          ops::store(at[q] + W, im[q]);
        }
      }
  }
  if (half < n)  // the last stage alone
    for (std::size_t j = 0; j < half; ++j) {
      double* a = z + 2 * j * W;
      double* b = z + 2 * (j + half) * W;
      V ar = ops::load<V>(a), ai = ops::load<V>(a + W), br = ops::load<V>(b), bi = ops::load<V>(b + W);
      butterfly(ar, ai, br, bi, j);
      ops::store(a, ar);
      ops::store(a + W, ai);
      ops::store(b, br);
      ops::store(b + W, bi);
    }
  // 4|X_d|² at bin k, of a batch or of one lane's values
  const auto powers = [](auto kr, auto ki, auto mr, auto mi, int d) {
    return d == 0 ? (kr + mr) * (kr + mr) + (ki - mi) * (ki - mi)
                  : (kr - mr) * (kr - mr) + (ki + mi) * (ki + mi);
  };
  const auto at = [&](std::size_t k, std::size_t part) { return ops::load<V>(z + (2 * k + part) * W); };
  V best[2] = {V(-1.0), V(-1.0)}, bin[2] = {V(0.0), V(0.0)};
  for (std::size_t k = 1; k < n / 2; ++k) {
    const std::size_t m = n - k;
    for (int d = 0; d < 2; ++d) {
      const V p = powers(at(k, 0), at(k, 1), at(m, 0), at(m, 1), d);
      const auto higher = p > best[d];
      best[d] = ops::select(higher, p, best[d]);
      bin[d] = ops::select(higher, V(static_cast<double>(k)), bin[d]);
    }
  }
  const int p = t.order;
  for (int d = 0; d < 2; ++d) {
    const auto bins = ops::integer_lanes(bin[d]);
    const auto energies = ops::lanes_of(energy[d]);
    alignas(64) std::array<double, W> found;
    for (std::size_t l = 0; l < W; ++l) {
      const auto amplitude = [&](std::size_t k) {
        const std::size_t m = (n - k) & (n - 1);
        const auto value = [&](std::size_t i, std::size_t part) { return z[(2 * i + part) * W + l]; };
        return std::sqrt(powers(value(k, 0), value(k, 1), value(m, 0), value(m, 1), d));
      };
      const std::size_t k = bins[l];
      const double here = amplitude(k), left = amplitude(k - 1), right = amplitude(k + 1);
      const double r = std::max(left, right) / here;
      const double delta = ((p + 1) * r - p) / (1 + r);
      found[l] = energies[l] > 0 ? 2 * pi * (static_cast<double>(k) + (right >= left ? delta : -delta)) /
                                       static_cast<double>(n)
                                 : std::numeric_limits<double>::quiet_NaN();
    }
    omega[d] = ops::load<V>(found.data());
  }
}

// How refine reads the signals: times the window at every pass (they stay as recorded), or
// times the window once, written back in place at the first pass and read so afterwards (where
// nothing else reads them: the same products, and no pass of its own over memory).
enum class Reading { windowing_each_pass, windowing_in_place };

// Newton's steps over the whole window from omega on the lanes `active`, each lane until its
// step is below the tolerance or after most_steps; active then holds those that had not
// converged, and power |F|² where each lane was last evaluated.
template <Reading reading = Reading::windowing_each_pass, class V>
void refine(double* signal, const NaffTables& t, V (&omega)[2], ops::mask_t<V> (&active)[2],
            V (&power)[2]) {
  constexpr std::size_t W = ops::lanes<V>;
  const auto n = static_cast<std::size_t>(t.n);
  const double bin = 2 * pi / static_cast<double>(t.n);
  const V limit(bin / 2), tolerance(bin * 1e-7), half_turn(pi), turn(2 * pi), kappa(t.curvature);
  const auto at = [&](std::size_t i, int d) { return signal + (2 * i + static_cast<std::size_t>(d)) * W; };
  const auto windowing = [&](std::size_t i, int d) { return V(t.weight[i]) * ops::load<V>(at(i, d)); };
  const auto windowing_in_place = [&](std::size_t i, int d) {
    const V y = V(t.weight[i]) * ops::load<V>(at(i, d));
    ops::store(at(i, d), y);
    return y;
  };
  const auto windowed = [&](std::size_t i, int d) { return ops::load<V>(at(i, d)); };
  for (int step = 0; step < most_steps && ops::any(active[0] | active[1]); ++step) {
    V s[2], c[2], k[2];
    for (int d = 0; d < 2; ++d) {
      ops::sin_cos(omega[d], s[d], c[d]);
      k[d] = c[d] + c[d];
    }
    // Goertzel's states of y (f) and of m y (g): s_{n−1} in f1, g1 and s_{n−2} in f2, g2 at even
    // n. Two steps per iteration, each writing s_n over s_{n−2}: nothing moves. s_{n−2} is
    // subtracted first, off the chain through s_{n−1}: one fma per step on it.
    V f1[2] = {V(0.0), V(0.0)}, f2[2] = {V(0.0), V(0.0)};
    V g1[2] = {V(0.0), V(0.0)}, g2[2] = {V(0.0), V(0.0)};
    const auto pass = [&](auto input) {
      V m(-0.5 * static_cast<double>(n - 1));  // exact: a half-integer
      for (std::size_t i = 0; i < n; i += 2) {
        const V next_m = m + V(1.0);
        for (int d = 0; d < 2; ++d) {
          const V y = input(i, d);
          f2[d] = ops::fma(k[d], f1[d], y - f2[d]);
          g2[d] = ops::fma(k[d], g1[d], ops::fms(m, y, g2[d]));
        }
        for (int d = 0; d < 2; ++d) {
          const V y = input(i + 1, d);
          f1[d] = ops::fma(k[d], f2[d], y - f1[d]);
          g1[d] = ops::fma(k[d], g2[d], ops::fms(next_m, y, g1[d]));
        }
        m = m + V(2.0);
      }
    };
    if (reading == Reading::windowing_each_pass) pass(windowing);
    else if (step == 0) pass(windowing_in_place);
    else pass(windowed);
    for (int d = 0; d < 2; ++d) {
      const V fr = f1[d] - c[d] * f2[d], fi = s[d] * f2[d];
      const V gr = g1[d] - c[d] * g2[d], gi = s[d] * g2[d];
      const V slope = fr * gi - fi * gr;  // g′/2
      const V now = fr * fr + fi * fi;
      V move = slope / (now * kappa);
      move = ops::min(ops::max(move, ops::neg(limit)), limit);
      V next = ops::abs(omega[d] + move);
      next = ops::select(next > half_turn, turn - next, next);
      power[d] = ops::select(active[d], now, power[d]);
      omega[d] = ops::select(active[d], next, omega[d]);
      active[d] = active[d] & (ops::abs(move) > tolerance);
    }
  }
}

}  // namespace qmaps::naff
