#include "core/observers/section.hpp"

#include <algorithm>
#include <numeric>

namespace qmaps {

void Section::order_by_orbit(std::size_t from) {
  const auto first = points.begin() + static_cast<std::ptrdiff_t>(from);
  if (points.end() - first < 2) return;
  const auto [lo, hi] = std::minmax_element(
      first, points.end(), [](const auto& a, const auto& b) { return a.orbit < b.orbit; });
  const std::int64_t low = lo->orbit, orbits = hi->orbit - low + 1;
  if (orbits == 1) return;
  // A counting sort by orbit: stable, so each orbit's points stay in step order.
  thread_local std::vector<std::size_t> start;
  thread_local std::vector<SectionPoint> sorted;
  const auto slot = [&](const SectionPoint& p) { return static_cast<std::size_t>(p.orbit - low); };
  start.assign(static_cast<std::size_t>(orbits) + 1, 0);
  for (auto p = first; p != points.end(); ++p) ++start[slot(*p) + 1];
  std::partial_sum(start.begin(), start.end(), start.begin());
  sorted.resize(static_cast<std::size_t>(points.end() - first));
  for (auto p = first; p != points.end(); ++p) sorted[start[slot(*p)]++] = *p;
  std::copy(sorted.begin(), sorted.end(), first);
}

Section Section::empty_copy() const {
  return {name, plane, value, direction, linear, x, y, cap, density.empty_copy(), {}, kept, {}};
}

void Section::merge(std::span<Section* const> partials) {
  std::vector<Section*> holding;  // the partials that hold points, in order
  std::size_t total = points.size();
  for (Section* partial : partials) {
    density.merge(partial->density);
    if (partial->points.empty()) continue;
    holding.push_back(partial);
    total += partial->points.size();
  }
  if (points.empty() && holding.size() == 1) {  // the only points: taken, not copied
    points.swap(holding[0]->points);
    runs = std::move(holding[0]->runs);
    return;
  }
  if (total > points.capacity()) points.reserve(std::max(total, 2 * points.capacity()));
  for (Section* other : holding) {
    if (!points.empty()) runs.push_back(points.size());
    for (const auto start : other->runs) runs.push_back(points.size() + start);
    points.insert(points.end(), other->points.begin(), other->points.end());
  }
}

void Section::finish() {
  density.flush();
  const auto by_orbit_step = [](const SectionPoint& a, const SectionPoint& b) {
    return a.orbit != b.orbit ? a.orbit < b.orbit : a.step < b.step;
  };
  // The ordered runs merged pairwise: log2(runs) passes.
  std::vector<std::size_t> bounds = {0};
  bounds.insert(bounds.end(), runs.begin(), runs.end());
  bounds.push_back(points.size());
  const auto at = [&](std::size_t i) { return points.begin() + static_cast<std::ptrdiff_t>(i); };
  while (bounds.size() > 2) {
    std::vector<std::size_t> merged = {0};
    std::size_t r = 0;
    for (; r + 2 < bounds.size(); r += 2) {
      std::inplace_merge(at(bounds[r]), at(bounds[r + 1]), at(bounds[r + 2]), by_orbit_step);
      merged.push_back(bounds[r + 2]);
    }
    if (merged.back() != bounds.back()) merged.push_back(bounds.back());  // an odd run out
    bounds = std::move(merged);
  }
  runs.clear();
}

}  // namespace qmaps
