#pragma once
// The initial conditions of a run: the ensemble kind that [ensemble] kind names (box, grid,
// shell, line, file), its points drawn in parallel, and the ensemble that starts from them.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/config.hpp"
#include "core/model.hpp"
#include "ensembles/ensemble_kind.hpp"

namespace qmaps {

// Every orbit's starting point, and the candidates rejected on the way (shell ensembles).
struct Generated {
  std::vector<Phase> points;
  std::uint64_t rejected = 0;
};

// Draws every orbit of `kind` with `threads` OpenMP threads (0: OpenMP's default), handing out
// `chunk` orbits at a time in whatever order threads come; the result does not depend on either.
// An orbit that cannot be drawn throws the error of the lowest such orbit.
Generated generate(const EnsembleKind& kind, int threads = 0, std::size_t chunk = 4096);

struct Started {
  Ensemble ensemble;
  std::vector<Phase> initial;  // the phase point of each orbit's start (/initial)
  std::uint64_t rejected = 0;
};

class InitialConditions {
 public:
  static constexpr const char* kinds = "box, grid, shell, line, file";

  // Reads [ensemble] kind (default "box") and that kind's keys; every error names its key.
  static InitialConditions from_config(const Config& config, const Model& model);

  const std::string& kind() const { return kind_; }
  const EnsembleKind& generator() const { return *generator_; }
  std::size_t orbits() const { return generator_->orbits(); }
  std::uint64_t seed() const { return generator_->seed(); }
  std::string description() const { return generator_->description(); }

  // The ensemble at step 0: from the points by the start rule, or the earlier run's exact state
  // (kind file, group final).
  Started start(const Model& model, Start rule, double escape_bound, int threads = 0) const;

 private:
  std::string kind_;
  std::shared_ptr<const EnsembleKind> generator_;
};

}  // namespace qmaps
