#pragma once
// What a run measures while it advances: its densities (density.hpp) and Poincaré sections
// (section.hpp); the invariants' tracking lives in the ensemble (invariant_track.hpp). Each
// observer knows how its thread partials are made, merged and finished; the runner's block
// (core/block.hpp) drives them in registers through their *_lanes.hpp, at every width.
// Each thread fills its own empty_copy(); merge() then finish() give a result that does not
// depend on threads. What they leave in a file, and how shards' add up, is described in
// ensembles/io/run_observers.
#include <vector>

#include "core/observers/density/density.hpp"
#include "core/observers/section/section.hpp"

namespace qmaps {

struct Observers {
  std::vector<Density> densities;
  std::vector<Section> sections;

  bool empty() const { return densities.empty() && sections.empty(); }
  bool densities_need_momentum() const;  // any axis over p1 or p2 (a reversed step per sample)
  bool sections_need_momentum() const;
  // The memory they hold in a run of `threads` threads: every histogram's cells, in each
  // thread's partial and the total, and the sections' point slots.
  double bytes(int threads) const;
  Observers empty_copy() const;
  void merge(Observers&& partial);  // adds the partial's counts (the points are shared)
  void merge(std::vector<Observers>&& partials);  // the same, one after the other
  void finish();
};

}  // namespace qmaps
