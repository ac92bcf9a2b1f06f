#include "integrability/degree_growth.hpp"

#include <algorithm>
#include <random>

namespace qmaps::exact {

DegreeSequence degree_sequence(const ExactMap& map, std::uint64_t prime, int line, int steps,
                               long cap, std::uint64_t seed) {
  PrimeField field(prime, cap);
  std::seed_seq sequence{seed, prime, static_cast<std::uint64_t>(line)};
  std::mt19937_64 random(sequence);
  const auto draw = [&] { return Residue::of(random() % prime); };
  State<FunctionOfT> s;
  for (std::size_t k = 0; k < 4; ++k) {
    const bool varies = std::find(map.varying.begin(), map.varying.end(), k) != map.varying.end();
    const Residue at0 = draw(), slope = draw();
    s[k] = varies ? FunctionOfT::line(at0, slope) : FunctionOfT(at0);
  }
  DegreeSequence out{prime, line, {1.0}, ""};
  for (int n = 1; n <= steps; ++n) {
    try {
      map.step(s);
    } catch (const DegreeCap&) {
      out.stopped = "the degree cap (" + std::to_string(cap) + ") at step " + std::to_string(n);
      break;
    } catch (const DivisionByZero&) {
      out.stopped = "a denominator vanishing on the whole line at step " + std::to_string(n);
      break;
    }
    long d = 0;
    for (const std::size_t k : map.varying) d = std::max(d, s[k].degree());
    out.degrees.push_back(static_cast<double>(d));
  }
  return out;
}

DegreeTest degree_test(const ExactMap& map, const std::vector<std::uint64_t>& primes, int lines,
                       int steps, long cap, std::uint64_t seed) {
  DegreeTest t;
  t.steps = steps;
  t.cap = cap;
  t.runs.resize(primes.size() * static_cast<std::size_t>(lines));
  const int runs = static_cast<int>(t.runs.size());
#pragma omp parallel for schedule(dynamic, 1)
  for (int r = 0; r < runs; ++r)
    t.runs[static_cast<std::size_t>(r)] =
        degree_sequence(map, primes[static_cast<std::size_t>(r / lines)], r % lines, steps, cap, seed);
  std::size_t shortest = t.runs.front().degrees.size();
  for (const auto& r : t.runs) shortest = std::min(shortest, r.degrees.size());
  for (const auto& r : t.runs)
    t.agree = t.agree && std::equal(r.degrees.begin(), r.degrees.begin() + static_cast<long>(shortest),
                                    t.runs.front().degrees.begin());
  t.growth = fit_growth(t.runs.front().degrees);
  return t;
}

}  // namespace qmaps::exact
