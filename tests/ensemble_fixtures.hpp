#pragma once
// Ensembles the numerical tests share: Suris orbits from a box, bounded or escaping.
#include <algorithm>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "core/model.hpp"
#include "ensembles/kinds/box.hpp"
#include "kernels/catalogue.hpp"
#include "ensembles/kinds/initial_conditions.hpp"

namespace qmaps::testing {

inline std::unique_ptr<Model> suris(double A = 0.7, double B = 0.3, double alpha = 0.9,
                                    double h = 0.1) {
  return make_model("suris", {{"A", A}, {"B", B}, {"alpha", alpha}, {"h", h}});
}

// n points uniform in [−q, q]² × [−p, p]², Philox-keyed by orbit index.
inline std::vector<Phase> box_points(std::size_t n, double q, double p, std::uint64_t seed = 7) {
  return generate(Box({{{-q, q}, {-q, q}, {-p, p}, {-p, p}}}, seed, n)).points;
}

// A map's name as a test name: "case2-hky" → "case2_hky".
inline std::string test_id(std::string_view map) {
  std::string id(map);
  std::replace(id.begin(), id.end(), '-', '_');
  return id;
}

}  // namespace qmaps::testing
