#include "ensembles/config/observer_config.hpp"

#include <algorithm>
#include <cmath>
#include <set>

#include "core/error.hpp"
#include "core/memory_limit.hpp"
#include "ensembles/io/trajectories.hpp"

namespace qmaps {
namespace {

// An axis over [lo, hi) with `bins` bins: lo < hi, both finite, and a finite width and bins per
// unit (else every point, or the bin arithmetic, would be infinite).
Axis axis(const Config& config, const std::string& section, const std::string& coordinate,
          const std::string& range_key, std::int64_t bins) {
  const auto [lo, hi] = config.range(section, range_key);
  if (!(lo < hi))
    throw usage_error(config.where(section, range_key) + " is an empty range: it needs lo < hi");
  const double width = hi - lo, per_unit = static_cast<double>(bins) / width;
  if (!std::isfinite(lo) || !std::isfinite(hi) || !std::isfinite(width) ||
      !std::isfinite(per_unit) || !std::isnormal(width))
    throw usage_error(config.where(section, range_key) +
                      " must be finite, with a finite width of which each bin is a normal number");
  return {coordinate, lo, hi, bins};
}

// The most cells the histograms of a run may have together (one 8192 x 8192 density): each
// thread keeps its own counts and 16-bit tallies, 10 bytes a cell (Observers::cells).
constexpr std::int64_t max_cells = std::int64_t{1} << 26;

// `bins`: n (every axis) or [nx, ny]; each > 0. `total`: the cells of the histograms before
// this one, to which its own are added.
std::vector<std::int64_t> bins_of(const Config& config, const std::string& section,
                                  std::size_t axes, std::int64_t fallback, std::int64_t& total) {
  std::vector<std::int64_t> bins;
  if (!config.has(section, "bins")) {
    bins.assign(axes, fallback);
  } else if (const auto r = config.range_or_integer(section, "bins"); r.size() == 1) {
    bins.assign(axes, r[0]);
  } else if (r.size() == axes) {
    bins = r;
  } else {
    throw usage_error(config.where(section, "bins") + " must be a number or [" +
                      (axes == 1 ? "n" : "nx, ny") + "]");
  }
  std::int64_t cells = 1;
  for (auto b : bins) {
    if (b <= 0) throw usage_error(config.where(section, "bins") + " must be > 0");
    if (b > max_cells / cells)
      throw usage_error(config.where(section, "bins") + " asks for more than " +
                        std::to_string(max_cells) + " cells");
    cells *= b;
  }
  if (cells > max_cells - total)
    throw usage_error(config.where(section, "bins") + ": " + std::to_string(cells) +
                      " cells, with the " + std::to_string(total) +
                      " of the histograms and sections before, exceed " +
                      std::to_string(max_cells) + " cells in all");
  total += cells;
  return bins;
}

Coordinate coordinate(const Config& config, const std::string& section, const std::string& key,
                      const Model& model) {
  try {
    return parse_coordinate(config.string(section, key), model.time_per_orbit());
  } catch (const Error& e) {
    throw usage_error(config.where(section, key) + ": " + e.what());
  }
}

std::string unique_name(const Config& config, const std::string& section,
                        std::set<std::string>& names) {
  const std::string name = config.string(section, "name");
  const bool printable = std::all_of(name.begin(), name.end(), [](char c) {
    return static_cast<unsigned char>(c) >= 0x20 && c != 0x7f;
  });
  if (name.empty() || name.size() > 255 || !printable || name.find('/') != std::string::npos ||
      name.find('.') != std::string::npos)
    throw usage_error(config.where(section, "name") +
                      " must be 1 to 255 printable characters, without '/' or '.'");
  if (!names.insert(name).second)
    throw usage_error(config.where(section, "name") + ": '" + name + "' is used twice");
  return name;
}

// A section's mode: `exact` needs a map that integrates a flow, and a position plane.
SectionMode section_mode(const Config& config, const std::string& s, Coordinate plane,
                         const Model& model) {
  const std::string mode = config.string_or(s, "mode", "iterate");
  const auto known = std::ranges::find(section_mode_names, mode);
  if (known == section_mode_names.end())
    throw usage_error(config.where(s, "mode") + " must be \"iterate\", \"linear\" or \"exact\"");
  const auto m = static_cast<SectionMode>(known - section_mode_names.begin());
  if (m == SectionMode::exact && !model.flows_to_plane())
    throw usage_error(config.where(s, "mode") + ": \"exact\" integrates a flow to the plane; map '" +
                      std::string(model.name()) +
                      "' is a discrete map with no flow between iterates (use \"iterate\")");
  if (m == SectionMode::exact && is_momentum(plane))
    throw usage_error(config.where(s, "mode") + ": \"exact\" needs a plane in q1 or q2 (the plane is " +
                      std::string(coordinate_name(plane)) + ")");
  return m;
}

}  // namespace

Observers observers_from_config(const Config& config, const Model& model, std::size_t orbits,
                                long long steps) {
  Observers o;
  double slot_bytes = 0;
  std::set<std::string> names;
  std::int64_t cells = 0;
  for (std::size_t i = 0; i < config.entries("histogram"); ++i) {
    const std::string s = "histogram[" + std::to_string(i) + "]";
    const std::string name = unique_name(config, s, names);
    std::vector<Coordinate> coords = {coordinate(config, s, "x", model)};
    if (config.has(s, "y")) coords.push_back(coordinate(config, s, "y", model));
    const auto bins = bins_of(config, s, coords.size(), 64, cells);
    std::vector<Axis> axes = {axis(config, s, std::string(coordinate_name(coords[0])), "x_range", bins[0])};
    if (coords.size() == 2)
      axes.push_back(axis(config, s, std::string(coordinate_name(coords[1])), "y_range", bins[1]));
    o.densities.push_back({Histogram(name, axes), coords});
  }
  for (std::size_t i = 0; i < config.entries("section"); ++i) {
    const std::string s = "section[" + std::to_string(i) + "]";
    Section section;
    section.name = unique_name(config, s, names);
    section.plane = coordinate(config, s, "plane", model);
    if (section.plane == Coordinate::t)
      throw usage_error(config.where(s, "plane") + ": a section plane must be q1, q2, p1 or p2");
    section.value = config.number_or(s, "value", 0.0);
    const std::string direction = config.string_or(s, "direction", "+");
    if (direction != "+" && direction != "-" && direction != "both")
      throw usage_error(config.where(s, "direction") + " must be \"+\", \"-\" or \"both\"");
    section.direction = direction == "+" ? 1 : direction == "-" ? -1 : 0;
    section.mode = section_mode(config, s, section.plane, model);
    section.x = coordinate(config, s, "x", model);
    section.y = coordinate(config, s, "y", model);
    section.cap = config.integer_or(s, "cap", 100);
    if (section.cap < 0) throw usage_error(config.where(s, "cap") + " must be >= 0");
    const auto bins = bins_of(config, s, 2, 64, cells);
    section.density = Histogram(section.name, {axis(config, s, std::string(coordinate_name(section.x)), "x_range", bins[0]),
                                               axis(config, s, std::string(coordinate_name(section.y)), "y_range", bins[1])});
    // The slots are reserved now: they must fit the memory limit with those before them.
    const std::int64_t slots = Section::slots_per_orbit(section.cap, section.direction, steps);
    slot_bytes += static_cast<double>(orbits) * static_cast<double>(8 + 24 * slots);
    if (const MemoryLimit have = memory_limit(); slot_bytes > have.bytes)
      throw usage_error(config.where(s, "cap") + ": " + std::to_string(orbits) + " orbits x " +
                        std::to_string(slots) + " points (cap " + std::to_string(section.cap) +
                        ") need about " + number_text(slot_bytes / (1 << 30)) +
                        " GiB with the sections before; " + have.what + " is " +
                        number_text(have.bytes / (1 << 30)) + " GiB");
    section.points = std::make_shared<SectionPoints>(orbits, slots);
    o.sections.push_back(std::move(section));
  }
  return o;
}

std::optional<InvariantImage> invariant_image_from_config(const Config& config,
                                                          const Model& model) {
  const std::string s = "invariant_image";
  if (!config.has(s, "x") && !config.has(s, "y")) return std::nullopt;
  const auto& names = model.invariant_names();
  const auto invariant = [&](const std::string& key) {
    const std::string name = config.string(s, key);
    if (std::find(names.begin(), names.end(), name) == names.end()) {
      std::string known;
      for (const auto& n : names) known += (known.empty() ? "" : ", ") + n;
      throw usage_error(config.where(s, key) + ": '" + name + "' is not an invariant of map '" +
                        std::string(model.name()) + "' (" + known + ")");
    }
    return name;
  };
  const std::string x = invariant("x"), y = invariant("y");
  std::int64_t cells = 0;  // the image is one histogram of the whole ensemble, not per thread
  const auto bins = bins_of(config, s, 2, 128, cells);
  return InvariantImage{Histogram("invariant_image", {axis(config, s, x, "x_range", bins[0]),
                                                     axis(config, s, y, "y_range", bins[1])})};
}

std::vector<Trajectory> trajectories_from_config(const Config& config, const Model& model,
                                                 std::size_t orbits, long long steps) {
  // At most this many rows in all: a trajectory is for looking at orbits, not for storing runs.
  constexpr double most_rows = 1 << 26;
  std::vector<Trajectory> out;
  std::set<std::string> names;
  double rows = 0;
  for (std::size_t i = 0; i < config.entries("trajectory"); ++i) {
    const std::string s = "trajectory[" + std::to_string(i) + "]";
    Trajectory t;
    t.name = unique_name(config, s, names);
    if (config.has(s, "orbits") == config.has(s, "first"))
      throw usage_error(config.where(s) + ": give either orbits = [i, j, ...] or first = N");
    if (config.has(s, "first")) {
      const long long first = config.integer(s, "first");
      if (first < 1 || static_cast<std::size_t>(first) > orbits)
        throw usage_error(config.where(s, "first") + " must be 1 to the " +
                          std::to_string(orbits) + " orbits of the ensemble (got " +
                          std::to_string(first) + ")");
      for (long long k = 0; k < first; ++k) t.orbits.push_back(static_cast<std::size_t>(k));
    } else {
      std::set<std::int64_t> seen;
      for (const std::int64_t k : config.range_or_integer(s, "orbits")) {
        if (k < 0 || static_cast<std::size_t>(k) >= orbits)
          throw usage_error(config.where(s, "orbits") + ": orbit " + std::to_string(k) +
                            " is not in the ensemble's 0 to " + std::to_string(orbits - 1));
        if (!seen.insert(k).second)
          throw usage_error(config.where(s, "orbits") + ": orbit " + std::to_string(k) +
                            " is listed twice");
        t.orbits.push_back(static_cast<std::size_t>(k));
      }
      if (t.orbits.empty()) throw usage_error(config.where(s, "orbits") + " lists no orbit");
    }
    t.every = config.integer_or(s, "every", 1);
    if (t.every < 1) throw usage_error(config.where(s, "every") + " must be >= 1");
    t.columns = trajectory_columns(model);
    rows += t.rows(steps);
    if (rows > most_rows)
      throw usage_error(config.where(s, "every") + ": the trajectories would hold " +
                        std::to_string(static_cast<long long>(rows)) + " rows; at most " +
                        std::to_string(static_cast<long long>(most_rows)) +
                        " (record fewer orbits or fewer steps)");
    out.push_back(std::move(t));
  }
  return out;
}

TuneSettings tunes_from_config(const Config& config, long long steps) {
  TuneSettings t;
  if (!config.has_section("tunes")) return t;
  constexpr long long least = 32, most = 1 << 20;  // least: the window's main lobe, 2(p + 1) bins, is a tenth of the spectrum
  const long long n = config.integer_or("tunes", "window", 1024);
  const std::string window = config.where("tunes", "window") +
                             (config.has("tunes", "window") ? "" : " (the default, 1024)");
  if (n < least || n > most || (n & (n - 1)) != 0)
    throw usage_error(window + " must be a power of two from " + std::to_string(least) + " to " +
                      std::to_string(most) + " (got " + std::to_string(n) + ")");
  if (2 * n > steps)
    throw usage_error(window + ": the tunes' two windows of " + std::to_string(n) +
                      " steps need " + std::to_string(2 * n) + " steps, but " +
                      config.where("run", "steps") + " gives " + std::to_string(steps) +
                      ": set window to a power of two at most steps/2");
  t.windows.window = n;
  const long long order = config.integer_or("tunes", "order", t.windows.order);
  if (order < 1 || order > 8)
    throw usage_error(config.where("tunes", "order") +
                      " must be 1 to 8: the Hann window's order (got " + std::to_string(order) + ")");
  t.windows.order = static_cast<int>(order);
  t.report.bins = config.integer_or("tunes", "bins", t.report.bins);
  if (t.report.bins < 1 || t.report.bins > 4096)
    throw usage_error(config.where("tunes", "bins") + " must be 1 to 4096 (got " +
                      std::to_string(t.report.bins) + ")");
  t.report.diffusion_threshold =
      config.number_or("tunes", "diffusion_threshold", t.report.diffusion_threshold);
  if (!(t.report.diffusion_threshold < 0 && t.report.diffusion_threshold > -300))
    throw usage_error(config.where("tunes", "diffusion_threshold") +
                      " must be a log10 below 0 (got " +
                      number_text(t.report.diffusion_threshold) + ")");
  return t;
}

}  // namespace qmaps
