#pragma once
// An ensemble of orbits as structure of arrays: one aligned column per state component, orbits
// contiguous within it, padded to a whole number of the widest blocks. Beside the state: each
// orbit's escape record, and the named per-orbit columns of the lane measurements
// (core/observers/lane_observers.hpp), which copying an orbit, checkpoints and merges carry
// without knowing what they hold.
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "core/aligned_array.hpp"
#include "core/escape.hpp"

namespace qmaps {

// A per-orbit column of a measurement: its dataset in the run's file (a path from the root, e.g.
// "invariants/H/max_abs_drift") and the least value a run leaves in it for an orbit that has not
// escaped (a checkpoint holding less, or a value that is not finite, is refused).
struct ColumnSpec {
  std::string path;
  double least = -std::numeric_limits<double>::infinity();
  bool may_be_nan = false;  // NaN is a value here (a tune that a signal does not have)
};

struct Ensemble {
  // Widest block of the runner: 8 lanes × 8 chains. Every block size divides it.
  static constexpr std::size_t padding = 64;

  // `measured`: the columns of each lane measurement, in the order of their list (none: off).
  Ensemble(std::size_t orbits, std::size_t state_size,
           const std::vector<std::vector<ColumnSpec>>& measured = {});

  std::size_t orbits;
  std::size_t padded;                              // orbits rounded up to `padding`
  std::vector<AlignedArray<double>> state;         // [component][orbit]
  AlignedArray<std::int64_t> escape_step;          // step whose state escaped; −1: never
  AlignedArray<std::uint8_t> escape_reason;        // EscapeReason
  std::vector<ColumnSpec> column_specs;            // every measurement's columns, in list order
  std::vector<AlignedArray<double>> columns;       // [column][orbit], as column_specs
  long long step = 0;                              // the step the state is at

  // The columns of lane measurement m (its place in the list); empty when it is off. Inline:
  // each block's chains ask at its start and end.
  std::span<AlignedArray<double>> columns_of(std::size_t m) {
    if (m + 1 >= first_column_.size()) return {};
    return {columns.data() + first_column_[m], first_column_[m + 1] - first_column_[m]};
  }
  std::span<const AlignedArray<double>> columns_of(std::size_t m) const {
    return const_cast<Ensemble&>(*this).columns_of(m);
  }
  // Orbit j of `from` (its state, escape record and columns) as orbit i.
  void set_orbit(std::size_t i, const Ensemble& from, std::size_t j);
  // Copies the last orbit into the padding lanes, so that every lane holds a valid state.
  void fill_padding();
  std::size_t escaped() const;

 private:
  std::vector<std::size_t> first_column_;  // of each measurement, then the end
};

}  // namespace qmaps
