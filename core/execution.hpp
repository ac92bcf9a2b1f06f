#pragma once
// How the runner executes: which path, how many threads, how many SIMD chains per block.
#include "core/isa.hpp"

namespace qmaps {

struct Execution {
  Isa isa = Isa::scalar;
  int threads = 1;
  int chains = 8;  // 1, 2, 4 or 8
};

}  // namespace qmaps
