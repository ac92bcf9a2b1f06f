#pragma once
// A section's kept points: at most per_orbit() per orbit, orbit o's in the slots
// [o · per_orbit, o · per_orbit + kept(o)), in step order. A run's threads write their orbits'
// slots directly (an orbit belongs to one thread at a time), so the points are in (orbit, step)
// order whatever the threads, chains and segments, with no sort and no merge. The slots are
// reserved at once, as untouched memory (pages cost only when a point lands in them), and count
// in the run's memory estimate: its size is known before the run starts.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace qmaps {

struct SectionPoint {
  std::int64_t orbit, step;
  double x, y;
};

class SectionPoints {
 public:
  SectionPoints(std::size_t orbits, std::int64_t per_orbit);

  // Keeps the point (x, y) of a crossing of `orbit` at `step`, if the orbit has a free slot.
  void keep(std::size_t orbit, std::int64_t step, double x, double y) {
    std::int64_t& n = kept_[orbit];
    if (n < per_orbit_) slots_[orbit * static_cast<std::size_t>(per_orbit_) + static_cast<std::size_t>(n++)] = {step, x, y};
  }
  std::int64_t per_orbit() const { return per_orbit_; }
  std::span<const std::int64_t> kept() const { return kept_; }  // per orbit
  std::size_t size() const;                                    // the points in all
  std::size_t bytes() const;  // what the slots and counts may come to hold

  // Where a pass of reads has got to: the orbit whose points begin at point `at`.
  struct Cursor {
    std::size_t at = 0, orbit = 0;
  };
  // Points [first, first + out.size()) in (orbit, step) order, within size(). Reads that go
  // forward part after part with one cursor (and no point kept meanwhile) cost one pass in all.
  void read(std::size_t first, std::span<SectionPoint> out, Cursor& cursor) const;
  std::vector<SectionPoint> all() const;  // every point, in (orbit, step) order
  void clear();                           // no point kept

 private:
  struct Slot {
    std::int64_t step;
    double x, y;
  };
  struct Release {
    void operator()(Slot* p) const;
  };
  std::int64_t per_orbit_;
  std::vector<std::int64_t> kept_;
  std::unique_ptr<Slot[], Release> slots_;
};

}  // namespace qmaps
