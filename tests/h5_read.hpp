#pragma once
// Whole datasets of a file this program wrote, their length taken from the file itself (the
// program's own readers are told the length they expect).
#include <cstdint>
#include <string>
#include <vector>

#include "core/io/h5.hpp"

namespace qmaps::testing {

inline std::size_t elements(const h5::Group& g, const std::string& name) {
  std::size_t n = 1;
  for (const auto d : g.shape(name)) n *= static_cast<std::size_t>(d);
  return n;
}
inline std::vector<double> all_doubles(const h5::Group& g, const std::string& name) {
  return g.read_doubles(name, elements(g, name));
}
inline std::vector<std::int64_t> all_int64(const h5::Group& g, const std::string& name) {
  return g.read_int64(name, elements(g, name));
}

}  // namespace qmaps::testing
