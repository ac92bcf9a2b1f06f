#include "integrability/height_growth.hpp"

#include <algorithm>
#include <cmath>
#include <random>

namespace qmaps::exact {

HeightTest height_test(const ExactMap& map, int steps, double max_bits, std::uint64_t seed) {
  HeightTest t;
  t.steps = steps;
  t.max_bits = max_bits;
  std::mt19937_64 random(seed);
  State<Rational> s;
  for (std::size_t k = 0; k < 4; ++k) {  // a/b, |a| ≤ 9, 1 ≤ b ≤ 9, in lowest terms
    mpq_class q(static_cast<long>(random() % 19) - 9, static_cast<unsigned long>(random() % 9 + 1));
    q.canonicalize();
    s[k] = Rational(q);
    t.start.push_back(q.get_str());
  }
  const auto height = [&] {
    double h = 0;
    for (const std::size_t k : map.varying) h = std::max(h, s[k].log_height());
    return h;
  };
  t.log_heights.push_back(height());
  const double max_log = max_bits * std::log(2.0);
  // Within a step, no operand beyond 8 times the cap (a step of degree d multiplies heights by d).
  const HeightLimit limit(8 * max_bits);
  for (int n = 1; n <= steps; ++n) {
    try {
      map.step(s);
    } catch (const DivisionByZero&) {
      t.stopped = "a denominator vanished at step " + std::to_string(n);
      break;
    } catch (const HeightCap&) {
      t.stopped = "the height cap (" + std::to_string(static_cast<long>(max_bits)) +
                  " bits, 8 times that within a step) at step " + std::to_string(n);
      break;
    }
    t.log_heights.push_back(height());
    if (t.log_heights.back() > max_log) {
      t.stopped = "the height cap (" + std::to_string(static_cast<long>(max_bits)) +
                  " bits) at step " + std::to_string(n);
      break;
    }
  }
  t.growth = fit_growth(t.log_heights, false);
  return t;
}

}  // namespace qmaps::exact
