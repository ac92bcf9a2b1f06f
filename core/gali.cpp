// GALI_k from Eigen's SVD: the generalized alignment index of k unit deviation vectors is the
// volume of the parallelepiped they span, the product of the singular values of the 4 × k matrix
// whose columns they are.
#include <Eigen/SVD>

#include "core/tangent_map.hpp"

namespace qmaps {

double gali(const std::array<std::array<double, 4>, 4>& vectors, int k) {
  Eigen::Matrix<double, 4, Eigen::Dynamic> m(4, k);
  for (int j = 0; j < k; ++j)
    for (int i = 0; i < 4; ++i) m(i, j) = vectors[static_cast<std::size_t>(j)][static_cast<std::size_t>(i)];
  const Eigen::JacobiSVD<Eigen::Matrix<double, 4, Eigen::Dynamic>> svd(m);
  return svd.singularValues().prod();
}

}  // namespace qmaps
