#include "core/observers/observers.hpp"

#include <algorithm>
#include <vector>

namespace qmaps {

bool Observers::densities_need_momentum() const {
  return std::ranges::any_of(densities, [](const Density& d) { return d.needs_momentum(); });
}

bool Observers::sections_need_momentum() const {
  return std::ranges::any_of(sections, [](const Section& s) { return s.needs_momentum(); });
}

double Observers::bytes(int threads) const {
  std::size_t cells = 0, points = 0;
  for (const auto& d : densities) cells += d.histogram.counts().size();
  for (const auto& s : sections) {
    cells += s.density.counts().size();
    points += s.points->bytes();
  }
  // A cell is a count and a pending 16-bit tally, in each thread's partial and the total.
  return 10.0 * static_cast<double>(cells) * (threads + 1) + static_cast<double>(points);
}

Observers Observers::empty_copy() const {
  Observers o;
  for (const auto& d : densities) o.densities.push_back(d.empty_copy());
  for (const auto& s : sections) o.sections.push_back(s.empty_copy());
  return o;
}

void Observers::merge(Observers&& partial) {
  std::vector<Observers> one;
  one.push_back(std::move(partial));
  merge(std::move(one));
}

void Observers::merge(std::vector<Observers>&& partials) {
  // A thread that took no block made no copy: its partial has no observers.
  std::erase_if(partials, [&](const Observers& p) {
    return p.densities.size() != densities.size() || p.sections.size() != sections.size();
  });
  for (auto& partial : partials) {
    for (std::size_t i = 0; i < densities.size(); ++i) densities[i].merge(partial.densities[i]);
    for (std::size_t i = 0; i < sections.size(); ++i) sections[i].merge(partial.sections[i]);
  }
}

void Observers::finish() {
  for (auto& d : densities) d.finish();
  for (auto& s : sections) s.finish();
}

}  // namespace qmaps
