#pragma once
// A point of phase space (q1, q2, p1, p2), and how a two-step map starts from one.
#include <array>
#include <string_view>

namespace qmaps {

struct Phase {
  double q1 = 0, q2 = 0, p1 = 0, p2 = 0;
};

// Phase-space coordinates by index: 0 q1, 1 q2, 2 p1, 3 p2.
inline constexpr std::array<std::string_view, 4> phase_names = {"q1", "q2", "p1", "p2"};
inline constexpr std::array<double Phase::*, 4> phase_members = {&Phase::q1, &Phase::q2,
                                                                 &Phase::p1, &Phase::p2};
inline std::array<double, 4> as_array(const Phase& x) { return {x.q1, x.q2, x.p1, x.p2}; }
inline Phase as_phase(const std::array<double, 4>& x) { return {x[0], x[1], x[2], x[3]}; }

// taylor: q_1 = q_0 + h p + (h²/2) F(q_0), global error O(h²) (default).
// euler:  q_1 = q_0 + h p, the forward difference equals p exactly, global error O(h).
enum class Start { taylor, euler };

Start parse_start(std::string_view name);  // throws qmaps::Error
std::string_view start_name(Start start);

}  // namespace qmaps
