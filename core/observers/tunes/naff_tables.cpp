#include "core/observers/tunes/naff_tables.hpp"

#include <algorithm>
#include <array>
#include <bit>

#include "core/aligned_array.hpp"
#include "core/ops.hpp"

namespace qmaps {
namespace {

constexpr double pi = 3.14159265358979323846264338327950288;

std::vector<double> hann(std::size_t n, int order) {
  std::vector<double> w(n);
  for (std::size_t i = 0; i < n; ++i) {
    double s, c;
    ops::sin_cos(pi * static_cast<double>(i) / static_cast<double>(n), s, c);
    w[i] = 1;
    for (int k = 0; k < order; ++k) w[i] *= s * s;
  }
  return w;
}

}  // namespace

const NaffTables& naff_tables(long long n, int order) {
  thread_local NaffTables t;
  if (t.n == n && t.order == order) return t;
  t.n = n;
  t.order = order;
  const auto size = static_cast<std::size_t>(n);
  t.weight = hann(size, order);
  double w0 = 0, w1 = 0, w2 = 0;  // Σ w m^k
  for (std::size_t i = 0; i < size; ++i) {
    const double m = static_cast<double>(i) - 0.5 * static_cast<double>(size - 1);
    w0 += t.weight[i];
    w1 += t.weight[i] * m;
    w2 += t.weight[i] * m * m;
  }
  t.curvature = w2 / w0 - (w1 / w0) * (w1 / w0);
  t.m = std::min(size, std::max<std::size_t>(64, size / 4));
  t.search_weight = hann(t.m, order);
  t.cos_twiddle.resize(t.m / 2);
  t.sin_twiddle.resize(t.m / 2);
  for (std::size_t j = 0; j < t.m / 2; ++j)
    ops::sin_cos(2 * pi * static_cast<double>(j) / static_cast<double>(t.m), t.sin_twiddle[j],
                 t.cos_twiddle[j]);
  t.reversed.resize(t.m);
  const int bits = std::countr_zero(t.m);
  for (std::size_t i = 0; i < t.m; ++i) {
    std::uint32_t r = 0;
    for (int b = 0; b < bits; ++b) r |= static_cast<std::uint32_t>((i >> b) & 1) << (bits - 1 - b);
    t.reversed[i] = r;
  }
  return t;
}

double* naff_scratch(std::size_t which, std::size_t doubles) {
  thread_local std::array<AlignedArray<double>, fft_slot + 1> slots;
  auto& slot = slots.at(which);
  if (slot.size() < doubles) slot = AlignedArray<double>(doubles);
  return slot.data();
}

}  // namespace qmaps
