#include "core/observers/observers.hpp"

#include <algorithm>

namespace qmaps {

bool Observers::densities_need_momentum() const {
  return std::ranges::any_of(densities, [](const Density& d) { return d.needs_momentum(); });
}

bool Observers::sections_need_momentum() const {
  return std::ranges::any_of(sections, [](const Section& s) { return s.needs_momentum(); });
}

std::size_t Observers::cells() const {
  std::size_t n = 0;
  for (const auto& d : densities) n += d.histogram.counts().size();
  for (const auto& s : sections) n += s.density.counts().size();
  return n;
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
  for (auto& partial : partials)
    for (std::size_t i = 0; i < densities.size(); ++i) densities[i].merge(partial.densities[i]);
  for (std::size_t i = 0; i < sections.size(); ++i) {
    std::vector<Section*> theirs;
    for (auto& partial : partials) theirs.push_back(&partial.sections[i]);
    sections[i].merge(theirs);
  }
}

void Observers::finish() {
  for (auto& d : densities) d.finish();
  for (auto& s : sections) s.finish();
}

}  // namespace qmaps
