#include "core/observers/coordinate.hpp"

#include <array>
#include <string>

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

}  // namespace qmaps
