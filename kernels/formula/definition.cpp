#include "kernels/formula/definition.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <utility>

namespace qmaps::formula {
namespace {

using Parameters = std::vector<std::pair<std::string, double>>;
using Names = std::vector<std::string>;

const Names phase_state = {"p1", "p2", "q1", "q2"};
const Names two_step_state = {"q1_prev", "q2_prev", "q1", "q2"};
const Names two_step_unknowns = {"q1_prev", "q2_prev", "q1", "q2", "q1_next", "q2_next"};
const Names two_step_node = {"q1", "q2", "q1_next", "q2_next"};
const Names momentum_inputs = {"q1", "q2", "q1_next", "q2_next", "q1_prev", "q2_prev"};
const Names start_inputs = {"q1", "q2", "p1", "p2"};
constexpr std::array<std::string_view, 5> potential_names = {"A", "B", "alpha", "beta", "delta"};

// The step with its state resident in registers (program.hpp's Rotation). Phase: two slots of 4,
// the new state written beside the old (a coordinate the step keeps stays in the first);
// two-step: three slots of 2 for q_{n−1}, q_n and q_{n+1}, in turn.
Rotation resident(const Program& step, Form form) {
  Rotation out;
  const std::uint64_t id = new_program_id();  // one register file for all of them
  const auto add = [&](std::size_t slots, std::array<std::uint16_t, 4> in,
                       std::vector<std::uint16_t> to) {
    auto p = with_state_in(step, slots, in, to);
    if (!p) return false;
    p->id = id;
    out.programs.push_back(std::move(*p));
    out.state_at.push_back(in);
    return true;
  };
  bool all = true;
  if (form == Form::phase) {
    const auto slot = [&](std::size_t side, std::uint16_t k) {
      return static_cast<std::uint16_t>(step.outputs[k] == k ? k : 4 * side + k);
    };
    for (std::size_t side : {0, 1})
      all = all && add(8, {slot(side, 0), slot(side, 1), slot(side, 2), slot(side, 3)},
                       {slot(1 - side, 0), slot(1 - side, 1), slot(1 - side, 2), slot(1 - side, 3)});
  } else {
    const auto slot = [](std::size_t v, std::uint16_t k) {
      return static_cast<std::uint16_t>(2 * (v % 3) + k);
    };
    for (std::size_t v : {0, 1, 2})
      all = all && add(6, {slot(v, 0), slot(v, 1), slot(v + 1, 0), slot(v + 1, 1)},
                       {slot(v + 2, 0), slot(v + 2, 1)});
  }
  return all ? out : Rotation{};
}

// Runs f, reporting a FormulaError as an error of `key`.
template <class F>
auto in_key(std::string_view key, F&& f) {
  try {
    return f();
  } catch (const FormulaError& e) {
    throw DefinitionError(std::string(key), e.what());
  }
}

Formulas parse_key(const MapText& text, std::string_view key) {
  return in_key(key, [&] { return parse_assignments(text_of(text, key)); });
}

// The register of `name` after the assignments, which must assign it.
std::uint16_t assigned(Lowering& l, const std::string& name, std::string_view key,
                       std::string_view needs) {
  if (!l.assigned(name))
    throw DefinitionError(std::string(key), "assigns no '" + name + "' (" + std::string(needs) + ")");
  return l.value_of(name, {});
}

// A program's single output when it is a constant, else nullopt.
std::optional<double> constant_of(const Program& p) {
  if (!p.code.empty()) return std::nullopt;
  return p.constants[p.outputs.front() - p.inputs];
}

}  // namespace

std::string& text_of(MapText& t, std::string_view key) {
  return const_cast<std::string&>(text_of(std::as_const(t), key));
}
const std::string& text_of(const MapText& t, std::string_view key) {
  const std::string* fields[] = {&t.name,     &t.form,  &t.parameters, &t.step,      &t.equations,
                                 &t.momentum, &t.start, &t.invariants, &t.continuous};
  for (std::size_t k = 0; k < map_keys.size(); ++k)
    if (map_keys[k] == key) return *fields[k];
  throw usage_error("no formula key '" + std::string(key) + "'");
}

const std::array<std::string_view, 4>& Definition::state_names() const {
  static constexpr std::array<std::string_view, 4> phase = {"p1", "p2", "q1", "q2"};
  static constexpr std::array<std::string_view, 4> two_step = {"q1_n", "q2_n", "q1_n+1", "q2_n+1"};
  return form_ == Form::phase ? phase : two_step;
}

std::shared_ptr<const Definition> Definition::parse(const MapText& given) {
  std::shared_ptr<Definition> d(new Definition);
  d->text_ = given;
  MapText& t = d->text_;
  if (t.name.empty()) throw DefinitionError("name", "a formula map needs a name");
  for (const char c : t.name)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-'))
      throw DefinitionError("name", "'" + t.name + "': letters, digits, '_' and '-' only");
  if (t.form == "phase")
    d->form_ = Form::phase;
  else if (t.form == "two_step")
    d->form_ = Form::two_step;
  else
    throw DefinitionError("form", "'" + t.form + "' is not a form (phase, two_step)");

  // The parameters and their defaults: each a number.
  if (!t.parameters.empty()) {
    const Formulas p = parse_key(t, "parameters");
    Lowering l(p, {}, {});
    for (const Assignment& a : p.assignments) {
      if (std::find(d->param_names_.begin(), d->param_names_.end(), a.name) !=
          d->param_names_.end())
        throw DefinitionError("parameters", "line " + std::to_string(a.at.line) + ", column " +
                                                std::to_string(a.at.column) + ": '" + a.name +
                                                "' is declared twice");
      const Program value = in_key("parameters", [&] { return l.finish({l.value(a.root)}); });
      const auto number = constant_of(value);
      if (!number || !std::isfinite(*number))
        throw DefinitionError("parameters", "line " + std::to_string(a.at.line) + ", column " +
                                                std::to_string(a.at.column) + ": the default of '" +
                                                a.name + "' is not a finite number");
      d->param_names_.push_back(a.name);
      d->specs_.push_back({{}, "a parameter of the formulas", *number});
    }
    for (std::size_t k = 0; k < d->param_names_.size(); ++k)
      d->specs_[k].name = d->param_names_[k];
  }
  const bool has_h =
      std::find(d->param_names_.begin(), d->param_names_.end(), "h") != d->param_names_.end();

  // The forms' keys, and their defaults.
  const auto refuse_key = [&](std::string_view key, std::string_view why) {
    if (!text_of(t, key).empty()) throw DefinitionError(std::string(key), std::string(why));
  };
  if (d->form_ == Form::phase) {
    if (t.step.empty()) throw DefinitionError("step", "the phase form needs its step");
    for (std::string_view key : {"equations", "momentum", "start"})
      refuse_key(key, "belongs to the two_step form; a phase map's state is its phase point");
  } else {
    if (t.step.empty() == t.equations.empty())
      throw DefinitionError(t.step.empty() ? "step" : "equations",
                            "the two_step form takes either its step (q1_next, q2_next) or its "
                            "equations (eq1, eq2 linear in q1_next, q2_next), one of them");
    for (std::string_view key : {"momentum", "start"})
      if (text_of(t, key).empty() && !has_h)
        throw DefinitionError(std::string(key),
                              std::string("not given, and its default (") +
                                  (key == "momentum" ? "p = (q_next - q)/h" : "q_next = q + h p") +
                                  ") needs a parameter h");
    if (t.momentum.empty()) t.momentum = "p1 = (q1_next - q1)/h\np2 = (q2_next - q2)/h";
    if (t.start.empty()) t.start = "q1_next = q1 + h*p1\nq2_next = q2 + h*p2";
    d->solves_ = !t.equations.empty();
  }
  d->step_ = parse_key(t, d->solves_ ? "equations" : "step");
  if (d->form_ == Form::two_step) {
    d->momentum_ = parse_key(t, "momentum");
    d->start_ = parse_key(t, "start");
  }
  if (!t.invariants.empty()) {
    d->invariants_ = parse_key(t, "invariants");
    for (const Assignment& a : d->invariants_.assignments)
      if (a.name.front() != '_' && std::find(d->invariant_names_.begin(),
                                             d->invariant_names_.end(),
                                             a.name) == d->invariant_names_.end())
        d->invariant_names_.push_back(a.name);
    if (d->invariant_names_.size() > max_invariants)
      throw DefinitionError("invariants", "more than " + std::to_string(max_invariants) +
                                              " invariants");
  }
  if (!t.continuous.empty()) d->continuous_ = parse_key(t, "continuous");

  // Lowered once at the defaults: unknown symbols, non-linear equations, missing assignments
  // and unused parameters are errors whatever the values.
  std::vector<double> defaults;
  for (const ParamSpec& s : d->specs_) defaults.push_back(s.default_value);
  d->lower(defaults);
  return d;
}

Lowered Definition::lower(std::span<const double> values) const {
  Parameters parameters;
  for (std::size_t k = 0; k < param_names_.size(); ++k)
    parameters.emplace_back(param_names_[k], values[k]);
  std::vector<bool> used(parameters.size(), false);
  const auto note_used = [&](const Lowering& l) {
    for (std::size_t k = 0; k < used.size(); ++k) used[k] = used[k] || l.parameters_used()[k];
  };
  Lowered out;
  out.form = form_;
  out.solves = solves_;
  for (std::size_t k = 0; k < param_names_.size(); ++k)
    if (param_names_[k] == "h") out.h = values[k];

  // The step.
  const std::string_view step_key = solves_ ? "equations" : "step";
  in_key(step_key, [&] {
    if (form_ == Form::phase) {
      Lowering l(step_, phase_state, parameters);
      l.assign_all();
      std::vector<std::uint16_t> outputs;
      for (const auto& name : phase_state) outputs.push_back(l.value_of(name, {}));
      out.step = l.finish(outputs);
      note_used(l);
    } else if (!solves_) {
      Lowering l(step_, two_step_state, parameters);
      l.assign_all();
      out.step = l.finish({assigned(l, "q1_next", step_key, "q_{n+1}"),
                           assigned(l, "q2_next", step_key, "q_{n+1}")});
      note_used(l);
    } else {
      Lowering l(step_, two_step_unknowns, parameters);
      l.assign_all();
      const std::vector<std::uint16_t> equations = {
          assigned(l, "eq1", step_key, "the equations eq1 = 0, eq2 = 0"),
          assigned(l, "eq2", step_key, "the equations eq1 = 0, eq2 = 0")};
      std::uint16_t determinant = 0;
      const Position at = step_.assignments.back().at;
      const auto solution =
          l.solve_linear(equations, {4, 5}, "q1_next, q2_next", at, determinant);
      out.step = l.finish({solution[0], solution[1], determinant});
      note_used(l);
    }
    return 0;
  });
  out.resident = resident(out.step, form_);

  // The two-step form's phase point and start.
  if (form_ == Form::two_step) {
    in_key("momentum", [&] {
      Lowering l(momentum_, momentum_inputs, parameters);
      l.assign_all();
      out.momentum = l.finish({assigned(l, "p1", "momentum", "p at node n"),
                               assigned(l, "p2", "momentum", "p at node n")});
      out.momentum_reads_previous = false;
      for (const Instruction& i : out.momentum.code)
        for (const std::uint16_t r : {i.a, i.b, i.c})
          if (r == 4 || r == 5) out.momentum_reads_previous = true;
      for (const std::uint16_t r : out.momentum.outputs)
        if (r == 4 || r == 5) out.momentum_reads_previous = true;
      note_used(l);
      return 0;
    });
    in_key("start", [&] {
      Lowering l(start_, start_inputs, parameters);
      l.assign_all();
      out.start = l.finish({assigned(l, "q1_next", "start", "q_{n+1} of the first state"),
                            assigned(l, "q2_next", "start", "q_{n+1} of the first state")});
      note_used(l);
      return 0;
    });
  }

  // The invariants, over the state's names.
  if (!invariants_.assignments.empty()) {
    in_key("invariants", [&] {
      Lowering l(invariants_, form_ == Form::phase ? phase_state : two_step_node, parameters);
      l.assign_all();
      std::vector<std::uint16_t> outputs;
      for (const auto& name : invariant_names_) outputs.push_back(l.value_of(name, {}));
      out.invariants = l.finish(outputs);
      note_used(l);
      return 0;
    });
  }

  // The continuous system: five numbers.
  if (!continuous_.assignments.empty()) {
    in_key("continuous", [&] {
      Lowering l(continuous_, {}, parameters);
      l.assign_all(true);  // A = A: the potential's A is the parameter A
      for (const Assignment& a : continuous_.assignments)
        if (std::find(potential_names.begin(), potential_names.end(), a.name) ==
            potential_names.end())
          throw FormulaError(a.at, "'" + a.name + "' is not a coefficient of the quartic "
                                   "potential (A, B, alpha, beta, delta)");
      std::array<double, 5> v{};
      for (std::size_t k = 0; k < potential_names.size(); ++k) {
        const std::string name(potential_names[k]);
        if (!l.assigned(name)) continue;
        const auto number = constant_of(l.finish({l.value_of(name, {})}));
        if (!number)
          throw FormulaError(continuous_.assignments.front().at,
                             "'" + name + "' depends on the state; it is a number of the parameters");
        v[k] = *number;
      }
      out.continuous = Potential{v[0], v[1], v[2], v[3], v[4]};
      note_used(l);
      return 0;
    });
  }

  for (std::size_t k = 0; k < used.size(); ++k)
    if (!used[k])
      throw DefinitionError("parameters", "'" + param_names_[k] + "' is declared but no formula uses it");
  return out;
}

}  // namespace qmaps::formula
