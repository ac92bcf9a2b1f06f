#include "integrability/finite_field_orbits.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <random>

namespace qmaps::exact {
namespace {

constexpr std::size_t W = Lanes::lanes;

std::uint64_t splitmix(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

void start_point(const ExactMap& map, std::uint64_t seed, std::uint64_t i, std::uint64_t p,
                 std::array<double, 4>& x) {
  const auto r = orbit_start(map, seed, i, p);
  for (std::size_t k = 0; k < 4; ++k) x[k] = static_cast<double>(r[k]);
}

double ks_distance(std::vector<double> x) {  // against R, x sorted here
  std::sort(x.begin(), x.end());
  const double n = static_cast<double>(x.size());
  double d = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double r = universal_law(x[i]);
    d = std::max({d, (static_cast<double>(i) + 1) / n - r, r - static_cast<double>(i) / n});
  }
  return d;
}

// x scaled by twice its own mean's inverse: R's mean is 2.
void scale_by_mean(std::vector<double>& x) {
  double mean = 0;
  for (const double v : x) mean += v;
  mean /= static_cast<double>(x.size());
  for (double& v : x) v *= 2 / mean;
}

// The levels: the first block's orbits, every invariant compared with its first value at every step.
void check_levels(const ExactMap& map, std::uint64_t prime, std::uint64_t seed,
                  std::uint64_t max_period, FieldOrbits& out) {
  const std::size_t ni = map.invariant_names.size();
  if (!map.invariants_exact || ni == 0) return;
  LaneField field(prime);
  State<Lanes> s, start;
  for (std::size_t lane = 0; lane < W; ++lane) {
    std::array<double, 4> x;
    start_point(map, seed, lane, prime, x);
    for (std::size_t k = 0; k < 4; ++k) s[k].v[lane] = start[k].v[lane] = x[k];
  }
  std::vector<Lanes> first(ni), now(ni);
  map.invariants(s, first.data());
  std::array<bool, W> done{}, kept;
  kept.fill(true);
  for (std::size_t lane = 0; lane < W; ++lane)
    for (std::size_t j = 0; j < ni; ++j) done[lane] = done[lane] || std::isnan(first[j].v[lane]);
  for (std::uint64_t n = 1; n <= max_period; ++n) {
    map.step(s);
    map.invariants(s, now.data());
    bool all_done = true;
    for (std::size_t lane = 0; lane < W; ++lane) {
      if (done[lane]) continue;
      bool singular = false, home = true;
      for (std::size_t k = 0; k < 4; ++k) {
        singular = singular || std::isnan(s[k].v[lane]);
        home = home && s[k].v[lane] == start[k].v[lane];
      }
      for (std::size_t j = 0; j < ni && !singular; ++j) {
        singular = std::isnan(now[j].v[lane]);
        kept[lane] = kept[lane] && (singular || now[j].v[lane] == first[j].v[lane]);
      }
      done[lane] = singular || home;
      all_done = all_done && done[lane];
    }
    if (all_done) break;
  }
  out.level_checked = W;
  out.level_kept = static_cast<std::size_t>(std::count(kept.begin(), kept.end(), true));
}

}  // namespace

std::array<std::uint64_t, 4> orbit_start(const ExactMap& map, std::uint64_t seed, std::uint64_t i,
                                         std::uint64_t p) {
  std::array<std::uint64_t, 4> x{};
  for (const std::size_t k : map.varying) x[k] = splitmix(splitmix(seed) ^ (4 * i + k)) % p;
  return x;
}

double universal_law(double x) { return x <= 0 ? 0 : 1 - std::exp(-x) * (1 + x); }

FieldOrbits finite_field_orbits(const ExactMap& map, std::uint64_t prime, std::size_t orbits,
                                std::uint64_t max_period, std::uint64_t seed) {
  FieldOrbits out;
  out.prime = prime;
  out.dimension = map.varying.size();
  out.orbits = orbits;
  out.max_period = max_period;
  enum Outcome : std::uint8_t { returned, singular, unfinished };
  std::vector<std::uint64_t> period(orbits, 0);
  std::vector<std::uint8_t> outcome(orbits, unfinished);
  std::atomic<std::size_t> next{0};
  std::exception_ptr failure;
  double steps = 0;
#pragma omp parallel reduction(+ : steps)
  try {
    LaneField field(prime);
    State<Lanes> s, start;
    std::array<long long, W> orbit_of;
    std::array<std::uint64_t, W> length;
    const auto load = [&](std::size_t lane) {
      const std::size_t i = next++;
      std::array<double, 4> x{};
      orbit_of[lane] = i < orbits ? static_cast<long long>(i) : -1;
      if (i < orbits) start_point(map, seed, i, prime, x);
      for (std::size_t k = 0; k < 4; ++k) s[k].v[lane] = start[k].v[lane] = x[k];
      length[lane] = 0;
    };
    for (std::size_t lane = 0; lane < W; ++lane) load(lane);
    for (bool active = true; active;) {
      map.step(s);
      active = false;
      for (std::size_t lane = 0; lane < W; ++lane) {
        if (orbit_of[lane] < 0) continue;
        const auto i = static_cast<std::size_t>(orbit_of[lane]);
        ++length[lane];
        bool nan = false, home = true;
        for (std::size_t k = 0; k < 4; ++k) {
          nan = nan || std::isnan(s[k].v[lane]);
          home = home && s[k].v[lane] == start[k].v[lane];
        }
        if (nan || home || length[lane] >= max_period) {
          steps += static_cast<double>(length[lane]);
          outcome[i] = nan ? singular : home ? returned : unfinished;
          period[i] = length[lane];
          load(lane);
        }
        active = active || orbit_of[lane] >= 0;
      }
    }
  } catch (...) {
#pragma omp critical(qmaps_field_orbits)
    failure = std::current_exception();
  }
  if (failure) std::rethrow_exception(failure);
  out.steps = steps;
  for (std::size_t i = 0; i < orbits; ++i) {
    if (outcome[i] == returned) out.periods.push_back(period[i]);
    out.singular += outcome[i] == singular;
    out.unfinished += outcome[i] == unfinished;
  }
  if (out.periods.size() >= 2) {
    std::vector<double> x(out.periods.begin(), out.periods.end());
    double mean = 0;
    for (const double v : x) mean += v;
    out.lambda = mean / static_cast<double>(x.size()) / 2;
    scale_by_mean(x);
    out.ks_distance = ks_distance(x);
    // The bootstrap: samples of Gamma(2, 1) of the same size, scaled as the data are.
    // 200 samples, fewer for many periods (at least 20: 2·10^6 draws in all).
    const int samples = static_cast<int>(std::clamp<std::size_t>(2000000 / x.size(), 20, 200));
    std::mt19937_64 random(seed ^ prime);
    std::uniform_real_distribution<double> uniform(0, 1);
    int as_far = 0;
    std::vector<double> y(x.size());
    for (int b = 0; b < samples; ++b) {
      for (double& v : y) v = -std::log1p(-uniform(random)) - std::log1p(-uniform(random));
      scale_by_mean(y);
      as_far += ks_distance(y) >= out.ks_distance;
    }
    out.p_value = (as_far + 1.0) / (samples + 1.0);
  }
  check_levels(map, prime, seed, max_period, out);
  return out;
}

}  // namespace qmaps::exact
