#pragma once
// One orbit's chaos record for Model::advance_chaos (`qmaps orbit --chaos`): its deviation
// vectors and running sums, as core/chaos.hpp defines them, in plain doubles.
#include <array>
#include <cstddef>
#include <vector>

#include "core/chaos_sums.hpp"

namespace qmaps {

struct OrbitChaos {
  // The deviations a run starts from: (1, 1, 1, 1)/2 for λ, FLI and MEGNO, the phase-space part's
  // unit vectors for the spectrum and the GALIs; 0 beyond the phase-space part.
  explicit OrbitChaos(std::size_t state_size) : deviation(state_size, 0.0) {
    for (std::size_t k = 0; k < 4; ++k) deviation[k] = 0.5;
    for (std::size_t i = 0; i < 4; ++i) {
      spectrum[i].assign(state_size, 0.0);
      spectrum[i][i] = 1.0;
      gali_vectors[i] = spectrum[i];
    }
  }

  std::vector<double> deviation;  // renormalized every step
  ChaosSums<double> sums;
  std::array<std::vector<double>, 4> spectrum;  // orthonormalized every step
  std::array<double, 4> spectrum_logs{};        // Σ ln of the Gram–Schmidt norms
  std::array<std::vector<double>, 4> gali_vectors;  // normalized every step
  std::array<double, 2> gali{1.0, 1.0};             // GALI_2, GALI_4 after the last step

  double lyapunov(std::size_t i) const { return spectrum_logs[i] / sums.steps; }
};

}  // namespace qmaps
