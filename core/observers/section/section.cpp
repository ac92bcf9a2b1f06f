#include "core/observers/section/section.hpp"

#include <algorithm>

namespace qmaps {

std::int64_t Section::slots_per_orbit(std::int64_t cap, int direction, long long steps) {
  const long long crossings = direction == 0 ? steps : (steps + 1) / 2;
  return std::max<std::int64_t>(0, std::min<std::int64_t>(cap, crossings));
}

Section Section::empty_copy() const {
  return {name, plane, value, direction, mode, x, y, cap, density.empty_copy(), points, 0};
}

void Section::finish() { density.flush(); }

}  // namespace qmaps
