#include "ensembles/kinds/line.hpp"

#include <cmath>

#include "core/error.hpp"

namespace qmaps {
namespace {

std::string point_text(const std::array<double, 4>& x) {
  std::string out = "(";
  for (std::size_t k = 0; k < 4; ++k) out += (k ? ", " : "") + number_text(x[k]);
  return out + ")";
}

}  // namespace

Line::Line(const Config& config) : orbits_(orbits_of(config)) {
  const auto from = config.numbers("ensemble", "from", 4), to = config.numbers("ensemble", "to", 4);
  std::copy(from.begin(), from.end(), from_.begin());
  std::copy(to.begin(), to.end(), to_.begin());
  if (from_ == to_)
    throw usage_error(config.where("ensemble", "to") +
                      " is the same point as [ensemble] from: the line is empty");
}

Drawn Line::draw(std::size_t orbit) const {
  const double t =
      orbits_ == 1 ? 0.0 : static_cast<double>(orbit) / static_cast<double>(orbits_ - 1);
  std::array<double, 4> x;
  for (std::size_t k = 0; k < 4; ++k) x[k] = std::lerp(from_[k], to_[k], t);
  return {as_phase(x)};
}

std::string Line::description() const {
  return "line: " + std::to_string(orbits_) + " orbits from " + point_text(from_) + " to " +
         point_text(to_) + ", both included";
}

}  // namespace qmaps
