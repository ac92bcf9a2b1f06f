#pragma once
// The data of invariant discovery (core/invariant_discovery.hpp) from a map: its variables are
// its state components as the map defines them (docs/maps.md §2: for the two-step maps
// (q_n, q_{n+1}), for flow and leapfrog (q, p)), with case3's clocks t_n, t_n+1 left out (no
// invariant involves them), and each step x_k → x_{k+1} of every orbit that has not escaped gives
// one row m(x_{k+1}) − m(x_k). The orbits are advanced one step at a time on the scalar
// reference path.
#include <cstddef>
#include <string>
#include <vector>

#include "core/ensemble.hpp"
#include "core/invariant_discovery.hpp"
#include "core/model.hpp"

namespace qmaps {

// The indices, in state_names() order, of the state components discovery uses.
std::vector<std::size_t> discovery_variables(const Model& model);
// Their names as a polynomial writes them: q1_n → q1[n], q2_n+1 → q2[n+1], q1 → q1.
std::vector<std::string> discovery_variable_names(const Model& model);

struct StepsAdded {
  std::size_t rows = 0;     // rows added
  std::size_t skipped = 0;  // steps whose row was not finite (a monomial overflowed)
  std::size_t escaped = 0;  // orbits that escaped on the way (their later steps give no rows)
};

// Advances every orbit of `e` (started, padding filled) `steps` steps and adds the row of each
// step of an orbit that has not escaped.
StepsAdded add_steps(const Model& model, Ensemble& e, long long steps, double escape_bound,
                     DifferenceRows& rows);

}  // namespace qmaps
