#pragma once
// The preset peer's loops (preset_isa.cpp), one per instruction set, each in its own translation
// unit: call one only where the CPU has its ISA. The work of the default preset
// (ensembles/presets/suris.toml) on the Suris map: its stride, histograms and cap are these.
#include <cstddef>
#include <cstdint>

namespace qmaps::peers {

inline constexpr long long preset_stride = 10;  // [run] stride: the samples' steps
inline constexpr std::int64_t preset_cap = 2;   // [[section]] cap: points kept per orbit
inline constexpr int preset_bins = 128;         // every histogram is 128 × 128
// A histogram's counts: its cells row-major, then the underflow and the overflow.
inline constexpr std::size_t preset_counts = preset_bins * preset_bins + 2;

// A histogram's ranges [lo, hi) over its two axes.
struct PresetRange {
  double lo[2], hi[2];
};
inline constexpr PresetRange preset_density = {{-1, -1}, {1, 1}};   // (q1, q2) every stride
inline constexpr PresetRange preset_section = {{-1, -1}, {1, 1}};   // (q2, p2) every crossing
inline constexpr PresetRange preset_image = {{0, 0}, {0.7, 0.0081}};  // (H, I1) at step 0

// The Suris map's coefficients and its invariants' (kernels/suris.hpp, A ≠ B).
struct PresetCoeffs {
  double two_a, two_b, g, two_h;
  double half_inv_h2, HA, HB, Halpha, two_Ah2, two_Bh2, k1, k2, kx1, kx2;
};

struct PresetPoint {
  std::int64_t step;
  double x, y;  // (q2, p2)
};

// One run of the preset over n orbits (n a multiple of 8 × chains), from step `first`, `steps`
// steps: the state stepped in place; each stride the invariants H, I1, I2 (their max |I − I(0)|
// in drift) and the (q1, q2) density; each upward crossing of q1 = 0 its (q2, p2), p from a
// reversed step, counted in the section's density and kept while the orbit has fewer than
// preset_cap points; at the end the invariants of the last state (last) and the image of the
// initial ones. The histograms' counts are added to, every other output written.
struct PresetRun {
  double* x[4];  // q1_n, q2_n, q1_{n+1}, q2_{n+1}
  std::size_t n;
  const double* initial[3];
  double* drift[3];
  double* last[3];
  std::int64_t* kept;   // per orbit
  PresetPoint* points;  // orbit o's in [o · preset_cap, o · preset_cap + kept[o])
  std::uint64_t* density;
  std::uint64_t* section;
  std::uint64_t* image;
  long long first, steps;  // a run from step 0 samples the density there too
};

void preset_avx512(const PresetCoeffs& c, const PresetRun& r, int threads, int chains);
void preset_avx2(const PresetCoeffs& c, const PresetRun& r, int threads, int chains);

}  // namespace qmaps::peers
