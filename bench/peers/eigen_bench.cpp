// Peer: the Suris map (suris_peer.hpp) on Eigen arrays, one expression per line as an Eigen user
// writes it; Eigen vectorizes each expression for the ISA it is compiled for (its own flags, see
// bench/CMakeLists.txt). One thread (Eigen does not parallelize coefficient-wise expressions).
// items_per_second = particle-steps/s.
//   build/bench/peers/eigen_<isa>_bench
#include <Eigen/Core>

#include "suris_peer.hpp"

namespace qmaps::peers {
namespace {

struct EigenState {
  Eigen::ArrayXd q1, q2, q1next, q2next;
};

EigenState to_eigen(const Columns& c) {
  const auto column = [&](int k) {
    return Eigen::ArrayXd(Eigen::Map<const Eigen::ArrayXd>(c[k].data(), Eigen::Index(c[k].size())));
  };
  return {column(0), column(1), column(2), column(3)};
}

void step_all(EigenState& s, long long steps, const SurisCoeffs& c) {
  Eigen::ArrayXd inv(s.q1.size());
  for (long long n = 0; n < steps; ++n) {
    inv = (c.g * (s.q1next.square() + s.q2next.square()) + 1.0).inverse();
    s.q1 = c.two_a * s.q1next * inv - s.q1;
    s.q2 = c.two_b * s.q2next * inv - s.q2;
    s.q1.swap(s.q1next);
    s.q2.swap(s.q2next);
  }
}

void run(Columns& c, long long steps) {
  EigenState s = to_eigen(c);
  step_all(s, steps, suris_coeffs());
  const Eigen::ArrayXd* parts[4] = {&s.q1, &s.q2, &s.q1next, &s.q2next};
  for (int k = 0; k < 4; ++k) c[k].assign(parts[k]->data(), parts[k]->data() + parts[k]->size());
}

void eigen(benchmark::State& state) {
  EigenState s = to_eigen(suris_start(static_cast<std::size_t>(state.range(0))));
  const SurisCoeffs c = suris_coeffs();
  time_peer(state, "peer-eigen", QMAPS_PEER_ISA, 1, [&](long long steps) {
    step_all(s, steps, c);
    benchmark::DoNotOptimize(s.q1next.data());
  });
}

}  // namespace
}  // namespace qmaps::peers

int main(int argc, char** argv) {
  using namespace qmaps;
  benchmark::RegisterBenchmark("peer/eigen/" QMAPS_PEER_ISA, peers::eigen)
      ->ArgNames({"orbits"})
      ->Arg(bench_size().simd_orbits)
      ->Unit(benchmark::kMillisecond)
      ->UseRealTime();
  return peers::peer_main(argc, argv, {{"Eigen (" QMAPS_PEER_ISA ")", peers::run}});
}
