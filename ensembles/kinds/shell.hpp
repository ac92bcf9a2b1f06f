#pragma once
// The `shell` ensemble: initial conditions on the energy surface H = E of the continuous system
// the map discretizes, H = ½|p|² + V(q) (core/potential.hpp).
//
// Three coordinates come from their ranges, the fourth (`solve`, default p2) from H = E, with
// the sign `sign` ("+", the default: ≥ 0, or "-"):
//   a momentum:  p = ±√(2(E − V(q) − ½p_other²)), impossible where the root's argument is < 0;
//   a position:  q² = x, the smallest x ≥ 0 with α_k x² + b x + c = 0 (the quartic in q_k is
//                quadratic in q_k²), impossible where no such x exists.
// Impossible points are rejected and counted.
//
// sampling = "random" (default): orbit i takes the first accepted of the Philox draws
//   (seed, i, k), k = 0, 1, …, max_draws − 1 (default 1000); its rejections are k. Reaching the
//   cap is an error naming the orbit, so `orbits` points are always accepted, each a function of
//   (seed, i) alone.
// sampling = "grid": the three coordinates form a lattice (grid.hpp, `points` per axis, in the
//   order q1, q2, p1, p2 without `solve`); the accepted lattice points, in lattice order, are the
//   orbits, and the others are rejected. No accepted point is an error.
#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "core/potential.hpp"
#include "ensembles/kinds/ensemble_kind.hpp"
#include "ensembles/kinds/grid.hpp"

namespace qmaps {

class Shell final : public EnsembleKind {
 public:
  // Reads [ensemble] energy, solve, sign, sampling, and for random: orbits, seed, max_draws;
  // for grid: points; the ranges of the three coordinates other than `solve`. `stop` is
  // checked while the grid is enumerated and while an orbit's draws are rejected.
  Shell(const Config& config, const Potential& potential, StopCheck stop = {});
  std::size_t orbits() const override { return orbits_; }
  Drawn draw(std::size_t orbit) const override;
  std::string description() const override;
  std::uint64_t seed() const override { return seed_; }
  std::uint64_t rejected_up_front() const override { return rejected_up_front_; }
  bool rejects_points() const override { return true; }

  // The point with the three other coordinates of x and `solve` from H = E, if there is a finite
  // one (a potential that overflows leaves none).
  std::optional<Phase> solve(std::array<double, 4> x) const;

 private:
  Potential potential_;
  StopCheck stop_;
  double energy_;
  int solve_;    // 0 q1, 1 q2, 2 p1, 3 p2
  double sign_;  // +1 or −1
  std::array<std::array<double, 2>, 4> ranges_{};
  bool random_;
  std::uint64_t seed_ = 0, max_draws_ = 0;
  std::optional<Lattice> lattice_;       // grid sampling
  std::vector<std::uint64_t> accepted_;  // grid: lattice indices of the orbits
  std::uint64_t rejected_up_front_ = 0;
  std::size_t orbits_ = 0;
  std::string energy_where_;  // for the error at the draw cap
};

}  // namespace qmaps
