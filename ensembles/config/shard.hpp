#pragma once
// A shard of a run (`qmaps run --shard k/K`, docs/cli.md): the k-th of K contiguous ranges of the
// ensemble's orbits, by orbit index. Orbit i's initial condition is a function of the
// configuration and i alone, so the shards together hold exactly the run's orbits, and
// `qmaps merge` joins their files into the file the whole run writes.
#include <cstddef>
#include <string>
#include <string_view>

namespace qmaps {

struct Shard {
  std::size_t index = 0;  // k, from 1
  std::size_t count = 0;  // K

  static constexpr std::size_t most = std::size_t{1} << 20;
  // "k/K" with 1 ≤ k ≤ K ≤ 2^20; anything else is a usage error quoting it.
  static Shard parse(std::string_view text);
  std::size_t first(std::size_t orbits) const { return (index - 1) * orbits / count; }
  std::size_t size(std::size_t orbits) const { return index * orbits / count - first(orbits); }
  std::string name() const { return std::to_string(index) + "/" + std::to_string(count); }
};

}  // namespace qmaps
