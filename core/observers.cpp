#include "core/observers.hpp"

#include "core/error.hpp"

namespace qmaps {

Coordinate parse_coordinate(std::string_view name, bool time_per_orbit) {
  if (name == "q1") return Coordinate::q1;
  if (name == "q2") return Coordinate::q2;
  if (name == "p1") return Coordinate::p1;
  if (name == "p2") return Coordinate::p2;
  if (name == "t" && time_per_orbit) return Coordinate::t;
  throw usage_error("unknown coordinate '" + std::string(name) + "' (expected q1, q2, p1, p2" +
                    (time_per_orbit ? ", t)" : "; t only for maps with per-orbit time)"));
}

bool Observers::needs_momentum() const {
  for (const auto& d : densities)
    for (Coordinate c : d.coordinates)
      if (c == Coordinate::p1 || c == Coordinate::p2) return true;
  return false;
}

Observers Observers::empty_copy() const {
  Observers o;
  for (const auto& d : densities) o.densities.push_back({d.histogram.empty_copy(), d.coordinates});
  return o;
}

void Observers::merge(const Observers& partial) {
  for (std::size_t i = 0; i < densities.size(); ++i)
    densities[i].histogram.merge(partial.densities[i].histogram);
}

}  // namespace qmaps
