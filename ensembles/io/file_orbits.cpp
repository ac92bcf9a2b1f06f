#include "ensembles/io/file_orbits.hpp"

#include <cstdio>

#include "core/error.hpp"
#include "core/memory_limit.hpp"

namespace qmaps {

std::size_t orbits_in(const h5::Group& root, const std::string& path, double bytes_per_orbit) {
  const std::int64_t orbits = root.attr_int64("orbits");
  if (orbits < 0)
    throw Error(ExitCode::io, "'" + path + "': attribute orbits is " + std::to_string(orbits));
  const MemoryLimit limit = memory_limit();
  if (static_cast<double>(orbits) * bytes_per_orbit > limit.bytes) {
    char text[200];
    std::snprintf(text, sizeof text, "%.3g GiB; %s is %.3g GiB",
                  static_cast<double>(orbits) * bytes_per_orbit / (1 << 30), limit.what.c_str(),
                  limit.bytes / (1 << 30));
    throw Error(ExitCode::io, "'" + path + "': its attribute orbits = " + std::to_string(orbits) +
                                  " would need " + text);
  }
  return static_cast<std::size_t>(orbits);
}

}  // namespace qmaps
