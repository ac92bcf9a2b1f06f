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
  // Blocks of 8 chains alone, whatever the run asks: each instruction is decoded once per block,
  // so fewer chains only slow the map (Suris as formulas, AVX-512, 1 thread: 3.2e8 particle-
  // steps/s in blocks of 1 chain, 6.4e8 of 2, 7.4e8 of 4, 1.0–1.3e9 of 8), and each count is the
  // interpreter compiled once more per ISA.
  static constexpr int min_chains = 8;

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
  // The state components the step leaves as they are (the value of its own input): q2, p2 of a
  // phase map of one degree of freedom, q2 at both nodes of such a two-step map.
  static std::vector<std::size_t> inert_state(const Coeffs& c) {
    const formula::Program& p = c.program->step;
    std::vector<std::size_t> out;
    if (c.program->form == formula::Form::phase) {
      for (std::size_t k = 0; k < 4; ++k)
        if (p.outputs[k] == k) out.push_back(k);
    } else {
      for (std::size_t k = 0; k < 4; ++k)  // q_k at nodes n − 1 and n
        if (p.outputs[k % 2] == k % 2 + 2) out.push_back(k);
    }
    return out;
  }
  static std::vector<std::string> invariant_names(const Coeffs& c) {
    return c.definition->invariant_names();
  }

  // K chains stepped `steps` steps together, each instruction decoded once for all of them
  // (core/block.hpp), with the state resident in the registers where the step allows
  // (Lowered::resident): escape gets each step's escape measures, summed chain by chain before
  // it; returns the sum of the fault codes.
  // Out of line: one copy per chain count, however many loops call it (inlined into each, the
  // interpreter's every kind was compiled once per call site).
  template <class V, int K>
  [[gnu::noinline]] static V step_chains(const Coeffs& c, State<V> (&s)[K], long long steps, V& escape) {
    const formula::Lowered& m = *c.program;
    const formula::Rotation& rotation = m.resident;
    const bool resident = !rotation.programs.empty();
    const std::size_t turns = resident ? rotation.programs.size() : 1;
    V* r = formula::registers_for<V, K>(resident ? rotation.programs[0] : m.step);
    const auto at = [&](std::size_t v, std::size_t i) -> V* {  // state component i's K values
      return r + (resident ? rotation.state_at[v][i] : i) * K;
    };
    for (std::size_t i = 0; i < 4; ++i)
      for (int k = 0; k < K; ++k) at(0, i)[k] = s[k][i];
    V faults(0.0);
    std::size_t v = 0;
    for (long long n = 0; n < steps; ++n) {
      for (int k = 0; k < K; ++k)
        escape = escape + escape_measure(State<V>{at(v, 0)[k], at(v, 1)[k], at(v, 2)[k], at(v, 3)[k]});
      const formula::Program& p = resident ? rotation.programs[v] : m.step;
      formula::run<V, K>(p, r);
      const auto out = [&](std::size_t o, int k) { return r[p.outputs[o] * K + k]; };
      if (m.solves)
        for (int k = 0; k < K; ++k)
          faults = faults + ops::select(out(2, k) == V(0.0),
                                        V(static_cast<double>(EscapeReason::singular)), V(0.0));
      if (resident) {
        v = v + 1 == turns ? 0 : v + 1;
        continue;
      }
      for (int k = 0; k < K; ++k) {  // the new state into the inputs
        const State<V> next = m.form == formula::Form::phase
                                  ? State<V>{out(0, k), out(1, k), out(2, k), out(3, k)}
                                  : State<V>{r[2 * K + k], r[3 * K + k], out(0, k), out(1, k)};
        for (std::size_t i = 0; i < 4; ++i) r[i * K + k] = next[i];
      }
    }
    for (int k = 0; k < K; ++k)
      s[k] = {at(v, 0)[k], at(v, 1)[k], at(v, 2)[k], at(v, 3)[k]};
    return faults;
  }
  template <class V>
  static V step(const Coeffs& c, State<V>& s) {
    State<V> one[1] = {s};
    V escape(0.0);
    const V faults = step_chains<V, 1>(c, one, 1, escape);
    s = one[0];
    return faults;
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
