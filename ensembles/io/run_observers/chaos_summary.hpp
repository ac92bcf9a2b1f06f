#pragma once
// The chaos indicators of every orbit (docs/chaos.md) and its class: 0 regular, 1 chaotic (MEGNO
// above the threshold), 2 escaped; /chaos in a run's file, a sweep's per-point summary.
#include <cstdint>
#include <string>
#include <vector>

#include "core/ensemble.hpp"
#include "core/model.hpp"
#include "ensembles/io/run_observers/orbit_classes.hpp"

namespace qmaps {

struct ChaosTable : OrbitClasses {
  std::vector<std::string> names;           // indicator_names(): lyapunov, fli, megno, …
  std::vector<std::vector<double>> values;  // [indicator][orbit]
  std::vector<std::uint8_t> classes;
  bool logarithmic(std::size_t k) const;  // the GALIs are summarized as log10
  std::string histogram_name(std::size_t k) const;  // "log10_gali2" for a GALI
  // Indicator k (log10 where logarithmic) over the orbits that stayed bounded, where finite.
  std::vector<double> bounded(std::size_t k) const;
};
ChaosTable chaos_table(const Model& model, const Ensemble& e, double megno_threshold);

}  // namespace qmaps
