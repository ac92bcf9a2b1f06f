#pragma once
// Counter-based random numbers (Philox4x64-10, Random123): the draws of orbit i are a pure
// function of (seed, stream, i, draw), so they never depend on threads, blocks or order.
#include <array>
#include <cstdint>

namespace qmaps {

class OrbitRandom {
 public:
  OrbitRandom(std::uint64_t seed, std::uint64_t stream) : seed_(seed), stream_(stream) {}
  // Four independent uniform doubles in [0, 1), each with 53 random bits.
  std::array<double, 4> uniform4(std::uint64_t orbit, std::uint64_t draw = 0) const;

 private:
  std::uint64_t seed_, stream_;
};

}  // namespace qmaps
