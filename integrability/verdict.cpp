#include "integrability/verdict.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <ostream>
#include <sstream>

#include <flint/ulong_extras.h>

#include "core/error.hpp"
#include "core/memory_limit.hpp"

namespace qmaps::exact {
namespace {

// F_p(t)'s values held at once in a step, and each one's two polynomials of 8-byte coefficients
// at the cap, with their products (twice the cap) while they are formed.
constexpr double values_per_step = 64, bytes_per_degree = 2 * 8 * 2;

void check_prime(std::uint64_t p, std::uint64_t largest, const std::string& option,
                 const std::string& arithmetic) {
  if (!is_prime(p))
    throw usage_error(option + ": " + std::to_string(p) + " is not prime");
  if (p < 5 || p > largest)
    throw usage_error(option + ": " + std::to_string(p) + " is outside 5 … " +
                      std::to_string(largest) + " (" + arithmetic + ")");
}

Says says(Growth::Kind k) {
  return k == Growth::Kind::polynomial    ? Says::integrable
         : k == Growth::Kind::exponential ? Says::not_integrable
                                          : Says::undecided;
}

std::string sequence(const std::vector<double>& v, int digits = 0) {
  std::ostringstream out;
  out << std::fixed << std::setprecision(digits);
  for (std::size_t i = 0; i < v.size(); ++i) out << (i ? " " : "") << v[i];
  return out.str();
}

std::string growth_text(const Growth& g) {
  std::ostringstream out;
  out << to_string(g.kind);
  if (g.kind == Growth::Kind::polynomial) out << ", degree " << std::setprecision(3) << g.degree;
  if (g.kind == Growth::Kind::exponential)
    out << ", lambda " << std::setprecision(10) << g.lambda << ", entropy log(lambda) = "
        << g.entropy << " +- " << std::setprecision(2) << g.entropy_error;
  return out.str();
}

}  // namespace

std::string to_string(Says s) {
  return s == Says::integrable ? "integrable" : s == Says::not_integrable ? "not integrable" : "undecided";
}

IntegrabilityOptions resolved(const IntegrabilityOptions& given, const ExactMap& map) {
  IntegrabilityOptions o = given;
  if (o.degree_primes.empty()) o.degree_primes = {n_nextprime(1ULL << 61, 1), n_nextprime(3ULL << 59, 1)};
  for (const auto p : o.degree_primes)
    check_prime(p, 1ULL << 62, "--degree-primes", "F_p(t) in FLINT's word-size arithmetic");
  if (o.field_primes.empty())
    o.field_primes = map.varying.size() <= 2 ? std::vector<std::uint64_t>{1009, 4001, 10007}
                                             : std::vector<std::uint64_t>{31, 61, 101};
  for (const auto p : o.field_primes)
    check_prime(p, max_lane_prime, "--field-primes",
                "residues held exactly in doubles, products below 2^52");
  if (o.lines < 1 || o.lines > 16) throw usage_error("--lines: 1 to 16 lines");
  if (o.steps < 1 || o.steps > 10000) throw usage_error("--steps: 1 to 10000 steps");
  if (o.degree_cap < 16) throw usage_error("--degree-cap: at least 16");
  check_fits(values_per_step * bytes_per_degree * static_cast<double>(o.degree_cap) *
                 static_cast<double>(std::min<std::size_t>(2, o.degree_primes.size() * o.lines)),
             "--degree-cap " + std::to_string(o.degree_cap), "rational functions of that degree",
             "; take a smaller --degree-cap");
  if (o.orbits < 2 || o.orbits > 100000000) throw usage_error("--orbits: 2 to 10^8 orbits");
  if (o.height_steps < 1 || o.height_steps > 10000) throw usage_error("--height-steps: 1 to 10000");
  if (!(o.height_bits >= 64 && o.height_bits <= 1e9))
    throw usage_error("--height-bits: 64 to 10^9 bits");
  check_fits(o.height_bits / 8 * 64, "--height-bits", "rationals of that height",
             "; take fewer --height-bits");
  return o;
}

Report integrability_report(const ExactMap& map, const IntegrabilityOptions& o) {
  Report r;
  r.map = map.name;
  r.evaluated_by = map.evaluated_by;
  for (const std::size_t k : map.varying) r.varying.push_back(map.state_names[k]);
  r.invariant_names = map.invariant_names;
  r.invariants_exact = map.invariants_exact;
  try {
    r.degrees = degree_test(map, o.degree_primes, o.lines, o.steps, o.degree_cap, o.seed);
  } catch (const DivisionByZero&) {
    throw usage_error("a degree prime divides the denominator of one of the map's coefficients; "
                      "choose other --degree-primes");
  }
  const double d = static_cast<double>(map.varying.size());
  for (const auto p : o.field_primes) {
    const std::uint64_t max_period =
        o.max_period ? o.max_period
                     : static_cast<std::uint64_t>(64 * std::pow(static_cast<double>(p), d / 2));
    try {
      FieldOrbits f = finite_field_orbits(map, p, o.orbits, max_period, o.seed);
      if (f.periods.size() < o.orbits / 2) {  // most orbits singular: draw more, up to 20 times
        const std::size_t more = f.periods.empty() ? 20 : std::min<std::size_t>(20, (o.orbits + f.periods.size() - 1) / f.periods.size());
        if (more > 1) f = finite_field_orbits(map, p, o.orbits * more, max_period, o.seed);
      }
      r.fields.push_back(std::move(f));
    } catch (const DivisionByZero&) {
      throw usage_error("--field-primes: " + std::to_string(p) +
                        " divides the denominator of one of the map's coefficients; choose another prime");
    }
  }
  r.heights = height_test(map, o.height_steps, o.height_bits, o.seed);

  r.degree_says = says(r.degrees.growth.kind);
  if (!r.degrees.agree) r.degree_says = Says::undecided;
  r.height_says = says(r.heights.growth.kind);
  const FieldOrbits& last = r.fields.back();
  const bool levels_broken = last.level_checked && last.level_kept < last.level_checked;
  if (last.periods.size() >= min_periods && !levels_broken) {
    if (last.p_value >= significance || last.ks_distance <= near_R)
      r.field_says = Says::not_integrable;
    else if (last.ks_distance >= far_from_R)
      r.field_says = Says::integrable;
  }

  std::vector<std::pair<std::string, Says>> decided;
  for (const auto& [name, s] : {std::pair{"degree growth", r.degree_says},
                                std::pair{"finite fields", r.field_says},
                                std::pair{"height growth", r.height_says}})
    if (s != Says::undecided) decided.emplace_back(name, s);
  const bool conflict = std::any_of(decided.begin(), decided.end(),
                                    [&](const auto& x) { return x.second != decided.front().second; });
  r.tests_agree = decided.size() == 3 && !conflict;
  if (decided.empty()) {
    r.reason = "no test decided";
  } else if (conflict) {
    r.reason = "the tests disagree:";
    for (const auto& [name, s] : decided) r.reason += " " + name + " says " + to_string(s) + ";";
    r.reason.pop_back();
  } else {
    r.verdict = decided.front().second;
    r.reason = decided.size() == 3 ? "all three tests agree"
                                   : std::to_string(decided.size()) + " of the three tests decided, and agree";
  }
  if (!r.degrees.agree) r.reason += "; the degree sequences of the primes and lines differ";
  if (levels_broken) r.reason += "; orbits mod p left the level sets of the invariants";
  return r;
}

void write_text(std::ostream& out, const Report& r) {
  out << "map " << r.map << ", evaluated exactly by " << r.evaluated_by << "\n";
  out << "coordinates that change: ";
  for (std::size_t i = 0; i < r.varying.size(); ++i) out << (i ? ", " : "") << r.varying[i];
  out << "\n\nverdict: " << to_string(r.verdict) << " (" << r.reason << ")\n";

  const DegreeTest& d = r.degrees;
  out << "\ndegree growth: " << to_string(r.degree_says) << "\n";
  out << "  d_n, n = 0 … " << d.runs.front().degrees.size() - 1 << ": " << sequence(d.runs.front().degrees) << "\n";
  for (const auto& run : d.runs)
    out << "  p = " << run.prime << ", line " << run.line << ": " << run.degrees.size() - 1 << " steps"
        << (run.stopped.empty() ? "" : ", stopped by " + run.stopped) << "\n";
  out << "  the " << d.runs.size() << " sequences " << (d.agree ? "agree" : "DIFFER") << "\n";
  out << "  growth: " << growth_text(d.growth) << "\n";
  if (d.growth.recurrence) {
    out << "  generating function: " << d.growth.generating_function << "\n";
    out << "  characteristic polynomial: " << d.growth.characteristic << "\n";
  }
  out << "  " << d.growth.reason << "\n";

  out << "\norbits over finite fields: " << to_string(r.field_says) << "\n";
  out << "  p        orbits  returned  singular  past max  lambda        D(R)    p-value  levels kept\n";
  for (const auto& f : r.fields) {
    out << "  " << std::left << std::setw(8) << f.prime << " " << std::right << std::setw(6)
        << f.orbits << "  " << std::setw(8) << f.periods.size() << "  " << std::setw(8) << f.singular
        << "  " << std::setw(8) << f.unfinished << "  " << std::setw(12) << std::setprecision(6)
        << f.lambda << "  " << std::setw(6) << std::setprecision(3) << f.ks_distance << "  "
        << std::setw(7) << std::setprecision(3) << f.p_value << "  ";
    if (f.level_checked) out << f.level_kept << "/" << f.level_checked;
    else out << "-";
    out << "\n";
  }
  out << "  D(R): the Kolmogorov-Smirnov distance of the periods over lambda = mean/2 from "
         "R(x) = 1 - e^-x (1 + x); a p-value of at least "
      << significance << " or D at most " << near_R
      << ": the law of a reversible map that is not integrable; D at least " << far_from_R
      << " with a p-value below " << significance << ": far from it\n";
  if (r.invariant_names.empty()) out << "  levels: the map names no invariants\n";
  else if (!r.invariants_exact)
    out << "  levels: not checked: the invariants are not exactly invariant at these parameters "
           "(a built-in kernel's coefficients rounded to doubles)\n";

  const HeightTest& h = r.heights;
  out << "\nheight growth: " << to_string(r.height_says) << "\n";
  out << "  from (";
  for (std::size_t i = 0; i < h.start.size(); ++i) out << (i ? ", " : "") << h.start[i];
  out << "), log heights: " << sequence(h.log_heights, 1) << "\n";
  if (!h.stopped.empty()) out << "  stopped by " << h.stopped << "\n";
  out << "  growth: " << growth_text(h.growth) << "\n  " << h.growth.reason << "\n";
}

}  // namespace qmaps::exact
