// Peer: the limit (limit_isa.cpp), the Suris map hand-written for AVX-512 and for AVX2, each run
// where the CPU has it (checked at run time; this file is compiled without ISA flags), with 4 and 8
// chains, on 1 and 2 threads (bench/report takes the fastest chains as the limit).
// items_per_second = particle-steps/s.
//   build/bench/peers/limit_bench
#include <string>

#include "limit.hpp"
#include "suris_peer.hpp"

namespace qmaps::peers {
namespace {

using Loop = void (*)(double* const[4], std::size_t, long long, double, double, double, int, int);

struct LimitIsa {
  const char* name;
  Loop loop;
};

std::vector<LimitIsa> limit_isas() {
  __builtin_cpu_init();
  std::vector<LimitIsa> isas;
  if (__builtin_cpu_supports("avx512f")) isas.push_back({"avx512", limit_avx512});
  if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma"))
    isas.push_back({"avx2", limit_avx2});
  return isas;
}

void run_with(Loop loop, Columns& c, long long steps, int threads, int chains) {
  const SurisCoeffs k = suris_coeffs();
  double* const x[4] = {c[0].data(), c[1].data(), c[2].data(), c[3].data()};
  loop(x, c[0].size(), steps, k.two_a, k.two_b, k.g, threads, chains);
}

void limit(benchmark::State& state, LimitIsa isa) {
  Columns c = suris_start(static_cast<std::size_t>(state.range(0)));
  const int threads = static_cast<int>(state.range(1));
  const int chains = static_cast<int>(state.range(2));
  time_peer(state, "peer-limit", isa.name, threads, [&](long long steps) {
    run_with(isa.loop, c, steps, threads, chains);
    benchmark::DoNotOptimize(c[2].data());
  });
  state.counters["chains"] = chains;
}

}  // namespace
}  // namespace qmaps::peers

int main(int argc, char** argv) {
  using namespace qmaps;
  const auto isas = peers::limit_isas();
  if (isas.empty()) {
    std::fprintf(stderr, "limit_bench: this CPU has neither AVX-512 nor AVX2 with FMA\n");
    return 1;
  }
  std::vector<peers::Peer> checked;
  for (const auto& isa : isas) {
    auto* b = benchmark::RegisterBenchmark(("peer/limit/" + std::string(isa.name)).c_str(),
                                           peers::limit, isa)
                  ->ArgNames({"orbits", "threads", "chains"})
                  ->Unit(benchmark::kMillisecond)
                  ->UseRealTime();
    for (long chains : {4, 8}) {
      for (long threads : {1, 2}) b->Args({bench_size().simd_orbits, threads, chains});
      checked.push_back({"limit " + std::string(isa.name) + ", " + std::to_string(chains) +
                             " chains",
                         [loop = isa.loop, k = static_cast<int>(chains)](peers::Columns& c,
                                                                          long long steps) {
                           peers::run_with(loop, c, steps, 1, k);
                         }});
    }
  }
  return peers::peer_main(argc, argv, checked);
}
