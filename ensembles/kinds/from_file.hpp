#pragma once
// The `file` ensemble: the orbits of an earlier qmaps run (docs/hdf5-schema.md), continued.
//   group = "final" (default): each orbit continues from the earlier run's exact map state
//     /final/state (no round trip through phase space), so the continuation steps exactly as the
//     earlier run would have gone on; orbits escaped there stay escaped (escape step 0 here,
//     with the earlier reason). Its /initial is the phase point of that state.
//   group = "initial": the earlier run's starting points /initial, started by this run's rule.
// The file's map and every parameter must equal this run's; a mismatch names both.
#include <string>
#include <vector>

#include "core/model.hpp"
#include "ensembles/kinds/ensemble_kind.hpp"

namespace qmaps {

class FromFile final : public EnsembleKind {
 public:
  // Reads [ensemble] path and group; the file is read (and checked) now.
  FromFile(const Config& config, const Model& model);
  std::size_t orbits() const override { return orbits_; }
  Drawn draw(std::size_t orbit) const override;
  std::string description() const override;
  // group = "final": the orbits continue the file's states (continue_into()), not its points.
  bool continues() const override { return final_; }
  // Starts orbit i of `e` in the file's state of orbit first + i, the orbits escaped there
  // escaped at step 0.
  void continue_into(Ensemble& e, std::size_t first, double escape_bound) const override;

 private:
  const Model& model_;
  std::string path_;
  bool final_;
  std::size_t orbits_ = 0;
  long long step_ = 0;                        // the earlier run's final step
  std::vector<std::vector<double>> columns_;  // state (final) or q1 q2 p1 p2 (initial)
  std::vector<std::int64_t> escape_step_, escape_reason_;
};

}  // namespace qmaps
