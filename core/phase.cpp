#include "core/phase.hpp"

#include <string>

#include "core/error.hpp"

namespace qmaps {

Start parse_start(std::string_view name) {
  if (name == "taylor") return Start::taylor;
  if (name == "euler") return Start::euler;
  throw usage_error("unknown start rule '" + std::string(name) + "' (expected taylor or euler)");
}

std::string_view start_name(Start start) { return start == Start::taylor ? "taylor" : "euler"; }

}  // namespace qmaps
