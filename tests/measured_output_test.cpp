// The run observers' one writer, checkpoint reader and merge (ensembles/io/measured_output.hpp),
// on a description of every kind of item, and the statistics they report.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <random>
#include <unistd.h>

#include "core/error.hpp"
#include "ensembles/io/measured_output.hpp"
#include "ensembles/io/statistics.hpp"

namespace qmaps {
namespace {

// A kept histogram, a kept count, events of `orbits` orbits: blank, or what a run observed of
// the ensemble's orbits first, first + 1, … (orbit g crosses g % 5 times, more than the cap of
// 3 for some, at points drawn from g alone).
struct Observed {
  Histogram density{"density", {Axis{"q1", -1, 1, 8}, Axis{"p1", -1, 1, 4}}};
  std::int64_t interpolated = 0;
  SectionPoints points;

  explicit Observed(std::size_t orbits) : points(orbits, 3) {}
  Observed(std::size_t orbits, std::size_t first) : points(orbits, 3) {
    for (std::size_t o = 0; o < orbits; ++o) {
      const std::size_t g = first + o;
      std::mt19937 random(static_cast<std::uint32_t>(g));
      std::uniform_real_distribution<double> u(-1.2, 1.2);
      for (std::int64_t step = 1; step <= static_cast<std::int64_t>(g % 5); ++step) {
        const double xy[2] = {u(random), u(random)};
        density.add(xy);
        points.keep(o, step, xy[0], xy[1]);
      }
      interpolated += static_cast<std::int64_t>(g % 2);
    }
    density.flush();
  }

  MeasuredOutput described() {
    MeasuredOutput out;
    out.histograms.push_back({"sections/s", "density", &density, true});
    out.events.push_back({"sections/s", &points});
    out.attributes.push_back({"sections/s", "interpolated", std::int64_t{0},
                              MeasuredOutput::Over::summed, &interpolated, &density});
    out.attribute("sections/s", "crossings", density.samples(), MeasuredOutput::Over::summed);
    out.attribute("sections/s", "plane", std::string("q2"));
    return out;
  }
};

std::string temporary(const char* name) {
  return (std::filesystem::temp_directory_path() /
          (std::string(name) + "-" + std::to_string(getpid()) + ".h5"))
      .string();
}

bool same_points(const SectionPoints& a, const SectionPoints& b) {
  const auto x = a.all(), y = b.all();
  return x.size() == y.size() &&
         std::memcmp(x.data(), y.data(), x.size() * sizeof(SectionPoint)) == 0 &&
         std::ranges::equal(a.kept(), b.kept());
}

TEST(MeasuredOutput, KeptItemsReadBackFromTheCheckpointByteForByte) {
  const std::string path = temporary("measured-kept");
  Observed run(40, 0);
  {
    auto file = h5::File::create(path);
    MeasuredOutput out = run.described();
    write_output(file.root(), out, {}, true);
    write_kept(file.root(), out);
    file.close();
  }
  Observed resumed(40);
  const auto file = h5::File::open_read(path);
  MeasuredOutput into = resumed.described();
  restore_kept(file.root(), into);
  EXPECT_TRUE(std::ranges::equal(resumed.density.counts(), run.density.counts()));
  EXPECT_EQ(resumed.density.underflow(), run.density.underflow());
  EXPECT_EQ(resumed.density.overflow(), run.density.overflow());
  EXPECT_EQ(resumed.interpolated, run.interpolated);
  EXPECT_TRUE(same_points(resumed.points, run.points));
  const auto g = file.root().open_group("sections").open_group("s");
  EXPECT_EQ(g.attr_int64("crossings"), run.density.samples());
  EXPECT_EQ(g.attr_string("plane"), "q2");
  std::filesystem::remove(path);
}

// A count of some of a histogram's samples (a section's interpolated crossings) above all of
// them is no run's: the checkpoint is refused, naming it.
TEST(MeasuredOutput, AKeptCountAboveItsHistogramsSamplesIsRefused) {
  const std::string path = temporary("measured-too-many");
  Observed run(40, 0);
  run.interpolated = run.density.samples() + 1;
  {
    auto file = h5::File::create(path);
    MeasuredOutput out = run.described();
    write_output(file.root(), out, {}, true);
    write_kept(file.root(), out);
    file.close();
  }
  Observed resumed(40);
  MeasuredOutput into = resumed.described();
  try {
    restore_kept(h5::File::open_read(path).root(), into);
    ADD_FAILURE() << "restored";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ExitCode::io);
    EXPECT_NE(std::string(e.what()).find("interpolated is " + std::to_string(run.interpolated) +
                                         ", not 0 to " + std::to_string(run.density.samples())),
              std::string::npos)
        << e.what();
  }
  std::filesystem::remove(path);
}

TEST(MeasuredOutput, PartsAddedInOrbitOrderEqualTheWhole) {
  // The ensemble's orbits 0..39 observed by one run, and by shards of 15 and 25 orbits.
  Observed whole(40, 0), first(15, 0), second(25, 15);
  Observed merged(40);
  MeasuredOutput into = merged.described();
  add_part(into, first.described(), 0);
  add_part(into, second.described(), 15);
  merged.density.flush();
  EXPECT_TRUE(std::ranges::equal(merged.density.counts(), whole.density.counts()));
  EXPECT_EQ(merged.density.samples(), whole.density.samples());
  EXPECT_EQ(merged.interpolated, whole.interpolated);
  EXPECT_TRUE(same_points(merged.points, whole.points));
}

TEST(MeasuredOutput, DistributionSpansItsValuesWithTheirQuartiles) {
  const std::string path = temporary("measured-distribution");
  MeasuredOutput out;
  out.distributions.push_back({"chaos/histograms/megno", {2.0, 2.5, 3.0, 8.0, 2.0}, 4});
  out.attribute("chaos", "regular", std::int64_t{0}, MeasuredOutput::Over::summed);
  out.attribute("chaos", "chaotic", std::int64_t{0}, MeasuredOutput::Over::summed);
  out.attribute("chaos", "chaotic_fraction", MeasuredOutput::Share{"chaotic", {"regular", "chaotic"}});
  {
    auto file = h5::File::create(path);
    write_output(file.root(), out, {}, true);
    file.close();
  }
  const auto file = h5::File::open_read(path);
  const auto g = file.root().open_group("chaos").open_group("histograms").open_group("megno");
  EXPECT_EQ(g.read_int64("counts", 4), (std::vector<std::int64_t>{4, 0, 0, 1}));
  EXPECT_EQ(g.attr_double("q1"), 2.0);
  EXPECT_EQ(g.attr_double("median"), 2.5);
  EXPECT_EQ(g.attr_double("q3"), 3.0);
  EXPECT_EQ(g.attr_int64("samples"), 5);
  // No orbit bounded: the share of none is not a number.
  EXPECT_TRUE(std::isnan(file.root().open_group("chaos").attr_double("chaotic_fraction")));
  std::filesystem::remove(path);
}

TEST(Statistics, QuantilesFromOneCopyAreEachQuantile) {
  std::mt19937 random(11);
  for (const std::size_t n : {1u, 2u, 3u, 10u, 1001u}) {
    std::vector<double> values(n);
    for (double& v : values) v = static_cast<double>(random() % 50) / 7;  // with repeats
    const auto q = quantiles(values, {0, 0.25, 0.5, 0.5, 0.75, 1});
    const double fs[] = {0, 0.25, 0.5, 0.5, 0.75, 1};
    for (std::size_t k = 0; k < 6; ++k) EXPECT_EQ(q[k], quantile(values, fs[k])) << n << " " << fs[k];
    std::ranges::sort(values);
    EXPECT_EQ(q[0], values.front());
    EXPECT_EQ(q[5], values.back());
  }
  EXPECT_TRUE(std::isnan(quantiles({}, {0.5})[0]));
}

}  // namespace
}  // namespace qmaps
