#pragma once
// The `grid` ensemble: a regular grid over two phase-space coordinates, the other two fixed.
// Along an axis of n points over [lo, hi] point j is lo + (hi − lo)·j/(n − 1): both endpoints
// are included (exactly); n = 1 is the midpoint (lo + hi)/2. Orbit i is point (j1, j2) with
// i = j1·n2 + j2: the first axis varies slowest.
#include <array>
#include <cstdint>
#include <vector>

#include "ensembles/kinds/ensemble_kind.hpp"

namespace qmaps {

// A regular grid over some of the four coordinates (the others untouched), as above.
struct Lattice {
  std::vector<int> axes;                      // coordinate indices, slowest first
  std::vector<std::array<double, 2>> ranges;  // per axis
  std::vector<std::size_t> points;            // per axis, ≥ 1
  // Reads `points` ([ensemble] n, or [n1, …], one per axis; each > 0) and each axis's range.
  static Lattice from_config(const Config& config, std::vector<int> axes);
  std::size_t size() const;
  void place(std::size_t index, std::array<double, 4>& x) const;  // sets the axes' coordinates
  std::string text() const;  // "q1 [lo, hi] × 64, p1 [lo, hi] × 32"
};
double lattice_value(const std::array<double, 2>& range, std::size_t points, std::size_t j);

class Grid final : public EnsembleKind {
 public:
  // Reads [ensemble] axes = ["x", "y"], points, the two axes' ranges, the others' fixed values.
  explicit Grid(const Config& config);
  std::size_t orbits() const override { return lattice_.size(); }
  Drawn draw(std::size_t orbit) const override;
  std::string description() const override;

 private:
  Lattice lattice_;
  std::array<double, 4> fixed_{};
};

}  // namespace qmaps
