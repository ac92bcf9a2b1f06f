#include "ensembles/config/shard.hpp"

#include <charconv>

#include "core/error.hpp"

namespace qmaps {

Shard Shard::parse(std::string_view text) {
  Shard s;
  const auto slash = text.find('/');
  const auto whole = [](std::string_view part, std::size_t& out) {
    const auto [end, ec] = std::from_chars(part.data(), part.data() + part.size(), out);
    return ec == std::errc() && end == part.data() + part.size() && !part.empty();
  };
  if (slash == std::string_view::npos || !whole(text.substr(0, slash), s.index) ||
      !whole(text.substr(slash + 1), s.count) || s.index < 1 || s.index > s.count ||
      s.count > most)
    throw usage_error("--shard " + std::string(text) + ": expected k/K with 1 <= k <= K <= " +
                      std::to_string(most));
  return s;
}

}  // namespace qmaps
