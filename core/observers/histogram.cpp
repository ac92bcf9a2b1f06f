#include "core/observers/histogram_lanes.hpp"

#include <numeric>
#include <string>

#include "core/error.hpp"

namespace qmaps {

std::vector<double> Axis::edges() const {
  std::vector<double> out(static_cast<std::size_t>(bins) + 1);
  for (std::int64_t i = 0; i <= bins; ++i)
    out[static_cast<std::size_t>(i)] =
        i == bins ? hi : lo + (hi - lo) * (static_cast<double>(i) / static_cast<double>(bins));
  return out;
}

Histogram::Histogram(std::string name, std::vector<Axis> axes)
    : name_(std::move(name)), axes_(std::move(axes)), rank_(static_cast<int>(axes_.size())) {
  if (rank_ < 1 || rank_ > 2) throw usage_error("histogram '" + name_ + "' needs 1 or 2 axes");
  std::size_t cells = 1;
  for (int k = 0; k < rank_; ++k) {
    const Axis& a = axes_[static_cast<std::size_t>(k)];
    lo_[k] = a.lo;
    hi_[k] = a.hi;
    bins_[k] = a.bins;
    last_[k] = static_cast<double>(a.bins - 1);
    scale_[k] = static_cast<double>(a.bins) / (a.hi - a.lo);
    if (a.bins <= 0 || static_cast<std::size_t>(a.bins) > (std::size_t{1} << 40) / cells)
      throw usage_error("histogram '" + name_ + "' has too many cells");
    cells *= static_cast<std::size_t>(a.bins);
  }
  if (cells > (std::size_t{1} << 40))
    throw usage_error("histogram '" + name_ + "' has too many cells (" + std::to_string(cells) + ")");
  cells_ = cells;
  bins1_ = static_cast<double>(bins_[1]);
  for (std::size_t t = 0; t < 2; ++t) tallies_[t] = static_cast<double>(cells + t);
  counts_.assign(cells + 2, 0);
  pending_.assign(cells + 2, 0);
}

std::int64_t Histogram::samples() const {
  return std::accumulate(counts_.begin(), counts_.end(), std::int64_t{0});
}

void Histogram::add(const double* x) {
  ++counts_[ops::integer_lanes(rank_ == 2 ? slot<2>(x) : slot<1>(x))[0]];
}

void Histogram::flush() {
  for (std::size_t i = 0; i < counts_.size(); ++i) counts_[i] += pending_[i];
  std::fill(pending_.begin(), pending_.end(), std::uint16_t{0});
  pending_samples_ = 0;
}

void Histogram::merge(const Histogram& other) {  // other's pending tallies too
  for (std::size_t i = 0; i < counts_.size(); ++i) counts_[i] += other.counts_[i] + other.pending_[i];
}

void Histogram::restore(std::span<const std::int64_t> cells, std::int64_t underflow,
                        std::int64_t overflow) {
  if (cells.size() != cells_)
    throw Error(ExitCode::io, "histogram '" + name_ + "' has " + std::to_string(cells_) +
                                  " cells, not " + std::to_string(cells.size()));
  std::fill(counts_.begin(), counts_.end(), 0);
  std::copy(cells.begin(), cells.end(), counts_.begin());
  counts_[cells_] = underflow;
  counts_[cells_ + 1] = overflow;
}

Histogram Histogram::empty_copy() const { return Histogram(name_, axes_); }

}  // namespace qmaps
