#include "ensembles/kinds/grid.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.hpp"

namespace qmaps {

double lattice_value(const std::array<double, 2>& range, std::size_t points, std::size_t j) {
  if (points == 1) {  // lo + hi may overflow where the width does not: then halve each first
    const double sum = range[0] + range[1];
    return std::isfinite(sum) ? 0.5 * sum : 0.5 * range[0] + 0.5 * range[1];
  }
  // std::lerp is exact at both ends: j = 0 gives lo, j = points − 1 gives hi.
  return std::lerp(range[0], range[1], static_cast<double>(j) / static_cast<double>(points - 1));
}

Lattice Lattice::from_config(const Config& config, std::vector<int> axes) {
  Lattice l;
  const auto given = config.range_or_integer("ensemble", "points");
  if (given.size() != 1 && given.size() != axes.size())
    throw usage_error(config.where("ensemble", "points") + " must be a number or an array of " +
                      std::to_string(axes.size()) + " numbers, one per axis");
  double total = 1;
  for (std::size_t k = 0; k < axes.size(); ++k) {
    const std::int64_t n = given.size() == 1 ? given[0] : given[k];
    if (n <= 0)
      throw usage_error(config.where("ensemble", "points") + " must be > 0 (got " +
                        std::to_string(n) + ")");
    const auto name = phase_names[static_cast<std::size_t>(axes[k])];
    const auto range = range_of(config, name);
    if (n > 1 && !(range[0] < range[1]))
      throw usage_error(config.where("ensemble", name) +
                        " is an empty range: " + std::to_string(n) + " grid points need lo < hi");
    l.ranges.push_back(range);
    l.points.push_back(static_cast<std::size_t>(n));
    total *= static_cast<double>(n);
  }
  if (total > static_cast<double>(std::numeric_limits<std::int64_t>::max()))
    throw usage_error(config.where("ensemble", "points") + ": too many grid points");
  l.axes = std::move(axes);
  return l;
}

std::size_t Lattice::size() const {
  std::size_t n = 1;
  for (auto p : points) n *= p;
  return n;
}

void Lattice::place(std::size_t index, std::array<double, 4>& x) const {
  for (std::size_t k = axes.size(); k-- > 0;) {
    x[static_cast<std::size_t>(axes[k])] = lattice_value(ranges[k], points[k], index % points[k]);
    index /= points[k];
  }
}

std::string Lattice::text() const {
  std::string out;
  for (std::size_t k = 0; k < axes.size(); ++k)
    out += std::string(k ? ", " : "") +
           std::string(phase_names[static_cast<std::size_t>(axes[k])]) + " " +
           range_text(ranges[k]) + " x " + std::to_string(points[k]);
  return out;
}

Grid::Grid(const Config& config) {
  if (config.has("ensemble", "orbits"))
    throw usage_error(config.where("ensemble", "orbits") +
                      ": a grid has one orbit per point; set [ensemble] points instead");
  std::vector<int> axes;
  for (const auto& name : config.strings("ensemble", "axes", 2))
    axes.push_back(phase_index(config, "axes", name));
  if (axes[0] == axes[1])
    throw usage_error(config.where("ensemble", "axes") + " must name two different coordinates");
  lattice_ = Lattice::from_config(config, axes);
  for (int k = 0; k < 4; ++k) {
    if (k == axes[0] || k == axes[1]) continue;
    const auto name = phase_names[static_cast<std::size_t>(k)];
    const auto range = range_of(config, name);
    if (range[0] != range[1])
      throw usage_error(config.where("ensemble", name) +
                        " must be one number: the grid's other coordinates are fixed");
    fixed_[static_cast<std::size_t>(k)] = range[0];
  }
}

Drawn Grid::draw(std::size_t orbit) const {
  auto x = fixed_;
  lattice_.place(orbit, x);
  return {as_phase(x)};
}

std::string Grid::description() const {
  std::string text = "grid: " + std::to_string(orbits()) + " orbits, " + lattice_.text();
  for (int k = 0; k < 4; ++k)
    if (std::find(lattice_.axes.begin(), lattice_.axes.end(), k) == lattice_.axes.end())
      text += ", " + std::string(phase_names[static_cast<std::size_t>(k)]) + " " +
              number_text(fixed_[static_cast<std::size_t>(k)]);
  return text;
}

}  // namespace qmaps
