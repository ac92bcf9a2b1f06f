#include "kernels/formula/program.hpp"

#include <array>
#include <atomic>
#include <bit>
#include <cmath>
#include <map>
#include <utility>
#include <vector>

#include "kernels/formula/evaluate.hpp"

namespace qmaps::formula {
namespace {

constexpr bool commutative(Code code) { return code == Code::add || code == Code::mul; }
// How many operands an instruction reads: a, then b, then c.
constexpr int operands(Code code) {
  if (code == Code::fma || code == Code::fms) return 3;
  return code == Code::add || code == Code::sub || code == Code::mul || code == Code::div ? 2 : 1;
}

// Marks the operands that are the previous instruction's result (chained) and the results that
// nothing else reads (not stored).
void chain(Program& p) {
  // the reads of each register: by the outputs and by the instructions' operands
  std::vector<int> reads(p.registers(), 0);
  for (const std::uint16_t r : p.outputs) ++reads[r];
  for (const Instruction& i : p.code) {
    ++reads[i.a];
    if (operands(i.code) >= 2) ++reads[i.b];
    if (operands(i.code) == 3) ++reads[i.c];
  }
  for (std::size_t k = 0; k < p.code.size(); ++k) {
    Instruction& i = p.code[k];
    i.chained = Chained::none;
    i.stored = true;
    if (k == 0 || !chainable(i.code) || !chainable(p.code[k - 1].code)) continue;
    const std::uint16_t previous = p.code[k - 1].out;
    const int n = operands(i.code);
    // the previous result first where the order is free (a + b, a·b, a·b ± c)
    const bool free_order = commutative(i.code) || i.code == Code::fma || i.code == Code::fms;
    if (free_order && i.b == previous && i.a != previous) std::swap(i.a, i.b);
    const bool a = i.a == previous, b = n >= 2 && i.b == previous, c = n == 3 && i.c == previous;
    i.chained = a && b ? Chained::a_and_b : a ? Chained::a : b ? Chained::b : c ? Chained::c
                                                                      : Chained::none;
    const int passed = i.chained == Chained::a_and_b ? 2 : i.chained == Chained::none ? 0 : 1;
    p.code[k - 1].stored = reads[previous] > passed;
  }
}

}  // namespace

Lowering::Lowering(const Formulas& f, const std::vector<std::string>& inputs,
                   const std::vector<std::pair<std::string, double>>& parameters)
    : f_(f), inputs_(inputs.size()), parameters_(parameters), used_(parameters.size(), false) {
  for (std::size_t k = 0; k < inputs.size(); ++k)
    inputs_by_name_[inputs[k]] = static_cast<std::uint16_t>(k);
}

void Lowering::assign_all(bool over_parameters) {
  for (const Assignment& a : f_.assignments) {
    for (const auto& parameter : parameters_)
      if (parameter.first == a.name && !over_parameters)
        throw FormulaError(a.at, "'" + a.name + "' is a parameter; it cannot be assigned");
    names_[a.name] = value(a.root);
  }
}

std::uint16_t Lowering::value_of(const std::string& name, Position at) {
  if (const auto it = names_.find(name); it != names_.end()) return it->second;
  if (const auto it = inputs_by_name_.find(name); it != inputs_by_name_.end()) return it->second;
  for (std::size_t k = 0; k < parameters_.size(); ++k)
    if (parameters_[k].first == name) {
      used_[k] = true;
      return constant(parameters_[k].second);
    }
  std::string known;
  for (const auto& [input, r] : inputs_by_name_) known += (known.empty() ? "" : ", ") + input;
  for (const auto& [parameter, v] : parameters_) known += (known.empty() ? "" : ", ") + parameter;
  throw FormulaError(at, "unknown symbol '" + name + "' (known here: " + known + ")");
}

std::uint16_t Lowering::next_register(Position at) {
  if (inputs_ + values_.size() >= max_instructions)
    throw FormulaError(at, "the formulas need more than " + std::to_string(max_instructions) +
                               " values");
  return static_cast<std::uint16_t>(inputs_ + values_.size());
}

std::uint16_t Lowering::constant(double number) {
  const auto bits = std::bit_cast<std::uint64_t>(number);
  if (const auto it = constants_.find(bits); it != constants_.end()) return it->second;
  const std::uint16_t r = next_register({});
  values_.push_back({true, number, {}, {}});
  constants_[bits] = r;
  return r;
}

std::uint16_t Lowering::emit(Code code, std::uint16_t a, std::uint16_t b, std::uint16_t c,
                             Position at) {
  const bool binary = operands(code) >= 2;
  if (code != Code::fma) c = 0;
  if (!binary) b = 0;
  if (code == Code::div && is_constant(b) && number_at(b) == 0)
    throw FormulaError(at, "a division by zero: the parameters make the divisor 0");
  if (is_constant(a) && (!binary || is_constant(b)) && (code != Code::fma || is_constant(c))) {
    const double number = apply<double>(code, number_at(a), binary ? number_at(b) : 0.0,
                                        code == Code::fma ? number_at(c) : 0.0);
    if (!std::isfinite(number))
      throw FormulaError(at, "the parameters make this value " + number_text(number));
    return constant(number);
  }
  // a·b and b·a are one value (IEEE products and sums commute exactly)
  const auto key = commutative(code) && b < a ? std::tuple{code, b, a, c} : std::tuple{code, a, b, c};
  if (const auto it = seen_.find(key); it != seen_.end()) return it->second;
  const std::uint16_t r = next_register(at);
  values_.push_back({false, 0, {code, r, a, b, c}, at});
  seen_[key] = r;
  return r;
}

std::uint16_t Lowering::power(std::uint16_t base, int exponent, Position at) {
  if (exponent == 0) return constant(1.0);
  const int n = exponent < 0 ? -exponent : exponent;
  // binary powering from the highest bit: x^n = (x^(n/2))² · x^(n mod 2)
  std::uint16_t result = base;
  for (int bit = std::bit_width(static_cast<unsigned>(n)) - 2; bit >= 0; --bit) {
    result = emit(Code::mul, result, result, 0, at);
    if ((n >> bit) & 1) result = emit(Code::mul, result, base, 0, at);
  }
  return exponent < 0 ? emit(Code::div, constant(1.0), result, 0, at) : result;
}

std::uint16_t Lowering::value(int i) {
  const Node& n = f_.nodes.at(static_cast<std::size_t>(i));
  switch (n.op) {
    case Op::number: return constant(n.number);
    case Op::symbol: return value_of(n.name, n.at);
    case Op::neg: return emit(Code::neg, value(n.a), 0, 0, n.at);
    case Op::power: return power(value(n.a), n.exponent, n.at);
    case Op::fma: {
      const std::uint16_t a = value(n.a), b = value(n.b);
      return emit(Code::fma, a, b, value(n.c), n.at);
    }
    default: break;
  }
  if (n.b >= 0) {
    const std::uint16_t a = value(n.a);
    const std::uint16_t b = value(n.b);
    const Code code = n.op == Op::add ? Code::add : n.op == Op::sub ? Code::sub
                    : n.op == Op::mul ? Code::mul : Code::div;
    return emit(code, a, b, 0, n.at);
  }
  const Code code = n.op == Op::sqrt ? Code::sqrt : n.op == Op::sin ? Code::sin
                  : n.op == Op::cos ? Code::cos : n.op == Op::exp ? Code::exp : Code::log;
  return emit(code, value(n.a), 0, 0, n.at);
}

Lowering::Affine Lowering::affine(std::uint16_t r, const std::vector<std::uint16_t>& unknowns,
                                  const std::string& what) {
  const std::size_t n = unknowns.size();
  std::map<std::uint16_t, Affine> known;  // the forms found, by register
  // the sum or difference of two terms that may be zero
  const auto combine = [&](Code code, std::uint16_t a, std::uint16_t b, Position at) -> std::uint16_t {
    if (b == zero) return a;
    if (a == zero) return code == Code::add ? b : emit(Code::neg, b, 0, 0, at);
    return emit(code, a, b, 0, at);
  };
  const auto scaled = [&](const Affine& f, Code code, std::uint16_t by, Position at) {
    Affine out{std::vector<std::uint16_t>(n, zero), zero};
    for (std::size_t j = 0; j < n; ++j)
      if (f.coefficient[j] != zero) out.coefficient[j] = emit(code, f.coefficient[j], by, 0, at);
    if (f.constant != zero) out.constant = emit(code, f.constant, by, 0, at);
    return out;
  };
  const auto free_of = [](const Affine& f) {
    for (const std::uint16_t c : f.coefficient)
      if (c != zero) return false;
    return true;
  };
  const auto form = [&](const auto& self, std::uint16_t x) -> Affine {
    if (const auto it = known.find(x); it != known.end()) return it->second;
    Affine f{std::vector<std::uint16_t>(n, zero), x};  // free of the unknowns: itself
    for (std::size_t j = 0; j < n; ++j)
      if (unknowns[j] == x) {
        f.constant = zero;
        f.coefficient[j] = constant(1.0);
      }
    if (x >= inputs_ && !values_[x - inputs_].constant) {
      const Instruction i = values_[x - inputs_].made;
      const Position at = values_[x - inputs_].at;
      const Affine a = self(self, i.a);
      const bool binary = operands(i.code) >= 2;
      const Affine b = binary ? self(self, i.b) : Affine{std::vector<std::uint16_t>(n, zero), zero};
      const bool a_free = free_of(a), b_free = free_of(b);
      const auto refuse = [&] { throw FormulaError(at, "not linear in " + what); };
      if (!a_free || !b_free) {
        switch (i.code) {
          case Code::add:
          case Code::sub:
            for (std::size_t j = 0; j < n; ++j)
              f.coefficient[j] = combine(i.code, a.coefficient[j], b.coefficient[j], at);
            f.constant = combine(i.code, a.constant, b.constant, at);
            break;
          case Code::neg:
            f = scaled(a, Code::mul, constant(-1.0), at);
            break;
          case Code::mul:
            if (!a_free && !b_free) refuse();
            f = a_free ? scaled(b, Code::mul, i.a, at) : scaled(a, Code::mul, i.b, at);
            break;
          case Code::div:
            if (!b_free) refuse();
            f = scaled(a, Code::div, i.b, at);
            break;
          case Code::fma: {
            if (!a_free && !b_free) refuse();
            const Affine product = a_free ? scaled(b, Code::mul, i.a, at) : scaled(a, Code::mul, i.b, at);
            const Affine c = self(self, i.c);
            for (std::size_t j = 0; j < n; ++j)
              f.coefficient[j] = combine(Code::add, product.coefficient[j], c.coefficient[j], at);
            f.constant = combine(Code::add, product.constant, c.constant, at);
            break;
          }
          default:
            refuse();
        }
      } else if (i.code == Code::fma && !free_of(self(self, i.c))) {
        const Affine c = self(self, i.c);  // a·b (free of the unknowns) + c
        f = c;
        f.constant = combine(Code::add, emit(Code::mul, i.a, i.b, 0, at), c.constant, at);
      }
    }
    known.emplace(x, f);
    return f;
  };
  return form(form, r);
}

std::vector<std::uint16_t> Lowering::solve_linear(const std::vector<std::uint16_t>& equations,
                                                  const std::vector<std::uint16_t>& unknowns,
                                                  const std::string& what, Position at,
                                                  std::uint16_t& determinant) {
  const std::size_t n = unknowns.size();
  std::vector<Affine> rows;
  for (const std::uint16_t e : equations) rows.push_back(affine(e, unknowns, what));
  const auto term = [&](std::uint16_t r) { return r == zero ? constant(0.0) : r; };
  const auto a = [&](std::size_t i, std::size_t j) { return term(rows[i].coefficient[j]); };
  const auto c = [&](std::size_t i) { return term(rows[i].constant); };
  // det = a00 a11 − a01 a10;  u0 = (a01 c1 − a11 c0)/det,  u1 = (a10 c0 − a00 c1)/det
  determinant = n == 1 ? a(0, 0)
                       : emit(Code::sub, emit(Code::mul, a(0, 0), a(1, 1)),
                              emit(Code::mul, a(0, 1), a(1, 0)));
  if (is_constant(determinant) && number_at(determinant) == 0)
    throw FormulaError(at, "the equations for " + what + " are singular whatever the state");
  if (n == 1) return {emit(Code::div, emit(Code::neg, c(0)), determinant)};  // a u + c = 0
  const std::uint16_t u0 =
      emit(Code::sub, emit(Code::mul, a(0, 1), c(1)), emit(Code::mul, a(1, 1), c(0)));
  const std::uint16_t u1 =
      emit(Code::sub, emit(Code::mul, a(1, 0), c(0)), emit(Code::mul, a(0, 0), c(1)));
  return {emit(Code::div, u0, determinant), emit(Code::div, u1, determinant)};
}

Program Lowering::finish(const std::vector<std::uint16_t>& outputs) const {
  // the instructions made, with fma(a, b, −c) as fms(a, b, c)
  std::vector<Value> made = values_;
  const auto negation = [&](std::uint16_t r) {
    return r >= inputs_ && !made[r - inputs_].constant && made[r - inputs_].made.code == Code::neg;
  };
  for (Value& v : made)
    if (!v.constant && v.made.code == Code::fma && negation(v.made.c))
      v.made = {Code::fms, v.made.out, v.made.a, v.made.b, made[v.made.c - inputs_].made.a};
  // what the outputs need, back from them (an instruction reads only earlier registers)
  std::vector<bool> needed(inputs_ + made.size(), false);
  for (const std::uint16_t r : outputs) needed[r] = true;
  for (std::size_t k = made.size(); k-- > 0;) {
    const Value& v = made[k];
    if (!needed[inputs_ + k] || v.constant) continue;
    needed[v.made.a] = true;
    if (operands(v.made.code) >= 2) needed[v.made.b] = true;
    if (operands(v.made.code) == 3) needed[v.made.c] = true;
  }
  Program p;
  p.id = new_program_id();
  p.inputs = inputs_;
  std::vector<std::uint16_t> final(inputs_ + made.size(), 0);
  for (std::size_t k = 0; k < inputs_; ++k) final[k] = static_cast<std::uint16_t>(k);
  for (std::size_t k = 0; k < made.size(); ++k)
    if (needed[inputs_ + k] && made[k].constant) {
      final[inputs_ + k] = static_cast<std::uint16_t>(inputs_ + p.constants.size());
      p.constants.push_back(made[k].number);
    }
  const std::size_t first = inputs_ + p.constants.size();
  for (std::size_t k = 0; k < made.size(); ++k)
    if (needed[inputs_ + k] && !made[k].constant) {
      Instruction i = made[k].made;
      final[inputs_ + k] = static_cast<std::uint16_t>(first + p.code.size());
      i.out = final[inputs_ + k];
      i.a = final[i.a];
      i.b = final[i.b];
      i.c = final[i.c];
      p.code.push_back(i);
    }
  for (const std::uint16_t r : outputs) p.outputs.push_back(final[r]);
  chain(p);
  return p;
}

std::uint64_t new_program_id() {
  static std::atomic<std::uint64_t> count{0};
  return ++count;
}

std::optional<Program> with_state_in(const Program& p, std::size_t slots,
                                      const std::array<std::uint16_t, 4>& inputs_at,
                                      const std::vector<std::uint16_t>& outputs_at) {
  if (p.inputs < 4 || slots < p.inputs) return std::nullopt;
  constexpr std::uint16_t unread = 0xffff;
  std::vector<std::uint16_t> to(p.registers());
  for (std::size_t r = 0; r < p.inputs; ++r) to[r] = r < 4 ? inputs_at[r] : unread;
  for (std::size_t r = p.inputs; r < to.size(); ++r)
    to[r] = static_cast<std::uint16_t>(r - p.inputs + slots);
  const std::size_t first_instruction = p.inputs + p.constants.size();
  for (std::size_t o = 0; o < outputs_at.size(); ++o) {
    const std::uint16_t r = p.outputs[o];
    if (r == o && inputs_at[o] == outputs_at[o]) continue;  // kept where it is
    if (r < first_instruction) return std::nullopt;
    for (std::size_t before = 0; before < o; ++before)
      if (p.outputs[before] == r) return std::nullopt;
    to[r] = outputs_at[o];
  }
  Program q = p;
  q.inputs = slots;
  for (Instruction& i : q.code) {
    const std::array<std::uint16_t*, 3> read = {&i.a, &i.b, &i.c};
    for (int k = 0; k < 3; ++k) {
      std::uint16_t& r = *read[static_cast<std::size_t>(k)];
      if (k >= operands(i.code)) r = 0;  // (not read)
      else if (to[r] == unread) return std::nullopt;
      else r = to[r];
    }
    i.out = to[i.out];
  }
  for (std::uint16_t& r : q.outputs) r = to[r];
  return q;
}

}  // namespace qmaps::formula
