#pragma once
// What a run observer leaves in a run's file (docs/hdf5-schema.md), described once: histograms,
// attributes, per-orbit columns, events (a section's points) and series (a trajectory's rows),
// each at its path from the file's root. One writer, one checkpoint writer and reader, and one merge serve every
// observer through this description:
//   write_output   the file of a run or a checkpoint, each rank its rows, the rest over ranks:
//                  histograms added, counts summed, distributions over every rank's values;
//   write_kept     what a checkpoint or a shard keeps besides (the events' counts per orbit);
//   restore_kept   a checkpoint's kept output read back into the run's state;
//   add_part       a shard's kept output added to the whole run's (qmaps merge).
// Over the ranks of qmaps-mpi each rank describes its own orbits, alike.
// Kept items point at the state a run accumulates while it steps (its Observers); the rest are
// computed from the orbits when the file is written, and a merge computes them again.
#include <cmath>
#include <cstdint>
#include <deque>
#include <string>
#include <variant>
#include <vector>

#include "core/observers/histogram.hpp"
#include "core/observers/section/section_points.hpp"
#include "core/observers/trajectory/trajectory.hpp"
#include "ensembles/io/h5.hpp"
#include "ensembles/io/output.hpp"

namespace qmaps {

struct MeasuredOutput {
  // The share of a group's summed count `part` in the sum of the counts `of` (NaN where that is 0).
  struct Share {
    std::string part;
    std::vector<std::string> of;
  };
  using Value = std::variant<std::int64_t, double, std::string, Share>;
  static double share(std::int64_t part, std::int64_t of) {
    return of > 0 ? static_cast<double>(part) / static_cast<double>(of) : std::nan("");
  }
  enum class Over { same, summed };  // a value the same on every rank, or a count each holds part of
  struct Attribute {
    std::string group, name;
    Value value;
    Over over = Over::same;
    std::int64_t* kept = nullptr;  // a summed count of the run's state: restored and added
    const Histogram* of = nullptr;  // a kept count of some of this histogram's samples: at most all
  };
  // A histogram's counts (named `counts`), edges and attributes at `group`, added over ranks.
  struct HistogramAt {
    std::string group, counts;
    Histogram* histogram;
    bool kept;  // the run's state (restored and added), or computed for the file
  };
  // The histogram of `values` over every rank's range, in `bins` bins, with its quartiles q1,
  // median and q3: the group's name is the histogram's.
  struct Distribution {
    std::string group;
    std::vector<double> values;
    std::int64_t bins;
  };
  // A per-orbit dataset (written where the run keeps per-orbit data).
  struct Column {
    std::string path;
    std::variant<std::vector<double>, std::vector<std::uint8_t>> values;
  };
  // Points of orbits in (orbit, step) order: the datasets orbit, step, x, y at `group`; kept
  // with each orbit's count (`kept`).
  struct Events {
    std::string group;
    SectionPoints* points;
  };

  // The rows of chosen orbits (a trajectory's): orbit, step and the named columns at `group`, as
  // rank 0 has them, orbit by orbit in the orbits' configured order; at most the rows they can
  // give over `steps` steps.
  struct Series {
    std::string group;
    Trajectory* rows;
    long long steps;
  };

  std::vector<Attribute> attributes;
  std::vector<HistogramAt> histograms;
  std::vector<Distribution> distributions;
  std::vector<Column> columns;
  std::vector<Events> events;
  std::vector<Series> series;

  // A histogram computed for the file, held here.
  Histogram& hold(Histogram h) { return held_.emplace_back(std::move(h)); }
  void attribute(std::string group, std::string name, Value value, Over over = Over::same) {
    attributes.push_back({std::move(group), std::move(name), std::move(value), over});
  }

 private:
  std::deque<Histogram> held_;  // stable addresses
};

// Writes the output; collective over ranks (every rank with the same description, its own
// rows and values). per_orbit: the columns are written.
void write_output(const h5::Group& root, const MeasuredOutput& out, Rows rows, bool per_orbit);
void write_kept(const h5::Group& root, const MeasuredOutput& out, Rows rows = {});
// The kept items' state from the file's rows: the histograms' counts, the summed counts and the
// series go to rank 0 alone, so that the ranks' add up to the file's.
void restore_kept(const h5::Group& root, MeasuredOutput& out, Rows rows = {});
// Adds the kept items of `part`, which observed orbits numbered from 0 (a shard's), to those of
// `whole`, its events and series as orbits first_orbit + i: parts added in orbit order equal one
// run's.
void add_part(MeasuredOutput& whole, const MeasuredOutput& part, std::size_t first_orbit);

}  // namespace qmaps
