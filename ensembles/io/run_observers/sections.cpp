// /sections/<name> (docs/hdf5-schema.md): each section's kept points (orbit, step, x, y), its
// density over every crossing, and its plane, direction, mode, cap and counts
// (core/observers/section/section.hpp).
#include "ensembles/io/run_observers/run_observers.hpp"

namespace qmaps {

void describe_sections(const RunRecord& run, MeasuredOutput& out) {
  if (!run.observers) return;
  using Over = MeasuredOutput::Over;
  for (Section& s : run.observers->sections) {
    const std::string group = "sections/" + s.name;
    out.events.push_back({group, s.points.get()});
    out.histograms.push_back({group, "density", &s.density, true});
    out.attribute(group, "plane", std::string(coordinate_name(s.plane)));
    out.attribute(group, "value", s.value);
    out.attribute(group, "direction",
                  std::string(s.direction > 0 ? "+" : s.direction < 0 ? "-" : "both"));
    out.attribute(group, "mode", std::string(section_mode_names[static_cast<std::size_t>(s.mode)]));
    if (s.mode == SectionMode::exact)
      out.attributes.push_back(
          {group, "interpolated", std::int64_t{0}, Over::summed, &s.interpolated, &s.density});
    out.attribute(group, "cap", s.cap);
    out.attribute(group, "crossings", s.density.samples(), Over::summed);
  }
}

}  // namespace qmaps
