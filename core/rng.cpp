#include "core/rng.hpp"

#include <Random123/philox.h>

namespace qmaps {

std::array<double, 4> OrbitRandom::uniform4(std::uint64_t orbit, std::uint64_t draw) const {
  r123::Philox4x64 philox;
  const r123::Philox4x64::ctr_type counter = {{orbit, draw, 0, 0}};
  const r123::Philox4x64::key_type key = {{seed_, stream_}};
  const auto bits = philox(counter, key);
  std::array<double, 4> u;
  for (int k = 0; k < 4; ++k) u[k] = static_cast<double>(bits[k] >> 11) * 0x1.0p-53;
  return u;
}

}  // namespace qmaps
