#pragma once
// The initial conditions of a run: the ensemble kind that [ensemble] kind names (box, grid,
// shell, line, file), its points drawn in parallel, and the ensemble that starts from them.
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "ensembles/config/config.hpp"
#include "core/model.hpp"
#include "ensembles/kinds/ensemble_kind.hpp"

namespace qmaps {

// Every orbit's starting point, and the candidates rejected on the way (shell ensembles).
struct Generated {
  std::vector<Phase> points;
  std::uint64_t rejected = 0;
};

// Draws orbits [first, first + out.size()) of `kind` into `out` with `threads` OpenMP threads (0:
// OpenMP's default), handing out `chunk` orbits at a time in whatever order threads come; the
// result does not depend on either. Returns the candidates rejected on the way. An orbit that
// cannot be drawn throws the error of the lowest such orbit.
std::uint64_t generate(const EnsembleKind& kind, std::size_t first, std::span<Phase> out,
                       int threads = 0, std::size_t chunk = 4096);
// Every orbit of `kind`.
Generated generate(const EnsembleKind& kind, int threads = 0, std::size_t chunk = 4096);

// Receives orbits [first, first + points.size())'s starting points as they are drawn.
using PointsSink = std::function<void(std::size_t first, std::span<const Phase> points)>;

class InitialConditions {
 public:
  static std::string kinds();  // "box, grid, shell, line, file"

  // Reads [ensemble] kind (default "box") and that kind's keys; every error names its key. Its
  // long loops, here and in start(), check `stop`.
  static InitialConditions from_config(const Config& config, const Model& model,
                                       StopCheck stop = {});
  // The caller's points (kind "points"): orbit i starts at points[i]; the configuration must then
  // have no [ensemble] table.
  static InitialConditions of_points(const Config& config,
                                     std::shared_ptr<const std::vector<Phase>> points);

  const std::string& kind() const { return kind_; }
  const EnsembleKind& generator() const { return *generator_; }
  std::size_t orbits() const { return generator_->orbits(); }
  std::uint64_t seed() const { return generator_->seed(); }
  std::string description() const { return generator_->description(); }

  // Starts every orbit i of `e` at step 0 as orbit offset + i of the ensemble (offset 0 and
  // e.orbits = orbits(): all of it; else a shard's range), a part of `part` orbits at a time, so
  // that no copy of all the points is ever held: each part's points are drawn, handed to `sink`
  // (e.g. to write /initial; numbered within `e`) and started by the rule, or, for kind file with
  // group final, the orbits continue the earlier run's exact state. Returns the candidates
  // rejected (shell ensembles) and leaves `e` complete, padding filled.
  std::uint64_t start(const Model& model, Ensemble& e, Start rule, double escape_bound,
                      const PointsSink& sink, std::size_t part = std::size_t{1} << 20,
                      std::size_t offset = 0) const;

 private:
  std::string kind_;
  std::shared_ptr<const EnsembleKind> generator_;
  StopCheck stop_;
};

}  // namespace qmaps
