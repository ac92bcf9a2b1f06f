#pragma once
// Formulas lowered once to a straight-line program that evaluate.hpp runs over any value type.
// Registers: the inputs first, then the constants (the numbers written and the parameters'
// values), then one per instruction in order. Each (operation, operands) is computed once: a
// common subexpression shares its register. An instruction whose operands are all constants is
// computed here, by the same ops, into a constant (so a parameter's expression costs nothing per
// step, and is refused where it is not finite: a division by a zero parameter). An integer power
// is a product by binary powering (x⁵ = (x²)²·x), a negative one its reciprocal. Nothing is
// reassociated, and a·b + c stays two roundings unless written fma: every path computes the same.
// fma(a, b, −c) is fms(a, b, c), one rounding of the same value. An instruction's operand that is
// the previous instruction's result is marked chained: evaluate.hpp passes it in the processor's
// registers, and writes a result to its register only where something else reads it (Suris: 3 of
// its 8 results), which halves the stores that bound the evaluation.
#include <array>
#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <tuple>
#include <utility>
#include <vector>

#include "kernels/formula/expression.hpp"

namespace qmaps::formula {

inline constexpr std::size_t max_instructions = 4096;

enum class Code : std::uint8_t { add, sub, mul, div, neg, fma, fms, sqrt, sin, cos, exp, log };
// The arithmetic (add … sqrt) is chained; sin, cos, exp and log read and write registers.
constexpr bool chainable(Code code) { return code <= Code::sqrt; }

// The operands of an instruction that are the previous instruction's result.
enum class Chained : std::uint8_t { none, a, b, c, a_and_b };

struct Instruction {
  Code code;
  std::uint16_t out, a, b, c;
  Chained chained = Chained::none;
  bool stored = true;  // false: only the next instruction reads it, chained
};

struct Program {
  std::size_t inputs = 0;
  std::vector<double> constants;  // registers inputs .. inputs + constants.size() − 1
  std::vector<Instruction> code;  // each writes a register of its own, after the constants
  std::vector<std::uint16_t> outputs;
  std::uint64_t id = 0;  // unique to the program finish() made (evaluate.hpp's register files)
  std::size_t registers() const { return inputs + constants.size() + code.size(); }
};

// A step whose state stays in the register file from step to step: its first registers are slots
// that the state's inputs and outputs rotate through, so that no step copies the state (two-step:
// q_{n−1}, q_n, q_{n+1} in three slots of two; phase: the new state written in the slots beside
// the old). Step n runs programs[n mod programs.size()], all on one register file; the state
// before programs[v] is in registers state_at[v].
struct Rotation {
  std::vector<Program> programs;
  std::vector<std::array<std::uint16_t, 4>> state_at;
};

// p with its state in slots: `slots` registers first, input i read from inputs_at[i] (i < 4; the
// inputs after those must be unread) and state output o written to outputs_at[o], the other
// registers after the slots. Nothing where a state output is no instruction's result of its own
// (a number, an input, another output's value), except input o itself, left in place (inputs_at[o]
// = outputs_at[o]: a coordinate the step keeps).
std::optional<Program> with_state_in(const Program& p, std::size_t slots,
                                      const std::array<std::uint16_t, 4>& inputs_at,
                                      const std::vector<std::uint16_t>& outputs_at);
// A new program id (evaluate.hpp's register files): programs sharing one file share it.
std::uint64_t new_program_id();

// Builds a program from the assignments of formulas over named inputs and parameters.
class Lowering {
 public:
  Lowering(const Formulas& f, const std::vector<std::string>& inputs,
           const std::vector<std::pair<std::string, double>>& parameters);

  // The assignments in order: each name then denotes its value (a later one replaces it). A
  // parameter's name may be assigned only where `over_parameters` (a name of another kind).
  void assign_all(bool over_parameters = false);
  // The register of node i's value, or of a name's current value (an input, a parameter or an
  // assignment's; at: where it is asked for, in an error).
  std::uint16_t value(int node);
  std::uint16_t value_of(const std::string& name, Position at);
  bool assigned(const std::string& name) const { return names_.contains(name); }
  // A new instruction (or the register that already holds it, or its constant).
  std::uint16_t emit(Code code, std::uint16_t a, std::uint16_t b = 0, std::uint16_t c = 0,
                     Position at = {});
  std::uint16_t constant(double value);
  // The program whose outputs are these registers, without what none of them needs.
  Program finish(const std::vector<std::uint16_t>& outputs) const;
  // A value as an affine form in some of the inputs (the unknowns):
  //   Σ_j coefficient[j]·unknown_j + constant,
  // each term a register that depends on no unknown, or `zero`. A value that is not affine in
  // them is refused where it stops being so (a product or quotient of two of them, a function of
  // one).
  static constexpr std::uint16_t zero = 0xffff;
  struct Affine {
    std::vector<std::uint16_t> coefficient;
    std::uint16_t constant = zero;
  };
  Affine affine(std::uint16_t r, const std::vector<std::uint16_t>& unknowns, const std::string& what);
  // The unknowns u solving Σ_j A_ij u_j + c_i = 0 for equations i (as many as unknowns, at most
  // 2), by Cramer's rule, and the determinant: 0 where the system is singular for a state (a
  // system singular for every state is refused, at `at`).
  std::vector<std::uint16_t> solve_linear(const std::vector<std::uint16_t>& equations,
                                          const std::vector<std::uint16_t>& unknowns,
                                          const std::string& what, Position at,
                                          std::uint16_t& determinant);
  // Whether parameter k was read.
  const std::vector<bool>& parameters_used() const { return used_; }

 private:
  // Registers while the program grows ("provisional"): the inputs, then every constant and
  // instruction in the order made; finish() numbers the constants before the instructions.
  struct Value {
    bool constant;
    double number;     // a constant's
    Instruction made;  // an instruction's, over provisional registers
    Position at;       // where the formulas ask for it
  };
  bool is_constant(std::uint16_t r) const { return r >= inputs_ && values_[r - inputs_].constant; }
  double number_at(std::uint16_t r) const { return values_[r - inputs_].number; }
  std::uint16_t next_register(Position at);
  std::uint16_t power(std::uint16_t base, int exponent, Position at);

  const Formulas& f_;
  std::size_t inputs_;
  std::vector<std::pair<std::string, double>> parameters_;
  std::vector<bool> used_;
  std::map<std::string, std::uint16_t, std::less<>> names_;  // the assignments' current values
  std::map<std::string, std::uint16_t, std::less<>> inputs_by_name_;
  std::vector<Value> values_;
  std::map<std::uint64_t, std::uint16_t> constants_;  // by bit pattern
  std::map<std::tuple<Code, std::uint16_t, std::uint16_t, std::uint16_t>, std::uint16_t> seen_;
};

}  // namespace qmaps::formula
