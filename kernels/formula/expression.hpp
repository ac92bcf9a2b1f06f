#pragma once
// A map's formulas as written: assignments `name = expression`, one per line (or separated by
// `;`; `#` starts a comment), parsed once into trees whose nodes know where they were written.
//   sum     = product { ("+" | "-") product }
//   product = unary { ("*" | "/") unary }
//   unary   = ("-" | "+") unary | power
//   power   = atom [ ("^" | "**") ["-" | "+"] integer ]         integer powers, |n| ≤ 64
//   atom    = number | name | name "(" sum { "," sum } ")" | "(" sum ")"
// Functions: fma(a, b, c) (a·b + c rounded once), sqrt, sin, cos, exp, log. So −x^2 is −(x²),
// and a·b + c is two roundings unless written fma. Limits (docs/formulas.md): a text of at most
// max_text characters, max_assignments assignments, nesting at most max_depth deep.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "core/error.hpp"

namespace qmaps::formula {

inline constexpr std::size_t max_text = 16384, max_assignments = 256;
inline constexpr int max_depth = 64, max_power = 64;

// Where a node was written: 1-based line and column of the formulas' text.
struct Position {
  int line = 1, column = 1;
};

// An error in the formulas, at a position: the configuration names the key and adds its line.
class FormulaError : public Error {
 public:
  FormulaError(Position at, const std::string& what)
      : Error(ExitCode::usage, "line " + std::to_string(at.line) + ", column " +
                                   std::to_string(at.column) + ": " + what),
        at_(at), what_(what) {}
  Position at() const { return at_; }
  const std::string& reason() const { return what_; }

 private:
  Position at_;
  std::string what_;
};

enum class Op : std::uint8_t {
  number, symbol,                         // leaves
  neg, add, sub, mul, div, power, fma,    // arithmetic (power: an integer exponent)
  sqrt, sin, cos, exp, log,               // functions of one argument
};

struct Node {
  Op op;
  int a = -1, b = -1, c = -1;  // operands: indices of nodes
  double number = 0;           // a number's value
  int exponent = 0;            // a power's
  std::string name;            // a symbol's
  Position at;
};

struct Assignment {
  std::string name;
  Position at;  // of the name
  int root;     // its expression's node
};

// The formulas of a text, their nodes in one pool.
struct Formulas {
  std::vector<Node> nodes;
  std::vector<Assignment> assignments;
};

// Parses `text` (assignments) or a single expression (`expression`: the text is one, named "").
Formulas parse_assignments(std::string_view text);
Formulas parse_expression(std::string_view text);

// The text of node i, fully parenthesized where precedence needs it (for `list` and messages).
std::string to_text(const Formulas& f, int i);

}  // namespace qmaps::formula
