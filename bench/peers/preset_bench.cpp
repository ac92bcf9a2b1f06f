// Peer: the default preset's work (ensembles/presets/suris.toml's measurements on the Suris map,
// preset_isa.cpp) hand-written for AVX-512 and for AVX2, each run where the CPU has it (checked
// at run time; this file is compiled without ISA flags), with 4 and 8 chains, on 1 and 2 threads:
// bench/report sets its fastest chains against observers_bench's observe/preset. As there, each
// iteration observes afresh (the counts and the kept points from 0) and the orbits run on.
// Before it is timed, each is checked against qmaps' run of the same observers.
// items_per_second = particle-steps/s.
//   build/bench/peers/preset_bench
#include <cstring>
#include <memory>
#include <string>

#include "core/observers/invariants/invariant_columns.hpp"
#include "core/observers/observers.hpp"
#include "preset.hpp"
#include "suris_peer.hpp"

namespace qmaps::peers {
namespace {

using Loop = void (*)(const PresetCoeffs&, const PresetRun&, int, int);

struct PresetIsa {
  const char* name;
  Loop loop;
};

std::vector<PresetIsa> preset_isas() {
  __builtin_cpu_init();
  std::vector<PresetIsa> isas;
  if (__builtin_cpu_supports("avx512f")) isas.push_back({"avx512", preset_avx512});
  if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma"))
    isas.push_back({"avx2", preset_avx2});
  return isas;
}

// kernels/suris.hpp's coefficients, the same roundings.
PresetCoeffs preset_coeffs() {
  const double A = suris_params.at("A"), B = suris_params.at("B");
  const double alpha = suris_params.at("alpha"), h = suris_params.at("h");
  const double h2 = h * h, a = 1 - A * h2, b = 1 - B * h2, g = 2 * alpha * h2;
  return {2 * a,           2 * b,           g,
          2 * h,           0.5 / h2,        (1 - a) / h2,
          (1 - b) / h2,    g / (2 * h2),    2 - 2 * a,
          2 - 2 * b,       g * a * a / ((a - b) * (a + b)),
          g * b * b / ((b - a) * (a + b)), 2 * g * a / (a + b),
          2 * g * b / (a + b)};
}

// The benchmarks' orbits (bench_ensemble) and everything the peer's runs write.
struct PresetState {
  std::size_t n;
  Columns x;
  std::array<std::vector<double>, 3> initial, drift, last;  // H, I1, I2
  std::vector<std::int64_t> kept;
  std::vector<PresetPoint> points;
  std::array<std::vector<std::uint64_t>, 3> counts;  // the density, the section's, the image
  long long step = 0;

  explicit PresetState(std::size_t orbits) : n(orbits) {
    const auto model = make_model("suris", suris_params);
    const Ensemble e = bench_ensemble(*model, orbits);
    for (std::size_t k = 0; k < 4; ++k) x[k].assign(e.state[k].data(), e.state[k].data() + n);
    for (std::size_t i = 0; i < 3; ++i) {
      initial[i].assign(invariant_initial(e, i).data(), invariant_initial(e, i).data() + n);
      drift[i].assign(n, 0.0);
      last[i].assign(n, 0.0);
    }
    kept.assign(n, 0);
    points.resize(n * preset_cap);
    for (auto& c : counts) c.assign(preset_counts, 0);
  }
  // `steps` steps on, observed afresh.
  void run(Loop loop, long long steps, int threads, int chains) {
    std::fill(kept.begin(), kept.end(), 0);
    for (auto& c : counts) std::fill(c.begin(), c.end(), 0);
    const PresetRun r{{x[0].data(), x[1].data(), x[2].data(), x[3].data()}, n,
                      {initial[0].data(), initial[1].data(), initial[2].data()},
                      {drift[0].data(), drift[1].data(), drift[2].data()},
                      {last[0].data(), last[1].data(), last[2].data()},
                      kept.data(), points.data(),
                      counts[0].data(), counts[1].data(), counts[2].data(), step, steps};
    loop(preset_coeffs(), r, threads, chains);
    step += steps;
  }
};

Histogram preset_histogram(const char* name, const char* x, const char* y, PresetRange r) {
  return Histogram(name, {{x, r.lo[0], r.hi[0], preset_bins}, {y, r.lo[1], r.hi[1], preset_bins}});
}

// What qmaps writes for the preset over `orbits` orbits and `steps` steps from step 0 on its
// scalar reference path: the observers as observers_bench's preset case makes them, the image
// as the output writes it (ensembles/io/output.cpp: the initial (H, I1) of every orbit).
struct Reference {
  std::unique_ptr<Model> model = make_model("suris", suris_params);
  Ensemble e;
  Observers o;
  Histogram image = preset_histogram("image", "H", "I1", preset_image);
  std::array<std::vector<double>, 3> last;

  Reference(std::size_t orbits, long long steps) : e(bench_ensemble(*model, orbits)) {
    Section s;
    s.name = "q1up";
    s.plane = Coordinate::q1;
    s.direction = 1;
    s.x = Coordinate::q2;
    s.y = Coordinate::p2;
    s.cap = preset_cap;
    s.density = preset_histogram("q1up", "q2", "p2", preset_section);
    s.points = std::make_shared<SectionPoints>(orbits,
                                               Section::slots_per_orbit(preset_cap, 1, steps));
    o.sections.push_back(s);
    o.densities.push_back({preset_histogram("q1q2", "q1", "q2", preset_density),
                           {Coordinate::q1, Coordinate::q2}});
    model->advance(e, next_steps(e, steps, true, preset_stride), Execution{}, &o);
    for (std::size_t i = 0; i < orbits; ++i) {
      const double v[2] = {invariant_initial(e, 0)[i], invariant_initial(e, 1)[i]};
      image.add(v);
    }
    std::vector<double*> out;
    for (auto& l : last) {
      l.assign(orbits, 0.0);
      out.push_back(l.data());
    }
    model->invariants_of_orbits(e, 0, orbits, Isa::scalar, out);
  }
};

bool same_bytes(const double* a, const double* b, std::size_t n) {
  return std::memcmp(a, b, n * sizeof(double)) == 0;
}
bool same_counts(const std::vector<std::uint64_t>& mine, const Histogram& h) {
  const auto cells = h.counts();
  return std::equal(cells.begin(), cells.end(), mine.begin()) &&
         mine[cells.size()] == static_cast<std::uint64_t>(h.underflow()) &&
         mine[cells.size() + 1] == static_cast<std::uint64_t>(h.overflow());
}

// The peer's run against qmaps' (the same orbits and steps from step 0, one thread): the parts
// whose bytes differ, or "" where none does.
std::string preset_difference(const Reference& q, Loop loop, int chains, long long steps) {
  PresetState mine(q.e.orbits);
  mine.run(loop, steps, 1, chains);
  const std::size_t n = mine.n;
  std::string differ;
  const auto check = [&](bool same, const char* what) {
    if (!same) differ += std::string(differ.empty() ? "" : ", ") + what;
  };
  bool states = true, drifts = true, lasts = true;
  for (std::size_t k = 0; k < 4; ++k)
    states &= same_bytes(mine.x[k].data(), q.e.state[k].data(), n);
  for (std::size_t i = 0; i < 3; ++i) {
    drifts &= same_bytes(mine.drift[i].data(), invariant_drift(q.e, i).data(), n);
    lasts &= same_bytes(mine.last[i].data(), q.last[i].data(), n);
  }
  check(states, "states");
  check(drifts, "drifts");
  check(lasts, "last invariants");
  check(same_counts(mine.counts[0], q.o.densities[0].histogram), "density");
  const Section& section = q.o.sections[0];
  check(same_counts(mine.counts[1], section.density), "section's density");
  const auto kept = section.points->kept();
  check(std::equal(kept.begin(), kept.end(), mine.kept.begin()), "points kept per orbit");
  bool points = true;  // each orbit's, in step order
  std::vector<std::size_t> seen(n, 0);
  for (const SectionPoint& p : section.points->all()) {
    const auto o = static_cast<std::size_t>(p.orbit);
    if (seen[o] == static_cast<std::size_t>(preset_cap)) {
      points = false;
      break;
    }
    const PresetPoint& m = mine.points[o * preset_cap + seen[o]++];
    points &= m.step == p.step && same_bytes(&m.x, &p.x, 1) && same_bytes(&m.y, &p.y, 1);
  }
  check(points, "points");
  check(same_counts(mine.counts[2], q.image), "image");
  return differ;
}

void preset(benchmark::State& state, PresetIsa isa) {
  PresetState p(static_cast<std::size_t>(state.range(0)));
  const int threads = static_cast<int>(state.range(1));
  const int chains = static_cast<int>(state.range(2));
  time_peer(state, "peer-preset", isa.name, threads, [&](long long steps) {
    p.run(isa.loop, steps, threads, chains);
    benchmark::DoNotOptimize(p.counts[0].data());
  });
  state.counters["chains"] = chains;
  state.counters["stride"] = static_cast<double>(preset_stride);
}

}  // namespace
}  // namespace qmaps::peers

int main(int argc, char** argv) {
  using namespace qmaps;
  const auto isas = peers::preset_isas();
  if (isas.empty()) {
    std::fprintf(stderr, "preset_bench: this CPU has neither AVX-512 nor AVX2 with FMA\n");
    return 1;
  }
  constexpr std::size_t orbits = 1024;
  constexpr long long steps = 1000;
  const peers::Reference q(orbits, steps);
  const Section& section = q.o.sections[0];
  char text[300];
  std::snprintf(text, sizeof text,
                "the same bytes as qmaps (scalar) after %lld steps of %zu orbits: states, drifts, "
                "last invariants, the density (%lld samples), the section (%lld crossings, %zu "
                "points kept), the image", steps, orbits,
                static_cast<long long>(q.o.densities[0].histogram.samples()),
                static_cast<long long>(section.density.samples()), section.points->size());
  for (const auto& isa : isas) {
    auto* b = benchmark::RegisterBenchmark(("peer/preset/" + std::string(isa.name)).c_str(),
                                           peers::preset, isa)
                  ->ArgNames({"orbits", "threads", "chains"})
                  ->Unit(benchmark::kMillisecond)
                  ->UseRealTime();
    for (int chains : {4, 8}) {
      for (long threads : {1, 2}) b->Args({bench_size().simd_orbits, threads, chains});
      const std::string name = "preset " + std::string(isa.name) + ", " +
                               std::to_string(chains) + " chains";
      const std::string differ = peers::preset_difference(q, isa.loop, chains, steps);
      if (!differ.empty()) {
        std::fprintf(stderr, "%s: differs from qmaps (scalar) after %lld steps of %zu orbits: "
                     "%s\n", name.c_str(), steps, orbits, differ.c_str());
        return 1;
      }
      std::fprintf(stderr, "%s: %s\n", name.c_str(), text);
      benchmark::AddCustomContext("agreement " + name, text);
    }
  }
  return peers::peer_main(argc, argv, {});
}
