// `qmaps list`: every built-in map with its parameters (meaning, default), invariants and the
// paper's equations it implements; `qmaps list FILE.toml …`: each map written as formulas there,
// with its form, parameters, formulas and invariants.
#include <cmath>
#include <ostream>
#include <sstream>

#include "core/error.hpp"
#include "ensembles/config/map_config.hpp"
#include "kernels/catalogue.hpp"
#include "ensembles/program/commands.hpp"

namespace qmaps {

void write_formulas(std::ostream& out, const std::vector<std::pair<std::string, std::string>>& keys) {
  for (const auto& [key, text] : keys) {
    std::istringstream lines(text);
    out << "  " << key << ":";
    std::string line;
    int written = 0;
    const std::string indent(key.size() + 4, ' ');
    while (std::getline(lines, line)) {
      if (line.empty()) continue;
      if (written++) out << '\n' << indent;
      else out << ' ';
      out << line;
    }
    out << '\n';
  }
}

int list_command(const std::vector<std::string>& files, std::ostream& out) {
  for (const std::string& file : files) {
    const auto model = map_named(file, {}, std::nullopt);
    out << model->name() << ": a map written as formulas (" << file << ")\n";
    write_formulas(out, model->formulas());
    const auto& invariants = model->invariant_names();
    out << "  invariants tracked:";
    for (const auto& name : invariants) out << ' ' << name;
    out << (invariants.empty() ? " none\n" : "\n");
  }
  if (!files.empty()) return 0;
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
