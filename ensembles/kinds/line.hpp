#pragma once
// The `line` ensemble: `orbits` points evenly spaced on the segment from phase-space point
// `from` to `to`, both included: orbit i is from + (to − from)·i/(orbits − 1), exactly `to` for
// the last; one orbit is `from`.
#include <array>

#include "ensembles/kinds/ensemble_kind.hpp"

namespace qmaps {

class Line final : public EnsembleKind {
 public:
  // Reads [ensemble] orbits, from = [q1, q2, p1, p2], to = [q1, q2, p1, p2].
  explicit Line(const Config& config);
  std::size_t orbits() const override { return orbits_; }
  Drawn draw(std::size_t orbit) const override;
  std::string description() const override;

 private:
  std::array<double, 4> from_{}, to_{};
  std::size_t orbits_;
};

}  // namespace qmaps
