#pragma once
// The coordinates an observer reads at node n of an orbit: q1, q2, p1, p2, and t for a map whose
// time differs per orbit.
#include <string_view>

namespace qmaps {

enum class Coordinate { q1 = 0, q2 = 1, p1 = 2, p2 = 3, t = 4 };
Coordinate parse_coordinate(std::string_view name, bool time_per_orbit);  // throws usage_error
std::string_view coordinate_name(Coordinate c);
inline bool is_momentum(Coordinate c) { return c == Coordinate::p1 || c == Coordinate::p2; }
inline bool is_position(Coordinate c) { return c == Coordinate::q1 || c == Coordinate::q2; }

}  // namespace qmaps
