// Peer: the limit (limit_isa.cpp), the Suris map hand-written for AVX-512 and for AVX2, each run
// where the CPU has it (checked at run time; this file is compiled without ISA flags), on 1 and 2
// threads. items_per_second = particle-steps/s.
//   build/bench/peers/limit_bench
#include <string>

#include "limit.hpp"
#include "suris_peer.hpp"

namespace qmaps::peers {
namespace {

using Loop = void (*)(double* const[4], std::size_t, long long, double, double, double, int);

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

void run_with(Loop loop, Columns& c, long long steps, int threads) {
  const SurisCoeffs k = suris_coeffs();
  double* const x[4] = {c[0].data(), c[1].data(), c[2].data(), c[3].data()};
  loop(x, c[0].size(), steps, k.two_a, k.two_b, k.g, threads);
}

void limit(benchmark::State& state, LimitIsa isa) {
  Columns c = suris_start(static_cast<std::size_t>(state.range(0)));
  const int threads = static_cast<int>(state.range(1));
  time_peer(state, "peer-limit", isa.name, threads, [&](long long steps) {
    run_with(isa.loop, c, steps, threads);
    benchmark::DoNotOptimize(c[2].data());
  });
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
  for (const auto& isa : isas)
    benchmark::RegisterBenchmark(("peer/limit/" + std::string(isa.name)).c_str(), peers::limit, isa)
        ->ArgNames({"orbits", "threads"})
        ->Args({bench_size().simd_orbits, 1})
        ->Args({bench_size().simd_orbits, 2})
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime();
  std::vector<peers::Peer> checked;
  for (const auto& isa : isas)
    checked.push_back({"limit " + std::string(isa.name), [loop = isa.loop](peers::Columns& c,
                                                                        long long steps) {
                         peers::run_with(loop, c, steps, 1);
                       }});
  return peers::peer_main(argc, argv, checked);
}
