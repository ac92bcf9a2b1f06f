#include "core/observers/observers.hpp"

#include <algorithm>
#include <array>

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

void Section::record(std::int64_t orbit, std::int64_t step, const double* before,
                     const double* after) {
  double xy[2] = {after[static_cast<int>(x)], after[static_cast<int>(y)]};
  if (linear) {
    const double a = before[static_cast<int>(plane)], b = after[static_cast<int>(plane)];
    const double f = b == a ? 1.0 : (value - a) / (b - a);
    xy[0] = before[static_cast<int>(x)] + f * (xy[0] - before[static_cast<int>(x)]);
    xy[1] = before[static_cast<int>(y)] + f * (xy[1] - before[static_cast<int>(y)]);
  }
  density.add(xy);
  auto& count = (*kept)[static_cast<std::size_t>(orbit)];
  if (count < cap) {
    ++count;
    points.push_back({orbit, step, xy[0], xy[1]});
  }
}

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
                          s.density.empty_copy(), {}, s.kept});
  return o;
}

void Observers::merge(Observers&& partial) {
  for (std::size_t i = 0; i < densities.size(); ++i)
    densities[i].histogram.merge(partial.densities[i].histogram);
  for (std::size_t i = 0; i < sections.size(); ++i) {
    sections[i].density.merge(partial.sections[i].density);
    auto& mine = sections[i].points;
    auto& theirs = partial.sections[i].points;
    if (mine.empty())
      mine.swap(theirs);  // the first partial's points are taken, not copied
    else
      mine.insert(mine.end(), theirs.begin(), theirs.end());
  }
}

void Observers::finish() {
  for (auto& d : densities) d.histogram.flush();
  for (auto& s : sections) s.density.flush();
  for (auto& s : sections)
    std::sort(s.points.begin(), s.points.end(), [](const SectionPoint& a, const SectionPoint& b) {
      return a.orbit != b.orbit ? a.orbit < b.orbit : a.step < b.step;
    });
}

}  // namespace qmaps
