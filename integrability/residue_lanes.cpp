#include "integrability/residue_lanes.hpp"

#include <cstring>
#include <limits>

#include <flint/ulong_extras.h>

namespace qmaps::exact {

thread_local const LaneField* LaneField::current_ = nullptr;

LaneField::LaneField(std::uint64_t prime)
    : p(static_cast<double>(prime)), inverse_p(1.0 / static_cast<double>(prime)), field_(prime),
      outer_(current_) {
  if (prime > max_lane_prime) throw std::logic_error("a lane prime above 2^26");
  if (prime <= (1U << 20)) {
    inverses.assign(prime, std::numeric_limits<double>::quiet_NaN());
    for (std::uint64_t a = 1; a < prime; ++a) inverses[a] = static_cast<double>(n_invmod(a, prime));
  }
  cached_bits_.fill(~0ULL);  // a NaN's pattern, which no constant has
  current_ = this;
}
LaneField::~LaneField() { current_ = outer_; }

double LaneField::constant(double x) const {
  std::uint64_t bits;
  std::memcpy(&bits, &x, sizeof bits);
  const std::size_t slot = (bits ^ (bits >> 29) ^ (bits >> 52)) % cached_.size();
  if (cached_bits_[slot] != bits) {
    cached_[slot] = static_cast<double>(PrimeField::reduce(decimal_value(x)));
    cached_bits_[slot] = bits;
  }
  return cached_[slot];
}

}  // namespace qmaps::exact
