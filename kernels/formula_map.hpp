#pragma once
// A map written as formulas (kernels/formula/definition.hpp, docs/formulas.md): the one map of
// the list defined at run time. Its step runs its lowered program over V with the project's ops,
// so that the scalar path, every ISA and its tangent (V = Dual) compute the same:
//
//   phase:     (p1, p2, q1, q2) ← step(p1, p2, q1, q2)
//   two_step:  (q_n, q_{n+1}) ← (q_{n+1}, q_{n+2}),  q_{n+2} = step(q_n, q_{n+1}),
//              or the solution of A(q_n, q_{n+1}) q_{n+2} + c(q_n, q_{n+1}) = 0 by Cramer's
//              rule, with the fault `singular` where det A = 0.
//
// The escape measure is |q|² + 0·p1 + 0·p2 (the phase form's p is then tested for being finite
// too, at no change to the value).
#include <array>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "core/escape.hpp"
#include "core/map_concept.hpp"
#include "core/ops.hpp"
#include "core/params.hpp"
#include "core/phase.hpp"
#include "core/potential.hpp"
#include "kernels/formula/definition.hpp"
#include "kernels/formula/evaluate.hpp"

namespace qmaps::kernels {

struct Formula {
  using Definition = formula::Definition;
  static constexpr std::string_view name = "formula";
  static constexpr std::string_view summary = "a map written as formulas (docs/formulas.md)";
  static constexpr std::string_view equations = "its formulas";
  static constexpr std::string_view invariant_summary = "its invariants' formulas";
  static constexpr bool time_per_orbit = false;
  static constexpr bool reports_faults = true;
  static constexpr MapFacts facts = {
      .example = {}, .escaping = {}, .step = "h", .order = 0,
      .reversal_tolerance = 0, .drift_tolerance = 0, .preset = "", .slow = false,
      .volume_preserving = false, .forces_per_step = 0, .speed_budget = 0};
  static constexpr std::array<ParamSpec, 0> params = {};
  static constexpr std::array<std::string_view, 4> state_names = {"x1", "x2", "x3", "x4"};
  template <class V>
  using State = std::array<V, 4>;
  static constexpr std::size_t max_invariants = formula::max_invariants;

  struct Coeffs {
    std::shared_ptr<const Definition> definition;
    std::shared_ptr<const formula::Lowered> program;
  };

  static Coeffs coefficients(std::span<const double> values,
                             const std::shared_ptr<const Definition>& d = nullptr) {
    if (!d) throw usage_error("a formula map is made from its formulas");
    return {d, std::make_shared<const formula::Lowered>(d->lower(values))};
  }
  static MapIdentity identity(const std::shared_ptr<const Definition>& d) {
    const auto names = d->state_names();
    return {d->text().name, {d->params().begin(), d->params().end()},
            {names.begin(), names.end()}};
  }
  static std::vector<std::pair<std::string, std::string>> formulas(const Coeffs& c) {
    std::vector<std::pair<std::string, std::string>> out;
    for (const std::string_view key : formula::map_keys)
      if (key != "name")
        if (const std::string& text = formula::text_of(c.definition->text(), key); !text.empty())
          out.emplace_back(std::string(key), text);
    return out;
  }
  static std::optional<Potential> continuous(const Coeffs& c) { return c.program->continuous; }
  static std::vector<std::string> invariant_names(const Coeffs& c) {
    return c.definition->invariant_names();
  }

  template <class V>
  static V step(const Coeffs& c, State<V>& s) {
    const formula::Lowered& m = *c.program;
    const formula::Program& p = m.step;
    V* r = run(p, s);
    const std::uint16_t* out = p.outputs.data();
    if (m.form == formula::Form::phase) {
      for (std::size_t k = 0; k < 4; ++k) s[k] = r[out[k]];
      return V(0.0);
    }
    const V z1 = r[out[0]], z2 = r[out[1]];
    s = {s[2], s[3], z1, z2};
    if (!m.solves) return V(0.0);
    return ops::select(r[out[2]] == V(0.0),
                       V(static_cast<double>(EscapeReason::singular)), V(0.0));
  }

  template <class V>
  static V escape_measure(const State<V>& s) {
    return ops::fma(V(0.0), s[0], ops::fma(V(0.0), s[1], ops::fma(s[3], s[3], s[2] * s[2])));
  }

  template <class V>
  static void invariants(const Coeffs& c, const State<V>& s, V* out) {
    const formula::Program& p = c.program->invariants;
    if (p.outputs.empty()) return;
    const V* r = run(p, s);
    for (std::size_t k = 0; k < p.outputs.size(); ++k) out[k] = r[p.outputs[k]];
  }

  static State<double> from_phase_space(const Coeffs& c, const Phase& x, Start) {
    if (c.program->form == formula::Form::phase) return {x.p1, x.p2, x.q1, x.q2};
    const formula::Program& p = c.program->start;
    const double* r = run(p, std::array{x.q1, x.q2, x.p1, x.p2});
    return {x.q1, x.q2, r[p.outputs[0]], r[p.outputs[1]]};
  }

  template <class V>
  static std::array<V, 2> position(const Coeffs& c, const State<V>& s) {
    if (c.program->form == formula::Form::phase) return {s[2], s[3]};
    return {s[0], s[1]};
  }

  // (q1, q2, p1, p2) at the state's node; the two-step form's momentum may read q_{n−1}, one step
  // of the reversed state.
  template <class V>
  static std::array<V, 4> phase(const Coeffs& c, const State<V>& s) {
    const formula::Lowered& m = *c.program;
    if (m.form == formula::Form::phase) return {s[2], s[3], s[0], s[1]};
    std::array<V, 6> in = {s[0], s[1], s[2], s[3], V(0.0), V(0.0)};
    if (m.momentum_reads_previous) {
      State<V> back = reversed(c, s);
      step(c, back);
      in[4] = back[2];
      in[5] = back[3];
    }
    const V* r = run(m.momentum, in);
    return {s[0], s[1], r[m.momentum.outputs[0]], r[m.momentum.outputs[1]]};
  }

  static Phase to_phase_space(const Coeffs& c, const State<double>& s) {
    const auto x = phase(c, s);
    return {x[0], x[1], x[2], x[3]};
  }

  static double time(const Coeffs& c, long long n, const State<double>&) {
    return static_cast<double>(n) * c.program->h;
  }

  // Two-step: (q_{n+1}, q_n). Phase: p → −p, which retraces the steps of a map reversible under it
  // (`qmaps check` measures how well).
  template <class V>
  static State<V> reversed(const Coeffs& c, const State<V>& s) {
    if (c.program->form == formula::Form::phase) return {ops::neg(s[0]), ops::neg(s[1]), s[2], s[3]};
    return {s[2], s[3], s[0], s[1]};
  }

 private:
  // p run on this thread's registers with its inputs from `in`; returns the registers.
  template <class V, std::size_t N>
  static V* run(const formula::Program& p, const std::array<V, N>& in) {
    V* r = formula::registers_for<V>(p);
    for (std::size_t k = 0; k < N && k < p.inputs; ++k) r[k] = in[k];  // (not the unknowns)
    formula::run<V, 1>(p, r);
    return r;
  }
};

}  // namespace qmaps::kernels
