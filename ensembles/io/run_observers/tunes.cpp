// /tunes (docs/tunes.md): each orbit's tunes over both windows and its diffusion (the lane
// measurement's columns), their histograms with quartiles, the frequency map (the 2D histogram of
// (ν1, ν2) over [0, 1/2]²) and the orbits' classes by diffusion.
#include <cmath>

#include "core/observers/lane_observers.hpp"
#include "core/observers/tunes/tunes.hpp"
#include "ensembles/io/run_observers/run_observers.hpp"
#include "ensembles/io/run_observers/tune_summary.hpp"

namespace qmaps {

using Column = TuneColumns;

TuneTable tune_table(const Ensemble& e, double diffusion_threshold) {
  TuneTable t;
  t.columns = e.columns_of(lane_index<Tunes>);
  if (t.columns.empty()) return t;
  const auto& diffusion = t.columns[Column::diffusion];
  const double floor = diffusion_floor();
  t.classes.resize(e.orbits);
  for (std::size_t i = 0; i < e.orbits; ++i) {
    const double d = diffusion[i];
    t.classes[i] = !std::isnan(d)            ? (d > diffusion_threshold ? 1 : 0)
                   : e.escape_step[i] >= 0 ? 2
                                           : 3;
    ++(t.classes[i] == 0 ? t.regular : t.classes[i] == 1 ? t.chaotic : t.classes[i] == 2 ? t.escaped : t.no_tune);
    if (d == floor) ++t.round_off;
  }
  return t;
}

std::vector<double> TuneTable::finite(std::size_t c) const {
  std::vector<double> out;
  for (std::size_t i = 0; i < classes.size(); ++i)
    if (std::isfinite(columns[c][i])) out.push_back(columns[c][i]);
  return out;
}

void describe_tunes(const RunRecord& run, MeasuredOutput& out) {
  const TuneTable t = tune_table(run.ensemble, run.tunes.diffusion_threshold);
  if (t.columns.empty()) return;
  using Over = MeasuredOutput::Over;
  const auto bins = static_cast<std::int64_t>(run.tunes.bins);
  out.attribute("tunes", "window", static_cast<std::int64_t>(run.plan.tunes.window));
  out.attribute("tunes", "order", static_cast<std::int64_t>(run.plan.tunes.order));
  out.attribute("tunes", "bins", bins);
  out.attribute("tunes", "signal", std::string("q1, q2"));
  out.attribute("tunes", "folding", std::string("[0, 1/2]"));
  out.attribute("tunes", "diffusion_floor", diffusion_floor());
  out.attribute("tunes", "diffusion_threshold", run.tunes.diffusion_threshold);
  out.attribute("tunes", "regular", t.regular, Over::summed);
  out.attribute("tunes", "chaotic", t.chaotic, Over::summed);
  out.attribute("tunes", "escaped", t.escaped, Over::summed);
  out.attribute("tunes", "no_tune", t.no_tune, Over::summed);
  out.attribute("tunes", "round_off", t.round_off, Over::summed);
  out.attribute("tunes", "chaotic_fraction", MeasuredOutput::Share{"chaotic", {"regular", "chaotic"}});
  out.attribute("tunes", "class_codes",
                std::string("0 regular, 1 chaotic (diffusion > diffusion_threshold), 2 escaped "
                            "within the windows, 3 no tune (both signals 0)"));
  out.distributions.push_back({"tunes/histograms/nu1", t.finite(Column::nu1), bins});
  out.distributions.push_back({"tunes/histograms/nu2", t.finite(Column::nu2), bins});
  out.distributions.push_back({"tunes/histograms/diffusion", t.finite(Column::diffusion), bins});
  Histogram& map = out.hold(Histogram("frequency_map", {{"nu1", 0.0, 0.5, bins}, {"nu2", 0.0, 0.5, bins}}));
  for (std::size_t i = 0; i < run.ensemble.orbits; ++i)
    if (t.classes[i] < 2) {
      const double v[2] = {t.columns[Column::nu1][i], t.columns[Column::nu2][i]};
      map.add(v);
    }
  out.histograms.push_back({"tunes/frequency_map", "counts", &map, false});
  out.columns.push_back({"tunes/class", t.classes});
}

}  // namespace qmaps
