#pragma once
// What the C++ peers share: the Suris map's coefficients from the benchmarks' parameters
// (bench_maps.hpp), their start (the same orbits as the qmaps benchmarks), the check that a peer
// computes what qmaps computes, and their main.
//
//   D = 1 + g(y1² + y2²),  z1 = two_a y1 / D − x1,  z2 = two_b y2 / D − x2   (kernels/suris.hpp)
//   two_a = 2(1 − Ah²), two_b = 2(1 − Bh²), g = 2αh²
#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "../bench_maps.hpp"
#include "kernels/catalogue.hpp"

namespace qmaps::peers {

struct SurisCoeffs {
  double two_a, two_b, g;
};

inline SurisCoeffs suris_coeffs() {
  const double A = suris_params.at("A"), B = suris_params.at("B");
  const double alpha = suris_params.at("alpha"), h = suris_params.at("h");
  const double h2 = h * h;
  return {2 * (1 - A * h2), 2 * (1 - B * h2), 2 * alpha * h2};
}

// The state (q1_n, q2_n, q1_{n+1}, q2_{n+1}) of each orbit, one column per component.
using Columns = std::array<std::vector<double>, 4>;

// The qmaps benchmarks' first `orbits` orbits (bench_ensemble).
inline Columns suris_start(std::size_t orbits) {
  const auto model = make_model("suris", suris_params);
  const Ensemble e = bench_ensemble(*model, orbits);
  Columns c;
  for (std::size_t k = 0; k < 4; ++k) c[k].assign(e.state[k].data(), e.state[k].data() + orbits);
  return c;
}

// Steps `orbits` orbits `steps` times with the peer and with qmaps' scalar reference path and
// returns the largest difference of a state component, relative to max(1, |qmaps' value|).
inline double suris_difference(const std::function<void(Columns&, long long)>& peer,
                               std::size_t orbits, long long steps) {
  Columns mine = suris_start(orbits);
  peer(mine, steps);
  const auto model = make_model("suris", suris_params);
  Ensemble e = bench_ensemble(*model, orbits);
  RunPlan plan;
  plan.total = plan.last = steps;
  plan.measure_orbits = false;
  model->advance(e, plan, Execution{});
  double worst = 0;
  for (std::size_t k = 0; k < 4; ++k)
    for (std::size_t i = 0; i < orbits; ++i) {
      const double d = std::abs(mine[k][i] - e.state[k][i]) / std::max(1.0, std::abs(e.state[k][i]));
      worst = std::isnan(d) ? INFINITY : std::max(worst, d);
    }
  return worst;
}

// Times `advance(steps)` (which steps the peer's orbits) and describes the result for bench/report.
template <class Advance>
void time_peer(benchmark::State& state, const char* peer, const char* isa, int threads,
               Advance advance) {
  const long long steps = bench_size().steps;
  for (auto _ : state) advance(steps);
  describe(state, peer, isa, static_cast<double>(state.range(0)), static_cast<double>(steps),
           threads);
}

// A peer's way of stepping its own copy of the columns `steps` times.
struct Peer {
  std::string name;
  std::function<void(Columns&, long long)> run;
};

// Checks each peer against qmaps (256 orbits, 1000 steps, relative tolerance 1e-10), records the
// differences in the benchmark context, then runs the benchmarks. Exits with 1 on disagreement.
inline int peer_main(int argc, char** argv, const std::vector<Peer>& peers) {
  constexpr double tolerance = 1e-10;
  for (const Peer& peer : peers) {
    const double d = suris_difference(peer.run, 256, 1000);
    char text[200];
    std::snprintf(text, sizeof text, "max relative difference to qmaps (scalar) %.3g after 1000 "
                  "steps of 256 orbits (tolerance %.0e)", d, tolerance);
    std::fprintf(stderr, "%s: %s\n", peer.name.c_str(), text);
    if (!(d <= tolerance)) return 1;
    benchmark::AddCustomContext("agreement " + peer.name, text);
  }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

}  // namespace qmaps::peers
