#include "core/observers/observers.hpp"

#include <algorithm>
#include <array>
#include <numeric>

#include "core/error.hpp"

namespace qmaps {

namespace {
constexpr std::array<std::string_view, 5> names = {"q1", "q2", "p1", "p2", "t"};
}

Coordinate parse_coordinate(std::string_view name, bool time_per_orbit) {
  for (std::size_t k = 0; k < names.size(); ++k)
    if (names[k] == name && (k < 4 || time_per_orbit)) return static_cast<Coordinate>(k);
  throw usage_error("unknown coordinate '" + std::string(name) + "' (expected q1, q2, p1, p2" +
                    (time_per_orbit ? ", t)" : "; t only for maps with per-orbit time)"));
}

std::string_view coordinate_name(Coordinate c) { return names[static_cast<std::size_t>(c)]; }

bool Observers::densities_need_momentum() const {
  for (const auto& d : densities)
    for (Coordinate c : d.coordinates)
      if (is_momentum(c)) return true;
  return false;
}

bool Observers::sections_need_momentum() const {
  for (const auto& s : sections)
    if (is_momentum(s.plane) || is_momentum(s.x) || is_momentum(s.y)) return true;
  return false;
}

Observers Observers::empty_copy() const {
  Observers o;
  for (const auto& d : densities) o.densities.push_back({d.histogram.empty_copy(), d.coordinates});
  for (const auto& s : sections)  // the points are not copied
    o.sections.push_back({s.name, s.plane, s.value, s.direction, s.linear, s.x, s.y, s.cap,
                          s.density.empty_copy(), {}, s.kept, {}});
  return o;
}

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
  start.assign(static_cast<std::size_t>(orbits) + 1, 0);
  for (auto p = first; p != points.end(); ++p) ++start[static_cast<std::size_t>(p->orbit - low) + 1];
  std::partial_sum(start.begin(), start.end(), start.begin());
  sorted.resize(static_cast<std::size_t>(points.end() - first));
  for (auto p = first; p != points.end(); ++p) sorted[start[static_cast<std::size_t>(p->orbit - low)]++] = *p;
  std::copy(sorted.begin(), sorted.end(), first);
}

void Observers::merge(Observers&& partial) {
  std::vector<Observers> one;
  one.push_back(std::move(partial));
  merge(std::move(one));
}

void Observers::merge(std::vector<Observers>&& partials) {
  for (auto& partial : partials) {
    if (partial.densities.size() != densities.size() || partial.sections.size() != sections.size())
      continue;  // a thread that took no block and made no copy
    for (std::size_t i = 0; i < densities.size(); ++i)
      densities[i].histogram.merge(partial.densities[i].histogram);
    for (std::size_t i = 0; i < sections.size(); ++i)
      sections[i].density.merge(partial.sections[i].density);
  }
  for (std::size_t i = 0; i < sections.size(); ++i) {
    auto& mine = sections[i];
    std::vector<Section*> theirs;  // the partials' sections that hold points, in order
    std::size_t total = mine.points.size();
    for (auto& partial : partials)
      if (i < partial.sections.size() && !partial.sections[i].points.empty()) {
        theirs.push_back(&partial.sections[i]);
        total += partial.sections[i].points.size();
      }
    if (mine.points.empty() && theirs.size() == 1) {  // the only points: taken, not copied
      mine.points.swap(theirs[0]->points);
      mine.runs = std::move(theirs[0]->runs);
      continue;
    }
    if (total > mine.points.capacity())
      mine.points.reserve(std::max(total, 2 * mine.points.capacity()));
    for (Section* other : theirs) {
      if (!mine.points.empty()) mine.runs.push_back(mine.points.size());
      for (const auto start : other->runs) mine.runs.push_back(mine.points.size() + start);
      mine.points.insert(mine.points.end(), other->points.begin(), other->points.end());
    }
  }
}

void Observers::finish() {
  for (auto& d : densities) d.histogram.flush();
  for (auto& s : sections) s.density.flush();
  const auto by_orbit_step = [](const SectionPoint& a, const SectionPoint& b) {
    return a.orbit != b.orbit ? a.orbit < b.orbit : a.step < b.step;
  };
  for (auto& s : sections) {  // the ordered runs merged pairwise, log2(runs) passes
    std::vector<std::size_t> bounds = {0};
    bounds.insert(bounds.end(), s.runs.begin(), s.runs.end());
    bounds.push_back(s.points.size());
    while (bounds.size() > 2) {
      std::vector<std::size_t> merged = {0};
      std::size_t r = 0;
      for (; r + 2 < bounds.size(); r += 2) {
        const auto at = [&](std::size_t k) { return s.points.begin() + static_cast<std::ptrdiff_t>(bounds[k]); };
        std::inplace_merge(at(r), at(r + 1), at(r + 2), by_orbit_step);
        merged.push_back(bounds[r + 2]);
      }
      if (merged.back() != bounds.back()) merged.push_back(bounds.back());  // an odd run out
      bounds = std::move(merged);
    }
    s.runs.clear();
  }
}

}  // namespace qmaps
