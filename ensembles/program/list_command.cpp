// `qmaps list`: every map with its parameters (meaning, default), invariants and the paper's
// equations it implements.
#include <cmath>
#include <ostream>

#include "core/error.hpp"
#include "kernels/catalogue.hpp"
#include "ensembles/program/commands.hpp"

namespace qmaps {

int list_command(std::ostream& out) {
  for (const auto& m : catalogue()) {
    out << m.name << ": " << m.summary << '\n';
    out << "  equations:  " << m.equations << '\n';
    out << "  invariants: " << m.invariant_summary << '\n';
    out << "  parameters:\n";
    for (const auto& p : m.params) {
      const std::string given = !std::isnan(p.default_value)
                                    ? "default " + number_text(p.default_value)
                                : p.optional ? "optional"
                                             : "required";
      out << "    " << p.name << std::string(p.name.size() < 8 ? 8 - p.name.size() : 1, ' ')
          << p.meaning << " (" << given << ")\n";
    }
  }
  return 0;
}

}  // namespace qmaps
