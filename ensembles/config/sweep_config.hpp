#pragma once
// [[sweep]]: the axes of a parameter sweep (docs/sweeps.md). One or two tables, each varying one
// map parameter, or a ratio "beta/alpha" (beta set to the value times alpha's value at that point),
// over a list (values = [...]) or a grid (from, to, points; scale = "linear" or "log"). The sweep's
// points are the axes' product, the first axis slowest; each runs the configuration with its own
// parameter values.
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "core/model.hpp"
#include "ensembles/config/config.hpp"

namespace qmaps {

struct SweepAxis {
  std::string parameter;    // as written: "delta" or "beta/alpha"
  std::string numerator;    // the map parameter it sets
  std::string denominator;  // a ratio's denominator; empty for a plain parameter
  std::vector<double> values;
  std::string name() const;  // a dataset's name: "delta", "beta_over_alpha"
};

class Sweep {
 public:
  // The sweep of the configuration's [[sweep]] tables over `base` (the model of its [map]), or
  // none; every error names its table and key.
  static std::optional<Sweep> from_config(const Config& config, const Model& base);

  const std::vector<SweepAxis>& axes() const { return axes_; }
  std::size_t points() const;
  std::vector<std::size_t> shape() const;  // each axis's length
  double axis_value(std::size_t point, std::size_t axis) const;
  // "beta/alpha = 8, delta/alpha = 6": the point in messages.
  std::string label(std::size_t point) const;
  // Every parameter of the map at the point, in the order of the model's param_specs().
  std::vector<double> parameters(std::size_t point) const;
  // The configuration of one point: `config` with the swept parameters' values in [map].
  Config config_of(const Config& config, std::size_t point) const;

 private:
  std::vector<SweepAxis> axes_;
  std::vector<std::string> names_;  // the map's parameters
  std::vector<double> base_;        // their values in [map] (defaults filled in)
};

}  // namespace qmaps
