#pragma once
// A 1D or 2D histogram over fixed ranges: integer counts in half-open bins [lo, hi), and the
// samples that fall outside counted apart (underflow: below some axis; overflow: otherwise at or
// above some axis, or not a number). Merging adds counts, exact in any order.
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace qmaps {

struct Axis {
  std::string coordinate;
  double lo = 0, hi = 1;
  std::int64_t bins = 1;

  std::vector<double> edges() const;
};

// One or two axes.
class Histogram {
 public:
  Histogram() = default;
  Histogram(std::string name, std::vector<Axis> axes);

  // One sample: a value per axis, counted at once.
  void add(const double* x);

  // One sample per alive lane of V: the values of axis k in x[k]. Each lane's slot (its cell, or
  // the underflow or overflow tally past the cells) is computed in V with the same arithmetic for
  // double, so every path bins alike; then one increment per alive lane (with no branch when
  // every lane is alive, as for densities; a section's crossings are a few lanes at a time).
  // These increments go to 16-bit pending tallies (a 128 × 128 histogram's stay in L1), added to
  // the counts by flush() before any of them could overflow, and by merge() and
  // Observers::merge/finish: counts(), underflow(), overflow() and samples() include the pending
  // tallies only once flushed.
  // (Defined in core/observers/histogram_lanes.hpp, which the runner's paths include.)
  template <class V, class Mask>
  void add_lanes(const V* x, Mask alive);
  // The same in two parts, for samples a few lanes at a time (a section's crossings): each
  // lane's slot, then one increment per lane counted.
  template <class V>
  auto slots(const V* x) const;  // std::array<std::uint64_t, lanes of V>
  void add_slot(std::uint64_t slot) {
    if (pending_samples_ == pending_limit) flush();
    ++pending_samples_;
    ++pending_[slot];
  }
  void flush();

  void merge(const Histogram& other);
  // Sets every count, as counts(), underflow() and overflow() gave them (a checkpoint's).
  void restore(std::span<const std::int64_t> cells, std::int64_t underflow, std::int64_t overflow);
  // The same histogram with every count 0 (a thread's partial).
  Histogram empty_copy() const;

  const std::string& name() const { return name_; }
  const std::vector<Axis>& axes() const { return axes_; }
  std::span<const std::int64_t> counts() const {  // row-major, x first
    return {counts_.data(), cells_};
  }
  std::int64_t underflow() const { return counts_[cells_]; }
  std::int64_t overflow() const { return counts_[cells_ + 1]; }
  std::int64_t samples() const;  // every count

 private:
  std::string name_;
  std::vector<Axis> axes_;
  int rank_ = 1;
  double lo_[2] = {0, 0}, hi_[2] = {1, 1}, scale_[2] = {1, 1}, last_[2] = {0, 0};
  std::int64_t bins_[2] = {1, 1};
  std::size_t cells_ = 1;
  std::vector<std::int64_t> counts_;  // the cells, then the underflow and overflow tallies
  // add_lanes' increments since the last flush, at most pending_limit in all (so in every slot)
  static constexpr std::size_t pending_limit = 0xFFFF;
  std::vector<std::uint16_t> pending_;
  std::size_t pending_samples_ = 0;
  // As the slots' doubles: the second axis' bins, and the tallies' slots cells, cells + 1.
  double bins1_ = 1, tallies_[2] = {1, 2};

  template <int rank, class V>
  V slot(const V* x) const;
};

}  // namespace qmaps
