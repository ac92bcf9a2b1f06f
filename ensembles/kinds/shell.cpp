#include "ensembles/kinds/shell.hpp"

#include <cmath>
#include <limits>
#include <utility>

#include "core/error.hpp"
#include "core/memory_limit.hpp"
#include "core/rng.hpp"

namespace qmaps {
namespace {

constexpr std::uint64_t shell_stream = 0x7368656c6c;  // "shell"
// What a grid point that becomes an orbit holds at least: its index, its state.
constexpr double bytes_per_candidate = 8 + 4 * 8;

// The smallest x ≥ 0 with a x² + b x + c = 0, if any.
std::optional<double> smallest_nonnegative_root(double a, double b, double c) {
  double r1, r2;
  if (a == 0) {
    if (b == 0) return std::nullopt;
    r1 = r2 = -c / b;
  } else {
    const double disc = b * b - 4 * a * c;
    if (!(disc >= 0)) return std::nullopt;
    // The stable pair: t = −(b + sign(b)√disc)/2, roots t/a and c/t.
    const double t = -0.5 * (b + std::copysign(std::sqrt(disc), b));
    r1 = t / a;
    r2 = t == 0 ? r1 : c / t;
  }
  if (r1 > r2) std::swap(r1, r2);
  if (r1 >= 0) return r1;
  if (r2 >= 0) return r2;
  return std::nullopt;
}

}  // namespace

Shell::Shell(const Config& config, const Potential& potential, StopCheck stop)
    : potential_(potential), stop_(std::move(stop)) {
  energy_ = config.number("ensemble", "energy");
  energy_where_ = config.where("ensemble", "energy");
  solve_ = phase_index(config, "solve", config.string_or("ensemble", "solve", "p2"));
  const std::string sign = config.string_or("ensemble", "sign", "+");
  if (sign != "+" && sign != "-")
    throw usage_error(config.where("ensemble", "sign") + " must be \"+\" or \"-\"");
  sign_ = sign == "+" ? 1.0 : -1.0;
  const std::string sampling = config.string_or("ensemble", "sampling", "random");
  if (sampling != "random" && sampling != "grid")
    throw usage_error(config.where("ensemble", "sampling") + " must be \"random\" or \"grid\"");
  random_ = sampling == "random";
  std::vector<int> axes;
  for (int k = 0; k < 4; ++k)
    if (k != solve_) {
      axes.push_back(k);
      ranges_[static_cast<std::size_t>(k)] =
          range_of(config, phase_names[static_cast<std::size_t>(k)]);
    }
  if (config.has("ensemble", phase_names[static_cast<std::size_t>(solve_)]))
    throw usage_error(config.where("ensemble", phase_names[static_cast<std::size_t>(solve_)]) +
                      ": this coordinate is solved from H = E (solve = \"" +
                      std::string(phase_names[static_cast<std::size_t>(solve_)]) +
                      "\"); give no range for it");
  if (random_) {
    orbits_ = orbits_of(config);
    seed_ = seed_of(config);
    const long long cap = config.integer_or("ensemble", "max_draws", 1000);
    if (cap <= 0) throw usage_error(config.where("ensemble", "max_draws") + " must be > 0");
    max_draws_ = static_cast<std::uint64_t>(cap);
    draw(0);  // fails now, before anything is written, when no draw reaches the surface
    return;
  }
  if (config.has("ensemble", "orbits"))
    throw usage_error(config.where("ensemble", "orbits") +
                      ": a shell grid has one orbit per accepted point; set points instead");
  lattice_ = Lattice::from_config(config, axes);
  const std::size_t n = lattice_->size();
  // Every point may lie on the surface and become an orbit (its index kept, then its state):
  // the grid must fit in memory before it is enumerated.
  const MemoryLimit have = memory_limit();
  if (static_cast<double>(n) * bytes_per_candidate > have.bytes)
    throw usage_error(config.where("ensemble", "points") + ": " + std::to_string(n) +
                      " grid points, each of which may become an orbit, need more than " +
                      number_text(static_cast<double>(n) * bytes_per_candidate / (1 << 30)) +
                      " GiB; " + have.what + " is " + number_text(have.bytes / (1 << 30)) + " GiB");
  for (std::size_t j = 0; j < n; ++j) {
    if (j % 4096 == 0) check_stop(stop_, "enumerating the shell's grid");
    std::array<double, 4> x{};
    lattice_->place(j, x);
    if (solve(x)) accepted_.push_back(j);
  }
  rejected_up_front_ = n - accepted_.size();
  orbits_ = accepted_.size();
  if (orbits_ == 0)
    throw usage_error(energy_where_ + ": no point of the grid lies on H = " + number_text(energy_) +
                      " (is E below the potential over the ranges?)");
}

std::optional<Phase> Shell::solve(std::array<double, 4> x) const {
  const auto s = static_cast<std::size_t>(solve_);
  if (s >= 2) {  // a momentum
    x[s] = 0;
    const double rest = potential_.energy(as_phase(x));
    const double p2 = 2 * (energy_ - rest);
    if (!(p2 >= 0 && p2 <= std::numeric_limits<double>::max())) return std::nullopt;
    x[s] = sign_ * std::sqrt(p2);
    return as_phase(x);
  }
  // A position q_k, k = s: V = α_k q_k⁴ + (A_k + δ q_o²) q_k² + (rest without q_k).
  const double qo = x[1 - s], xo = qo * qo;
  const double ak = s == 0 ? potential_.alpha : potential_.beta;
  const double Ak = s == 0 ? potential_.A : potential_.B;
  x[s] = 0;
  const double rest = potential_.energy(as_phase(x));  // everything without q_k
  const auto root = smallest_nonnegative_root(ak, Ak + potential_.delta * xo, rest - energy_);
  if (!root || !(*root <= std::numeric_limits<double>::max())) return std::nullopt;
  x[s] = sign_ * std::sqrt(*root);
  return as_phase(x);
}

Drawn Shell::draw(std::size_t orbit) const {
  if (!random_) {
    std::array<double, 4> x{};
    lattice_->place(static_cast<std::size_t>(accepted_[orbit]), x);
    return {*solve(x)};
  }
  const OrbitRandom random(seed_, shell_stream);
  for (std::uint64_t k = 0; k < max_draws_; ++k) {
    if (k % 4096 == 4095) check_stop(stop_, "drawing the shell's initial conditions");
    const auto u = random.uniform4(orbit, k);
    std::array<double, 4> x{};
    for (std::size_t c = 0; c < 4; ++c) {
      const auto [lo, hi] = ranges_[c];
      x[c] = lo == hi ? lo : lo + (hi - lo) * u[c];
    }
    if (const auto point = solve(x)) return {*point, k};
  }
  throw usage_error(energy_where_ + ": orbit " + std::to_string(orbit) + " found no point of H = " +
                    number_text(energy_) + " in " + std::to_string(max_draws_) +
                    " draws (max_draws): do the ranges reach the energy surface? (is E below "
                    "the potential's minimum over them?)");
}

std::string Shell::description() const {
  const auto name = std::string(phase_names[static_cast<std::size_t>(solve_)]);
  std::string text = "shell: " + std::to_string(orbits_) +
                     " orbits on H = " + number_text(energy_) +
                     " of (A, B, alpha, beta, delta) = (" + number_text(potential_.A) + ", " +
                     number_text(potential_.B) + ", " + number_text(potential_.alpha) + ", " +
                     number_text(potential_.beta) + ", " + number_text(potential_.delta) + "), " +
                     name + (sign_ > 0 ? " >= 0" : " <= 0") + " solved from H = E, ";
  if (lattice_) return text + "grid " + lattice_->text();
  for (std::size_t k = 0; k < 4; ++k)
    if (static_cast<int>(k) != solve_)
      text += std::string(phase_names[k]) + " " + range_text(ranges_[k]) + ", ";
  return text + "random, seed " + std::to_string(seed_) + ", max_draws " +
         std::to_string(max_draws_);
}

}  // namespace qmaps
