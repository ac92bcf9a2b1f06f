#include "ensembles/kinds/ensemble_kind.hpp"

#include <cmath>
#include <stdexcept>

#include "core/error.hpp"

namespace qmaps {

void EnsembleKind::continue_into(Ensemble&, std::size_t, double) const {
  throw std::logic_error("continue_into: " + description() + " does not continue saved states");
}

int phase_index(const Config& config, std::string_view key, const std::string& name) {
  for (std::size_t k = 0; k < phase_names.size(); ++k)
    if (phase_names[k] == name) return static_cast<int>(k);
  throw usage_error(config.where("ensemble", key) + ": unknown coordinate '" + name +
                    "' (expected q1, q2, p1 or p2)");
}

std::size_t orbits_of(const Config& config) {
  const long long orbits = config.integer("ensemble", "orbits");
  if (orbits <= 0)
    throw usage_error(config.where("ensemble", "orbits") + " must be > 0 (got " +
                      std::to_string(orbits) + ")");
  return static_cast<std::size_t>(orbits);
}

std::uint64_t seed_of(const Config& config) {
  const long long seed = config.integer_or("ensemble", "seed", 0);
  if (seed < 0) throw usage_error(config.where("ensemble", "seed") + " must be >= 0");
  return static_cast<std::uint64_t>(seed);
}

std::array<double, 2> range_of(const Config& config, std::string_view key) {
  const auto range = config.range("ensemble", key);
  // lo + (hi − lo)·u is monotone in u under rounding: its largest value is below lo + (hi − lo).
  const double width = range[1] - range[0];
  if (!std::isfinite(width) || !std::isfinite(range[0] + width))
    throw usage_error(config.where("ensemble", key) + " = " + range_text(range) +
                      ": its width hi - lo overflows; a range must have a finite width, so that "
                      "every point drawn in it is finite");
  return range;
}

std::string range_text(const std::array<double, 2>& range) {
  if (range[0] == range[1]) return number_text(range[0]);
  std::string text = "[";
  text.append(number_text(range[0])).append(", ").append(number_text(range[1]));
  return text.append("]");
}

}  // namespace qmaps
