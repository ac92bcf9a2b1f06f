// Peer: what a C++ user writes first for the Suris map (suris_peer.hpp): an array of structs, one
// orbit after the other, plain divisions, one thread, built with -O2 and no ISA flags.
// items_per_second = particle-steps/s.
//   build/bench/peers/naive_bench
#include <vector>

#include "suris_peer.hpp"

namespace qmaps::peers {
namespace {

struct Orbit {
  double q1, q2, q1next, q2next;
};

void step_all(std::vector<Orbit>& orbits, long long steps, const SurisCoeffs& c) {
  for (long long s = 0; s < steps; ++s)
    for (Orbit& o : orbits) {
      const double den = 1 + c.g * (o.q1next * o.q1next + o.q2next * o.q2next);
      const double q1 = c.two_a * o.q1next / den - o.q1;
      const double q2 = c.two_b * o.q2next / den - o.q2;
      o = {o.q1next, o.q2next, q1, q2};
    }
}

std::vector<Orbit> to_structs(const Columns& c) {
  std::vector<Orbit> orbits(c[0].size());
  for (std::size_t i = 0; i < orbits.size(); ++i) orbits[i] = {c[0][i], c[1][i], c[2][i], c[3][i]};
  return orbits;
}

void run(Columns& c, long long steps) {
  auto orbits = to_structs(c);
  step_all(orbits, steps, suris_coeffs());
  for (std::size_t i = 0; i < orbits.size(); ++i)
    c[0][i] = orbits[i].q1, c[1][i] = orbits[i].q2, c[2][i] = orbits[i].q1next,
    c[3][i] = orbits[i].q2next;
}

void naive(benchmark::State& state) {
  auto orbits = to_structs(suris_start(static_cast<std::size_t>(state.range(0))));
  const SurisCoeffs c = suris_coeffs();
  time_peer(state, "peer-naive", "scalar", 1, [&](long long steps) {
    step_all(orbits, steps, c);
    benchmark::DoNotOptimize(orbits.data());
  });
}

}  // namespace
}  // namespace qmaps::peers

int main(int argc, char** argv) {
  using namespace qmaps;
  benchmark::RegisterBenchmark("peer/naive", peers::naive)
      ->ArgNames({"orbits"})
      ->Arg(bench_size().simd_orbits)
      ->Unit(benchmark::kMillisecond)
      ->UseRealTime();
  return peers::peer_main(argc, argv, {{"naive C++", peers::run}});
}
