// /chaos (docs/chaos.md): each indicator of every orbit; each one's histogram and quartiles over
// the orbits that stayed bounded (log10 of the GALIs); the orbits' classes by MEGNO.
#include "ensembles/io/run_observers/chaos_summary.hpp"

#include <cmath>

#include <omp.h>

#include "ensembles/io/run_observers/run_observers.hpp"

namespace qmaps {

ChaosTable chaos_table(const Model& model, const Ensemble& e, double megno_threshold) {
  ChaosTable t;
  t.names = model.indicator_names();
  const std::size_t n = e.orbits;
  t.values.assign(t.names.size(), std::vector<double>(n));
  const long long orbits = static_cast<long long>(n);
#pragma omp parallel for schedule(static) num_threads(omp_get_max_threads())
  for (long long r = 0; r < orbits; ++r) {
    const auto i = static_cast<std::size_t>(r);
    const auto v = model.indicators(e, i);
    for (std::size_t k = 0; k < v.size(); ++k) t.values[k][i] = v[k];
  }
  t.classes.resize(n);
  if (t.names.empty()) return t;
  const std::size_t megno = 2;  // indicator_names(): lyapunov, fli, megno, …
  for (std::size_t i = 0; i < n; ++i) {
    t.classes[i] = e.escape_step[i] >= 0                  ? 2
                   : t.values[megno][i] > megno_threshold ? 1
                                                          : 0;
    ++(t.classes[i] == 0 ? t.regular : t.classes[i] == 1 ? t.chaotic : t.escaped);
  }
  return t;
}

bool ChaosTable::logarithmic(std::size_t k) const { return names[k].starts_with("gali"); }

std::string ChaosTable::histogram_name(std::size_t k) const {
  return logarithmic(k) ? "log10_" + names[k] : names[k];
}

std::vector<double> ChaosTable::bounded(std::size_t k) const {
  std::vector<double> out;
  for (std::size_t i = 0; i < classes.size(); ++i) {
    const double v = logarithmic(k) ? std::log10(values[k][i]) : values[k][i];
    if (classes[i] != 2 && std::isfinite(v)) out.push_back(v);
  }
  return out;
}

void describe_chaos(const RunRecord& run, MeasuredOutput& out) {
  if (run.model.indicator_names().empty()) return;
  ChaosTable t = chaos_table(run.model, run.ensemble, run.chaos.megno_threshold);
  using Over = MeasuredOutput::Over;
  out.attribute("chaos", "megno_threshold", run.chaos.megno_threshold);
  out.attribute("chaos", "regular", t.regular, Over::summed);
  out.attribute("chaos", "chaotic", t.chaotic, Over::summed);
  out.attribute("chaos", "escaped", t.escaped, Over::summed);
  out.attribute("chaos", "chaotic_fraction", MeasuredOutput::Share{"chaotic", {"regular", "chaotic"}});
  out.attribute("chaos", "class_codes",
                std::string("0 regular, 1 chaotic (megno > megno_threshold), 2 escaped"));
  out.attribute("chaos", "unit", std::string("Lyapunov exponents per step"));
  for (std::size_t k = 0; k < t.names.size(); ++k)
    out.distributions.push_back({"chaos/histograms/" + t.histogram_name(k), t.bounded(k), run.chaos.bins});
  for (std::size_t k = 0; k < t.names.size(); ++k)
    out.columns.push_back({"chaos/" + t.names[k], std::move(t.values[k])});
  out.columns.push_back({"chaos/class", std::move(t.classes)});
}

}  // namespace qmaps
