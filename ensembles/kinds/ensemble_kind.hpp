#pragma once
// What every ensemble kind (box, grid, shell, line, file) provides: its orbit count and orbit i's
// initial condition as a pure function of (configuration, seed, i), so that any thread may draw
// any orbit and the result never depends on threads, chunks or order.
#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>

#include "core/ensemble.hpp"
#include "ensembles/config/config.hpp"
#include "core/phase.hpp"

namespace qmaps {

// Called now and then by the long loops of drawing and enumerating, with what they are doing: it
// throws to stop them (the program stops so on a signal). Empty: never stops.
using StopCheck = std::function<void(const char* doing)>;
inline void check_stop(const StopCheck& stop, const char* doing) {
  if (stop) stop(doing);
}

// Orbit i's starting point, and how many candidates were rejected before it (shell ensembles).
struct Drawn {
  Phase point;
  std::uint64_t rejected = 0;
};

class EnsembleKind {
 public:
  virtual ~EnsembleKind() = default;
  virtual std::size_t orbits() const = 0;
  virtual Drawn draw(std::size_t orbit) const = 0;
  // One line saying what the ensemble is (the `ensemble_description` attribute).
  virtual std::string description() const = 0;
  virtual std::uint64_t seed() const { return 0; }
  // Candidates rejected once for all, not by any one orbit (a shell grid's points off the shell).
  virtual std::uint64_t rejected_up_front() const { return 0; }
  // Whether drawing rejects candidate points (a shell's off the energy surface): the run then
  // reports how many.
  virtual bool rejects_points() const { return false; }
  // Whether the orbits continue saved map states (a file's /final/state) instead of starting at
  // their drawn points; then continue_into() starts orbit i of `e` in the state of orbit
  // first + i.
  virtual bool continues() const { return false; }
  virtual void continue_into(Ensemble& e, std::size_t first, double escape_bound) const;
};


// The index of coordinate `name` read from [ensemble] `key` (an error naming the key otherwise).
int phase_index(const Config& config, std::string_view key, const std::string& name);
// [ensemble] orbits, > 0.
std::size_t orbits_of(const Config& config);
// [ensemble] seed, ≥ 0 (default 0).
std::uint64_t seed_of(const Config& config);
// [ensemble] `key`, a range [lo, hi] or one number, whose width hi − lo is finite, so that every
// point lo + (hi − lo)·u drawn in it (u < 1) is finite (an error naming the key otherwise).
std::array<double, 2> range_of(const Config& config, std::string_view key);
// "[lo, hi]" with round-trip digits, or "x" when lo = hi.
std::string range_text(const std::array<double, 2>& range);

}  // namespace qmaps
