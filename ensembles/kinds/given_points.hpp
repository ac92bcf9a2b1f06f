#pragma once
// The orbits' starting points given by the caller (qmaps.run's `initial` arrays) instead of an
// [ensemble] table: orbit i starts at point i, by the run's start rule, as the same points read
// from a file's /initial would (kind file, group "initial").
#include <memory>
#include <vector>

#include "ensembles/kinds/ensemble_kind.hpp"

namespace qmaps {

class GivenPoints final : public EnsembleKind {
 public:
  // Every coordinate must be finite; the first that is not is an error naming orbit and column.
  explicit GivenPoints(std::shared_ptr<const std::vector<Phase>> points);
  std::size_t orbits() const override { return points_->size(); }
  Drawn draw(std::size_t orbit) const override { return {(*points_)[orbit], 0}; }
  std::string description() const override;

 private:
  std::shared_ptr<const std::vector<Phase>> points_;
};

}  // namespace qmaps
