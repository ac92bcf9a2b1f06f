#include "core/histogram.hpp"

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
    scale_[k] = static_cast<double>(a.bins) / (a.hi - a.lo);
    cells *= static_cast<std::size_t>(a.bins);
  }
  counts_.assign(cells, 0);
}

void Histogram::merge(const Histogram& other) {
  for (std::size_t i = 0; i < counts_.size(); ++i) counts_[i] += other.counts_[i];
  underflow_ += other.underflow_;
  overflow_ += other.overflow_;
  samples_ += other.samples_;
}

Histogram Histogram::empty_copy() const { return Histogram(name_, axes_); }

}  // namespace qmaps
