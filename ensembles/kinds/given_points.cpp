#include "ensembles/kinds/given_points.hpp"

#include <cmath>

#include "core/error.hpp"

namespace qmaps {

GivenPoints::GivenPoints(std::shared_ptr<const std::vector<Phase>> points)
    : points_(std::move(points)) {
  if (points_->empty()) throw usage_error("initial conditions: no points given");
  static constexpr const char* names[] = {"q1", "q2", "p1", "p2"};
  for (std::size_t i = 0; i < points_->size(); ++i) {
    const auto x = as_array((*points_)[i]);
    for (int k = 0; k < 4; ++k)
      if (!std::isfinite(x[k]))
        throw usage_error("initial conditions: " + std::string(names[k]) + " of orbit " +
                          std::to_string(i) + " is " + number_text(x[k]) + ", not finite");
  }
}

std::string GivenPoints::description() const {
  const std::size_t n = points_->size();
  return std::to_string(n) + (n == 1 ? " point" : " points") + " given by the caller";
}

}  // namespace qmaps
