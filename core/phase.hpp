#pragma once
// A point of phase space (q1, q2, p1, p2), and how a two-step map starts from one.
#include <string_view>

namespace qmaps {

struct Phase {
  double q1 = 0, q2 = 0, p1 = 0, p2 = 0;
};

// taylor: q_1 = q_0 + h p + (h²/2) F(q_0), global error O(h²) (default).
// euler:  q_1 = q_0 + h p, the forward difference equals p exactly, global error O(h).
enum class Start { taylor, euler };

Start parse_start(std::string_view name);  // throws qmaps::Error
std::string_view start_name(Start start);

}  // namespace qmaps
