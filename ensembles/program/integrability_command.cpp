// `qmaps integrability --map MAP`: whether a rational map is integrable, by three exact tests
// (integrability/verdict.hpp, docs/integrability.md), as text and, with --output, an HDF5 file
// (the schema in docs/integrability.md), written atomically under the output's lock.
#include <ostream>

#include "core/error.hpp"
#include "ensembles/config/config.hpp"
#include "ensembles/config/map_config.hpp"
#include "ensembles/io/h5.hpp"
#include "ensembles/io/output_lock.hpp"
#include "ensembles/program/commands.hpp"
#include "core/version.hpp"
#include "integrability/verdict.hpp"

namespace qmaps {

exact::ExactMap exact_map_named(const std::string& map, const ParamValues& params) {
  if (!names_file(map)) return exact::exact_map(map, params);
  const Config config = formula_map_file(map, params);
  const auto definition = definition_of(config);
  const auto values =
      resolve_params(definition->text().name, definition->params(), map_params(config));
  try {
    return exact::exact_map(definition, values);
  } catch (const formula::DefinitionError& e) {
    throw Error(e.code(), config.where("map", e.key()) + ": " + e.reason());
  }
}

namespace {

void write_growth(const h5::Group& g, const exact::Growth& growth) {
  g.attr("growth", exact::to_string(growth.kind));
  g.attr("polynomial_degree", growth.degree);
  g.attr("lambda", growth.lambda);
  g.attr("entropy", growth.entropy);
  g.attr("entropy_error", growth.entropy_error);
  g.attr("generating_function", growth.generating_function);
  g.attr("characteristic_polynomial", growth.characteristic);
  g.attr("reason", growth.reason);
}

void write_report(const h5::Group& root, const exact::Report& r) {
  const h5::Group top = root.create_group("integrability");
  top.attr("qmaps_version", build::version);
  top.attr("map", r.map);
  top.attr("evaluated_by", r.evaluated_by);
  top.attr("verdict", exact::to_string(r.verdict));
  top.attr("reason", r.reason);
  top.attr("tests_agree", static_cast<std::int64_t>(r.tests_agree));
  std::string varying;
  for (const auto& v : r.varying) varying += (varying.empty() ? "" : ",") + v;
  top.attr("coordinates", varying);

  const h5::Group degrees = top.create_group("degrees");
  degrees.attr("says", exact::to_string(r.degree_says));
  degrees.attr("agree", static_cast<std::int64_t>(r.degrees.agree));
  degrees.attr("steps", static_cast<std::int64_t>(r.degrees.steps));
  degrees.attr("cap", static_cast<std::int64_t>(r.degrees.cap));
  write_growth(degrees, r.degrees.growth);
  for (std::size_t k = 0; k < r.degrees.runs.size(); ++k) {
    const auto& run = r.degrees.runs[k];
    const h5::Group g = degrees.create_group("run" + std::to_string(k));
    g.attr("prime", static_cast<std::int64_t>(run.prime));
    g.attr("line", static_cast<std::int64_t>(run.line));
    g.attr("stopped", run.stopped);
    std::vector<std::int64_t> d(run.degrees.begin(), run.degrees.end());
    g.write("degrees", std::span<const std::int64_t>(d));
  }

  const h5::Group fields = top.create_group("finite_fields");
  fields.attr("says", exact::to_string(r.field_says));
  fields.attr("near_R", exact::near_R);
  fields.attr("far_from_R", exact::far_from_R);
  fields.attr("significance", exact::significance);
  fields.attr("invariants_exact", static_cast<std::int64_t>(r.invariants_exact));
  for (const auto& f : r.fields) {
    const h5::Group g = fields.create_group("p" + std::to_string(f.prime));
    g.attr("prime", static_cast<std::int64_t>(f.prime));
    g.attr("dimension", static_cast<std::int64_t>(f.dimension));
    g.attr("orbits", static_cast<std::int64_t>(f.orbits));
    g.attr("singular", static_cast<std::int64_t>(f.singular));
    g.attr("past_max_period", static_cast<std::int64_t>(f.unfinished));
    g.attr("max_period", static_cast<std::int64_t>(f.max_period));
    g.attr("steps", f.steps);
    g.attr("lambda", f.lambda);
    g.attr("ks_distance", f.ks_distance);
    g.attr("p_value", f.p_value);
    g.attr("level_checked", static_cast<std::int64_t>(f.level_checked));
    g.attr("level_kept", static_cast<std::int64_t>(f.level_kept));
    std::vector<std::int64_t> periods(f.periods.begin(), f.periods.end());
    g.write("periods", std::span<const std::int64_t>(periods));
  }

  const h5::Group heights = top.create_group("heights");
  heights.attr("says", exact::to_string(r.height_says));
  std::string start;
  for (const auto& s : r.heights.start) start += (start.empty() ? "" : ",") + s;
  heights.attr("start", start);
  heights.attr("stopped", r.heights.stopped);
  write_growth(heights, r.heights.growth);
  heights.write("log_heights", std::span<const double>(r.heights.log_heights));
}

}  // namespace

exact::Report integrability_report(const IntegrabilityCommandOptions& o) {
  const exact::ExactMap map = exact_map_named(o.map, parse_params(o.sets));
  return exact::integrability_report(map, exact::resolved(o.tests, map));
}

int integrability_command(const IntegrabilityCommandOptions& o, std::ostream& out) {
  if (!o.output.empty()) h5::AtomicFile::check_writable(o.output);  // before the work
  const exact::Report r = integrability_report(o);
  exact::write_text(out, r);
  if (!o.output.empty()) {
    const OutputLock lock(o.output);
    h5::AtomicFile file(o.output, false);
    h5::File h = file.create_hdf5();
    write_report(h.root(), r);
    h.close();
    file.commit();
    out << "\nwritten to " << o.output << "\n";
  }
  return 0;
}

}  // namespace qmaps
