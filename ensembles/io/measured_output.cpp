#include "ensembles/io/measured_output.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <span>
#include <stdexcept>

#include "core/error.hpp"
#include "ensembles/io/ranks.hpp"
#include "ensembles/io/statistics.hpp"
#include "ensembles/io/trajectories.hpp"

namespace qmaps {
namespace {

constexpr std::int64_t most_count = std::int64_t{1} << 53;  // no sum of counts can overflow

// counts (shape bins, or bins × bins), edges per axis, and the attributes of a histogram.
void write_histogram(const h5::Group& g, const Histogram& h, const std::string& counts_name) {
  std::vector<hsize_t> dims;
  for (const Axis& a : h.axes()) dims.push_back(static_cast<hsize_t>(a.bins));
  g.write(counts_name, std::span<const std::int64_t>(h.counts()), dims);
  const char* edge_names[2] = {"x_edges", "y_edges"};
  const char* coordinate_names[2] = {"x", "y"};
  for (std::size_t k = 0; k < h.axes().size(); ++k) {
    g.write(edge_names[k], h.axes()[k].edges());
    g.attr(coordinate_names[k], h.axes()[k].coordinate);
  }
  g.attr("underflow", h.underflow());
  g.attr("overflow", h.overflow());
  g.attr("samples", h.samples());
}

// Counts of a histogram as a run leaves them: 0 ≤ count ≤ 2^53.
void restore_histogram(const h5::Group& g, const std::string& counts, Histogram& h) {
  const auto cells = g.read_int64(counts, h.counts().size());
  const std::int64_t under = g.attr_int64("underflow"), over = g.attr_int64("overflow");
  for (const std::int64_t c : cells)
    if (c < 0 || c > most_count) throw g.error(counts + " holds the count " + std::to_string(c));
  if (under < 0 || under > most_count || over < 0 || over > most_count)
    throw g.error("underflow or overflow out of range");
  h.restore(cells, under, over);
}

// Reads elements [first, first + count) of dataset `name` of `g`, which must hold `total`.
template <class T>
std::vector<T> read_column(const h5::Group& g, const std::string& name, std::size_t first,
                           std::size_t count, std::size_t total) {
  if (g.shape(name) != std::vector<hsize_t>{total})
    throw Error(ExitCode::io, "HDF5: dataset " + g.path() + "/" + name + " does not hold " +
                                  std::to_string(total) + " elements");
  std::vector<T> out(count);
  g.read_part<T>(name, first, std::span<T>(out));
  return out;
}

std::string last_part(const std::string& path) { return path.substr(path.rfind('/') + 1); }

// The histogram of every rank's values, in orbit order: the same range and quartiles on each.
void write_distribution(const h5::Group& root, const MeasuredOutput::Distribution& d) {
  const std::vector<double> all = ranks::gathered(d.values);
  double lo = 0, hi = 1;
  if (!all.empty()) {
    const auto [min, max] = std::minmax_element(all.begin(), all.end());
    lo = *min;
    hi = *max > *min ? std::nextafter(*max, HUGE_VAL) : *min + 1;
  }
  const std::string name = last_part(d.group);
  Histogram h(name, {Axis{name, lo, hi, d.bins}});
  for (double v : all) h.add(&v);
  const auto g = root.group_at(d.group);
  write_histogram(g, h, "counts");
  const auto q = quantiles(all, {0.25, 0.5, 0.75});
  g.attr("q1", q[0]);
  g.attr("median", q[1]);
  g.attr("q3", q[2]);
}

// The columns orbit, step, x, y of the points, in parts read in (orbit, step) order: no second
// copy. A rank's points follow those of the ranks before it, as its orbits do.
void write_events(const h5::Group& g, const SectionPoints& points, Rows orbits) {
  const std::size_t n = points.size();
  const auto mine = static_cast<std::int64_t>(n);
  const Rows rows{static_cast<std::size_t>(ranks::before(mine)), n,
                  static_cast<std::size_t>(ranks::sum(mine))};
  std::vector<SectionPoint> part(std::min(n, orbits_per_part));
  SectionPoints::Cursor cursor;
  for (const char* name : {"orbit", "step"}) g.create_column<std::int64_t>(name, rows.total);
  for (const char* name : {"x", "y"}) g.create_column<double>(name, rows.total);
  std::vector<std::int64_t> orbit(part.size()), step(part.size());
  std::vector<double> x(part.size()), y(part.size());
  for (std::size_t p = 0, parts = parts_of(n); p < parts; ++p) {
    const std::size_t first = std::min(p * orbits_per_part, n);
    const std::size_t count = std::min(orbits_per_part, n - first);
    points.read(first, std::span(part).first(count), cursor);
    for (std::size_t i = 0; i < count; ++i) {
      orbit[i] = part[i].orbit + static_cast<std::int64_t>(orbits.first);
      step[i] = part[i].step;
      x[i] = part[i].x;
      y[i] = part[i].y;
    }
    g.write_part<std::int64_t>("orbit", rows.first + first, std::span(orbit).first(count));
    g.write_part<std::int64_t>("step", rows.first + first, std::span(step).first(count));
    g.write_part<double>("x", rows.first + first, std::span(x).first(count));
    g.write_part<double>("y", rows.first + first, std::span(y).first(count));
  }
}

// Sets `kept` to the points of the file's orbits `orbits` at `g`, each orbit's in step order,
// as many as the file says it keeps.
void restore_events(const h5::Group& g, SectionPoints& kept, Rows orbits) {
  const auto counts = read_column<std::int64_t>(g, "kept", orbits.first, orbits.count, orbits.total);
  std::size_t points = 0;
  for (const std::int64_t k : counts) {
    if (k < 0 || k > kept.per_orbit())
      throw g.error("an orbit keeps " + std::to_string(k) + " points, not 0 to " +
                    std::to_string(kept.per_orbit()));
    points += static_cast<std::size_t>(k);
  }
  // This process's points follow those of the orbits before its rows.
  const auto mine = static_cast<std::int64_t>(points);
  const auto before = static_cast<std::size_t>(ranks::before(mine));
  const auto total = static_cast<std::size_t>(ranks::sum(mine));
  const auto orbit = read_column<std::int64_t>(g, "orbit", before, points, total);
  const auto step = read_column<std::int64_t>(g, "step", before, points, total);
  const auto x = read_column<double>(g, "x", before, points, total);
  const auto y = read_column<double>(g, "y", before, points, total);
  kept.clear();
  const auto first = static_cast<std::int64_t>(orbits.first);
  for (std::size_t i = 0; i < points; ++i) {
    const bool ordered = i == 0 || orbit[i] > orbit[i - 1] ||
                         (orbit[i] == orbit[i - 1] && step[i] > step[i - 1]);
    if (!ordered || orbit[i] < first ||
        static_cast<std::size_t>(orbit[i] - first) >= counts.size() || step[i] < 1 ||
        !std::isfinite(x[i]) || !std::isfinite(y[i]))
      throw g.error("point " + std::to_string(before + i) + " is not one a run records");
    kept.keep(static_cast<std::size_t>(orbit[i] - first), step[i], x[i], y[i]);
  }
  if (!std::ranges::equal(counts, kept.kept()))
    throw g.error("its points are not spread over the orbits as kept says");
}

// The rows of a checkpoint's series, at most those its orbits can give.
void restore_series(const h5::Group& g, Trajectory& t, long long steps) {
  const auto shape = g.shape("orbit");
  if (shape.size() != 1) throw g.error("orbit is not a column");
  const auto rows = static_cast<std::size_t>(shape[0]);
  if (static_cast<double>(rows) > t.rows(steps))
    throw g.error("it holds " + std::to_string(rows) + " rows; its orbits and steps give at most " +
                  std::to_string(static_cast<long long>(t.rows(steps))));
  t.orbit = g.read_int64("orbit", rows);
  t.step = g.read_int64("step", rows);
  t.values.clear();
  for (const auto& name : t.columns) t.values.push_back(g.read_doubles(name, rows));
}

// Appends the rows of `part` (of its orbits, numbered from 0) as orbits first + o, then orders
// every row orbit by orbit as `whole` lists its orbits, each orbit's in step order.
void add_series(Trajectory& whole, const Trajectory& part, std::size_t first, const std::string& where) {
  whole.values.resize(whole.columns.size());
  for (std::size_t row = 0; row < part.orbit.size(); ++row) {
    const auto o = part.orbit[row];
    if (o < 0 || std::ranges::find(part.orbits, static_cast<std::size_t>(o)) == part.orbits.end())
      throw Error(ExitCode::io, where + " has a row of orbit " + std::to_string(o) +
                                    ", not one of the orbits it records");
    whole.orbit.push_back(static_cast<std::int64_t>(first) + o);
    whole.step.push_back(part.step[row]);
    for (std::size_t c = 0; c < whole.columns.size(); ++c) whole.values[c].push_back(part.values[c][row]);
  }
  std::map<std::int64_t, std::size_t> place;
  for (std::size_t k = 0; k < whole.orbits.size(); ++k)
    place[static_cast<std::int64_t>(whole.orbits[k])] = k;
  std::vector<std::size_t> order(whole.orbit.size());
  for (std::size_t r = 0; r < order.size(); ++r) order[r] = r;
  std::ranges::stable_sort(order, {}, [&](std::size_t r) { return place.at(whole.orbit[r]); });
  reorder_rows(whole, order);
}

void check_aligned(const MeasuredOutput& whole, const MeasuredOutput& part) {
  if (whole.histograms.size() != part.histograms.size() ||
      whole.attributes.size() != part.attributes.size() || whole.events.size() != part.events.size() ||
      whole.series.size() != part.series.size())
    throw std::logic_error("add_part: the part is described otherwise than the whole");
}

}  // namespace

void write_output(const h5::Group& root, const MeasuredOutput& out, Rows rows, bool per_orbit) {
  for (const auto& h : out.histograms) {
    Histogram total = *h.histogram;
    add_over_ranks(total);
    write_histogram(root.group_at(h.group), total, h.counts);
  }
  for (const auto& d : out.distributions) write_distribution(root, d);
  for (const auto& e : out.events) write_events(root.group_at(e.group), *e.points, rows);
  for (const auto& s : out.series) {
    const auto g = root.group_at(s.group);
    const Trajectory& t = *s.rows;
    g.write("orbit", t.orbit);
    g.write("step", t.step);
    for (std::size_t k = 0; k < t.columns.size(); ++k) g.write(t.columns[k], t.values[k]);
  }
  if (per_orbit)
    for (const auto& c : out.columns) {
      const DatasetAt at = dataset_at(root, c.path, true);
      std::visit([&](const auto& v) { write_rows(at.group, at.name, std::span(v), rows); }, c.values);
    }
  // The summed counts in one sum over the ranks; a share is of the group's sums.
  std::vector<std::int64_t> sums;
  for (const auto& a : out.attributes)
    if (a.over == MeasuredOutput::Over::summed)
      sums.push_back(a.kept ? *a.kept : std::get<std::int64_t>(a.value));
  ranks::sum(sums);
  std::map<std::pair<std::string, std::string>, std::int64_t> summed;
  for (std::size_t k = 0, s = 0; k < out.attributes.size(); ++k) {
    const auto& a = out.attributes[k];
    const auto g = root.group_at(a.group);
    if (a.over == MeasuredOutput::Over::summed) {
      summed[{a.group, a.name}] = sums[s];
      g.attr(a.name, sums[s++]);
    } else if (const auto* share = std::get_if<MeasuredOutput::Share>(&a.value)) {
      std::int64_t of = 0;
      for (const auto& name : share->of) of += summed.at({a.group, name});
      g.attr(a.name, MeasuredOutput::share(summed.at({a.group, share->part}), of));
    } else {
      std::visit([&](const auto& v) {
        if constexpr (!std::is_same_v<std::decay_t<decltype(v)>, MeasuredOutput::Share>)
          g.attr(a.name, v);
      }, a.value);
    }
  }
}

void write_kept(const h5::Group& root, const MeasuredOutput& out, Rows rows) {
  for (const auto& e : out.events) {
    const auto kept = e.points->kept();
    write_rows<std::int64_t>(root.group_at(e.group), "kept", kept, rows.or_all(kept.size()));
  }
}

void restore_kept(const h5::Group& root, MeasuredOutput& out, Rows rows) {
  const bool counts_here = ranks::root();  // each count once over the ranks
  for (auto& h : out.histograms)
    if (h.kept && counts_here) restore_histogram(root.open_group(h.group), h.counts, *h.histogram);
  for (auto& a : out.attributes) {
    if (!a.kept || !counts_here) continue;
    const auto g = root.open_group(a.group);
    if (!g.has_attr(a.name)) throw g.error("it has no attribute " + a.name);
    *a.kept = g.attr_int64(a.name);
    const std::int64_t most = a.of ? a.of->samples() : most_count;
    if (*a.kept < 0 || *a.kept > most)
      throw g.error(a.name + " is " + std::to_string(*a.kept) + ", not 0 to " +
                    (a.of ? std::to_string(most) + " (its histogram's samples)" : "2^53"));
  }
  for (auto& e : out.events)
    restore_events(root.open_group(e.group), *e.points, rows.or_all(e.points->kept().size()));
  for (auto& s : out.series)
    if (counts_here) restore_series(root.open_group(s.group), *s.rows, s.steps);
}

void add_part(MeasuredOutput& whole, const MeasuredOutput& part, std::size_t first_orbit) {
  check_aligned(whole, part);
  for (std::size_t k = 0; k < whole.histograms.size(); ++k)
    if (whole.histograms[k].kept) whole.histograms[k].histogram->merge(*part.histograms[k].histogram);
  for (std::size_t k = 0; k < whole.attributes.size(); ++k)
    if (whole.attributes[k].kept) *whole.attributes[k].kept += *part.attributes[k].kept;
  for (std::size_t k = 0; k < whole.series.size(); ++k)
    add_series(*whole.series[k].rows, *part.series[k].rows, first_orbit, "/" + part.series[k].group);
  for (std::size_t k = 0; k < whole.events.size(); ++k) {
    const SectionPoints& from = *part.events[k].points;
    SectionPoints& to = *whole.events[k].points;
    SectionPoints::Cursor cursor;
    std::vector<SectionPoint> some(std::min<std::size_t>(from.size(), std::size_t{1} << 16));
    for (std::size_t at = 0; at < from.size(); at += some.size()) {  // by parts: no second copy
      const auto points = std::span(some).first(std::min(some.size(), from.size() - at));
      from.read(at, points, cursor);
      for (const SectionPoint& p : points)
        to.keep(first_orbit + static_cast<std::size_t>(p.orbit), p.step, p.x, p.y);
    }
  }
}

}  // namespace qmaps
