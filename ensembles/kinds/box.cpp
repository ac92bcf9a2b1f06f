#include "ensembles/kinds/box.hpp"

#include "core/rng.hpp"

namespace qmaps {
namespace {
constexpr std::uint64_t box_stream = 0x626f78;  // "box"
}

Box::Box(const Config& config) : seed_(seed_of(config)), orbits_(orbits_of(config)) {
  for (int k = 0; k < 4; ++k)
    ranges_[k] = range_of(config, phase_names[static_cast<std::size_t>(k)]);
}

Drawn Box::draw(std::size_t orbit) const {
  const auto u = OrbitRandom(seed_, box_stream).uniform4(orbit);
  std::array<double, 4> x;
  for (int k = 0; k < 4; ++k) {
    const auto [lo, hi] = ranges_[k];
    x[k] = lo == hi ? lo : lo + (hi - lo) * u[k];
  }
  return {as_phase(x)};
}

std::string Box::description() const {
  std::string text = "box: " + std::to_string(orbits_) + " orbits uniform in";
  for (int k = 0; k < 4; ++k)
    text += std::string(k ? "," : "") + " " + std::string(phase_names[k]) + " " +
            range_text(ranges_[k]);
  return text + ", seed " + std::to_string(seed_);
}

}  // namespace qmaps
