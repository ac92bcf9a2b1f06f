#include "core/observers/section/section_points.hpp"

#include <cstdlib>
#include <new>
#include <numeric>
#include <stdexcept>

#include "core/observers/large_pages.hpp"

namespace qmaps {

SectionPoints::SectionPoints(std::size_t orbits, std::int64_t per_orbit)
    : per_orbit_(per_orbit), kept_(orbits, 0) {
  const std::size_t slots = orbits * static_cast<std::size_t>(per_orbit);
  // Not initialized: a slot is read only once a point is written to it.
  if (slots > 0) slots_.reset(LargePages<Slot>().allocate(slots));
}

void SectionPoints::Release::operator()(Slot* p) const { LargePages<Slot>().deallocate(p, 0); }

std::size_t SectionPoints::size() const {
  return static_cast<std::size_t>(std::accumulate(kept_.begin(), kept_.end(), std::int64_t{0}));
}

std::size_t SectionPoints::bytes() const {
  return kept_.size() * (sizeof(std::int64_t) + static_cast<std::size_t>(per_orbit_) * sizeof(Slot));
}

void SectionPoints::read(std::size_t first, std::span<SectionPoint> out, Cursor& cursor) const {
  if (first < cursor.at) cursor = {};  // a read behind the cursor starts over
  std::size_t orbit = cursor.orbit, begins = cursor.at;
  while (orbit < kept_.size() && begins + static_cast<std::size_t>(kept_[orbit]) <= first)
    begins += static_cast<std::size_t>(kept_[orbit++]);
  cursor = {begins, orbit};
  std::size_t j = first - begins;  // the point of `orbit` that comes first
  for (auto& p : out) {
    while (orbit < kept_.size() && j == static_cast<std::size_t>(kept_[orbit])) {
      ++orbit;
      j = 0;
    }
    if (orbit == kept_.size()) throw std::out_of_range("SectionPoints::read past the last point");
    const Slot& s = slots_[orbit * static_cast<std::size_t>(per_orbit_) + j++];
    p = {static_cast<std::int64_t>(orbit), s.step, s.x, s.y};
  }
}

std::vector<SectionPoint> SectionPoints::all() const {
  std::vector<SectionPoint> points(size());
  Cursor cursor;
  read(0, points, cursor);
  return points;
}

void SectionPoints::clear() {
  std::fill(kept_.begin(), kept_.end(), 0);
}

}  // namespace qmaps
