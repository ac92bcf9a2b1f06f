#pragma once
// A map written as formulas (docs/formulas.md): its name, its parameters with their defaults, and
// the formulas of one of two forms, checked once (Definition::parse), then lowered for a run's
// parameter values into the programs that kernels/formula_map.hpp evaluates (Definition::lower).
//
//   phase     `step` assigns new q1, q2, p1, p2 in order, each assignment seeing those before it
//             (a map that never names q2 or p2 has one degree of freedom; they keep their values).
//   two_step  the state (q_n, q_{n+1}). Either `step` assigns q1_next, q2_next from q1_prev,
//             q2_prev, q1, q2; or `equations` assigns eq1, eq2, linear in q1_next and q2_next, and
//             the map solves eq1 = eq2 = 0 (a state where they are singular is that orbit's
//             fault). `momentum` assigns p1, p2 from q1, q2, q1_next, q2_next (and q1_prev,
//             q2_prev: one step of the reversed state); default (q_next − q)/h. `start` assigns
//             q1_next, q2_next from q1, q2, p1, p2; default q + h p.
//   invariants  every name assigned, in order, except those starting with '_', over the state's
//               names (phase: q1, q2, p1, p2; two_step: q1, q2, q1_next, q2_next).
//   continuous  A, B, alpha, beta, delta of the quartic Hamiltonian the map discretizes, from the
//               parameters (what H_cont, `shell` ensembles and `orbit --energy` need).
// `parameters` assigns each parameter its default: "A = 0.7; h = 0.1". The time step is the
// parameter h where there is one, else 1.
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/params.hpp"
#include "core/potential.hpp"
#include "kernels/formula/expression.hpp"
#include "kernels/formula/program.hpp"

namespace qmaps::formula {

inline constexpr std::size_t max_invariants = 16;

enum class Form : std::uint8_t { phase, two_step };

// A map as its user writes it ([map], qmaps.Map); an empty text is a key not given.
struct MapText {
  std::string name, form, parameters, step, equations, momentum, start, invariants, continuous;
};
// The keys of MapText, in its order, and the text of key k.
inline constexpr std::array<std::string_view, 9> map_keys = {
    "name", "form", "parameters", "step", "equations", "momentum", "start", "invariants",
    "continuous"};
std::string& text_of(MapText& text, std::string_view key);
const std::string& text_of(const MapText& text, std::string_view key);

// An error in one key's formulas: the key, then the line and column within them.
class DefinitionError : public Error {
 public:
  DefinitionError(std::string key, const std::string& what)
      : Error(ExitCode::usage, key + ": " + what), key_(std::move(key)), what_(what) {}
  const std::string& key() const { return key_; }
  const std::string& reason() const { return what_; }

 private:
  std::string key_, what_;
};

// The programs of one set of parameter values. The state is (p1, p2, q1, q2) for the phase form
// (the configuration last, where the runner's escape test reads it) and (q_n, q_{n+1}) for the
// two-step form; every program that reads the state takes it in that order.
struct Lowered {
  Form form;
  Program step;        // the new state (phase), or q1_next, q2_next [, the system's determinant]
  Rotation resident;   // the step with its state kept in registers (none: the step copies it)
  bool solves = false;  // two_step by equations
  Program momentum;    // two_step: (q1, q2, q1_next, q2_next, q1_prev, q2_prev) → (p1, p2)
  bool momentum_reads_previous = false;
  Program start;       // two_step: (q1, q2, p1, p2) → (q1_next, q2_next)
  Program invariants;  // the state → the invariants
  std::optional<Potential> continuous;
  double h = 1;        // the time step
};

class Definition {
 public:
  // Parses and checks everything the values cannot change (lowering once at the defaults).
  static std::shared_ptr<const Definition> parse(const MapText& text);
  // The programs for these values (in the order of params()): a division by a parameter that is
  // 0, or a value they make not finite, is a DefinitionError.
  Lowered lower(std::span<const double> values) const;

  const MapText& text() const { return text_; }
  Form form() const { return form_; }
  std::span<const ParamSpec> params() const { return specs_; }
  const std::vector<std::string>& invariant_names() const { return invariant_names_; }
  const std::array<std::string_view, 4>& state_names() const;

  Definition(const Definition&) = delete;  // params() views its names
  Definition& operator=(const Definition&) = delete;

 private:
  Definition() = default;
  MapText text_;
  Form form_ = Form::phase;
  std::vector<std::string> param_names_;
  std::vector<ParamSpec> specs_;
  std::vector<std::string> invariant_names_;
  Formulas step_, momentum_, start_, invariants_, continuous_;
  bool solves_ = false;
};

}  // namespace qmaps::formula
