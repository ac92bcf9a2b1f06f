#pragma once
// One orbit's chaos record for Model::advance_chaos (`qmaps orbit --chaos`): its deviation
// vectors and running sums, as core/chaos.hpp defines them, in plain doubles.
#include <array>
#include <cstddef>
#include <vector>

#include "core/chaos_sums.hpp"

namespace qmaps {

struct OrbitChaos {
  // The deviations a run starts from, in chaos_step's order (core/chaos.hpp): (1, 1, 1, 1)/2 for
  // λ, FLI and MEGNO, then the phase-space part's unit vectors for the spectrum and again for the
  // GALIs; 0 beyond the phase-space part.
  explicit OrbitChaos(std::size_t state_size) {
    for (auto& w : deviations) w.assign(state_size, 0.0);
    for (std::size_t k = 0; k < 4; ++k) {
      deviations[0][k] = 0.5;
      deviations[1 + k][k] = deviations[5 + k][k] = 1.0;
    }
  }

  std::array<std::vector<double>, 9> deviations;
  ChaosSums<double> sums;
  std::array<double, 4> spectrum_logs{};  // Σ ln of the Gram–Schmidt norms
  std::array<double, 2> gali{1.0, 1.0};   // GALI_2, GALI_4 after the last step

  double lyapunov(std::size_t i) const { return spectrum_logs[i] / sums.steps; }
};

}  // namespace qmaps
