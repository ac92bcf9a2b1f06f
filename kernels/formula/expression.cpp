#include "kernels/formula/expression.hpp"

#include <array>
#include <charconv>
#include <cmath>
#include <utility>

namespace qmaps::formula {
namespace {

struct Function {
  std::string_view name;
  Op op;
  int arguments;
};
constexpr std::array<Function, 6> functions = {{{"fma", Op::fma, 3},
                                                {"sqrt", Op::sqrt, 1},
                                                {"sin", Op::sin, 1},
                                                {"cos", Op::cos, 1},
                                                {"exp", Op::exp, 1},
                                                {"log", Op::log, 1}}};

bool name_start(char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_'; }
bool digit(char c) { return c >= '0' && c <= '9'; }

class Parser {
 public:
  explicit Parser(std::string_view text) : text_(text) {
    if (text.size() > max_text)
      throw FormulaError({1, 1}, "the formulas are " + std::to_string(text.size()) +
                                     " characters long; at most " + std::to_string(max_text));
    for (std::size_t k = 0; k < text.size(); ++k) {
      const auto c = static_cast<unsigned char>(text[k]);
      if (c >= 0x7f || (c < 0x20 && c != '\n' && c != '\t' && c != '\r'))
        throw FormulaError(position_of(k), "a character that is not printable ASCII");
    }
  }

  Formulas assignments() {
    for (;;) {
      skip_blank_lines();
      if (at_end()) break;
      if (f_.assignments.size() == max_assignments)
        throw FormulaError(here(), "more than " + std::to_string(max_assignments) + " assignments");
      const Position at = here();
      if (!name_start(peek())) throw FormulaError(at, "expected a name to assign, found " + found());
      std::string name = read_name();
      skip_spaces();
      if (peek() != '=') throw FormulaError(here(), "expected '=' after '" + name + "', found " + found());
      ++i_;
      const int root = sum(0);
      f_.assignments.push_back({std::move(name), at, root});
      end_of_statement();
    }
    if (f_.assignments.empty()) throw FormulaError(here(), "no assignment");
    return std::move(f_);
  }

  Formulas expression() {
    skip_spaces();
    if (at_end()) throw FormulaError(here(), "an empty expression");
    const int root = sum(0);
    skip_spaces();
    if (!at_end()) throw FormulaError(here(), "unexpected " + found() + " after the expression");
    f_.assignments.push_back({"", {1, 1}, root});
    return std::move(f_);
  }

 private:
  Position position_of(std::size_t offset) const {
    Position p;
    for (std::size_t k = 0; k < offset && k < text_.size(); ++k) {
      if (text_[k] == '\n') {
        ++p.line;
        p.column = 1;
      } else {
        ++p.column;
      }
    }
    return p;
  }
  Position here() const { return position_of(i_); }
  bool at_end() const { return i_ >= text_.size(); }
  char peek(std::size_t ahead = 0) const {
    return i_ + ahead < text_.size() ? text_[i_ + ahead] : '\0';
  }
  std::string found() const {
    if (at_end()) return "the end";
    if (peek() == '\n') return "the end of the line";
    return "'" + std::string(1, peek()) + "'";
  }
  void skip_comment() {
    if (peek() == '#')
      while (!at_end() && peek() != '\n') ++i_;
  }
  void skip_spaces() {  // within a line
    while (peek() == ' ' || peek() == '\t' || peek() == '\r') ++i_;
    skip_comment();
  }
  void skip_blank_lines() {
    for (;;) {
      skip_spaces();
      if (peek() == '\n' || peek() == ';') ++i_;
      else return;
    }
  }
  void end_of_statement() {
    skip_spaces();
    if (at_end() || peek() == '\n' || peek() == ';') return;
    throw FormulaError(here(), "unexpected " + found() + " after the expression");
  }
  std::string read_name() {
    const std::size_t start = i_;
    while (name_start(peek()) || digit(peek())) ++i_;
    return std::string(text_.substr(start, i_ - start));
  }
  int add(Node n) {
    f_.nodes.push_back(std::move(n));
    return static_cast<int>(f_.nodes.size() - 1);
  }
  void deeper(int depth, Position at) const {
    if (depth > max_depth)
      throw FormulaError(at, "nested more than " + std::to_string(max_depth) + " deep");
  }

  // depth: the parentheses, calls and signs around the expression being read
  int sum(int depth) {
    int left = product(depth);
    for (;;) {
      skip_spaces();
      const char c = peek();
      if (c != '+' && c != '-') return left;
      const Position at = here();
      ++i_;
      const int right = product(depth);
      left = add({c == '+' ? Op::add : Op::sub, left, right, -1, 0, 0, {}, at});
    }
  }
  int product(int depth) {
    int left = unary(depth);
    for (;;) {
      skip_spaces();
      const char c = peek();
      if ((c != '*' && c != '/') || (c == '*' && peek(1) == '*')) return left;
      const Position at = here();
      ++i_;
      const int right = unary(depth);
      left = add({c == '*' ? Op::mul : Op::div, left, right, -1, 0, 0, {}, at});
    }
  }
  int unary(int depth) {
    skip_spaces();
    const Position at = here();
    if (peek() == '-' || peek() == '+') deeper(depth + 1, at);
    if (peek() == '-') {
      ++i_;
      const int operand = unary(depth + 1);
      return add({Op::neg, operand, -1, -1, 0, 0, {}, at});
    }
    if (peek() == '+') {
      ++i_;
      return unary(depth + 1);
    }
    return power(depth);
  }
  int power(int depth) {
    const int base = atom(depth);
    skip_spaces();
    const bool caret = peek() == '^', stars = peek() == '*' && peek(1) == '*';
    if (!caret && !stars) return base;
    const Position at = here();
    i_ += stars ? 2 : 1;
    skip_spaces();
    bool negative = false;
    if (peek() == '-' || peek() == '+') {
      negative = peek() == '-';
      ++i_;
      skip_spaces();
    }
    const Position exponent_at = here();
    const std::size_t start = i_;
    while (digit(peek())) ++i_;
    if (start == i_ || peek() == '.' || peek() == 'e' || peek() == 'E' || name_start(peek()))
      throw FormulaError(exponent_at, "a power's exponent must be an integer (write exp(y·log(x)) "
                                      "for another)");
    int n = 0;
    const auto digits = text_.substr(start, i_ - start);
    const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), n);
    if (error != std::errc() || n > max_power)
      throw FormulaError(exponent_at, "a power's exponent is at most " + std::to_string(max_power) +
                                          " in size");
    skip_spaces();
    if (peek() == '^' || (peek() == '*' && peek(1) == '*'))
      throw FormulaError(here(), "a power of a power: write the parentheses, (x^a)^b");
    return add({Op::power, base, -1, -1, 0, negative ? -n : n, {}, at});
  }
  int atom(int depth) {
    skip_spaces();
    const Position at = here();
    const char c = peek();
    if (c == '(') {
      deeper(depth + 1, at);
      ++i_;
      const int inside = sum(depth + 1);
      skip_spaces();
      if (peek() != ')') throw FormulaError(here(), "expected ')' to close the '(' at column " +
                                                        std::to_string(at.column) + ", found " + found());
      ++i_;
      return inside;
    }
    if (digit(c) || (c == '.' && digit(peek(1)))) return number(at);
    if (name_start(c)) {
      std::string name = read_name();
      skip_spaces();
      if (peek() != '(') return add({Op::symbol, -1, -1, -1, 0, 0, std::move(name), at});
      return call(name, at, depth);
    }
    throw FormulaError(at, "expected a number, a name or '(', found " + found());
  }
  int number(Position at) {
    const std::size_t start = i_;
    while (digit(peek())) ++i_;
    if (peek() == '.') {
      ++i_;
      while (digit(peek())) ++i_;
    }
    if (peek() == 'e' || peek() == 'E') {
      ++i_;
      if (peek() == '+' || peek() == '-') ++i_;
      if (!digit(peek())) throw FormulaError(here(), "a number's exponent has no digits");
      while (digit(peek())) ++i_;
    }
    if (name_start(peek())) throw FormulaError(here(), "a name runs into a number (write '*')");
    double value = 0;
    const auto digits = text_.substr(start, i_ - start);
    const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
    if (error != std::errc() || !std::isfinite(value))
      throw FormulaError(at, "the number " + std::string(digits) + " is not a finite double");
    return add({Op::number, -1, -1, -1, value, 0, {}, at});
  }
  int call(const std::string& name, Position at, int depth) {
    deeper(depth + 1, at);
    const Function* f = nullptr;
    for (const auto& candidate : functions)
      if (candidate.name == name) f = &candidate;
    if (!f)
      throw FormulaError(at, "unknown function '" + name + "' (fma, sqrt, sin, cos, exp, log)");
    ++i_;  // '('
    int arguments[3] = {-1, -1, -1};
    int count = 0;
    for (;;) {
      skip_spaces();
      if (count == 0 && peek() == ')') break;
      const int argument = sum(depth + 1);
      if (count < 3) arguments[count] = argument;
      ++count;
      skip_spaces();
      if (peek() == ',') {
        ++i_;
        continue;
      }
      if (peek() == ')') break;
      throw FormulaError(here(), "expected ',' or ')' in " + name + "(…), found " + found());
    }
    ++i_;  // ')'
    if (count != f->arguments)
      throw FormulaError(at, name + " takes " + std::to_string(f->arguments) + " argument" +
                                 (f->arguments == 1 ? "" : "s") + ", not " + std::to_string(count));
    return add({f->op, arguments[0], arguments[1], arguments[2], 0, 0, {}, at});
  }

  std::string_view text_;
  std::size_t i_ = 0;
  Formulas f_;
};

int precedence(Op op) {
  switch (op) {
    case Op::add: case Op::sub: return 1;
    case Op::mul: case Op::div: return 2;
    case Op::neg: return 3;
    case Op::power: return 4;
    default: return 5;
  }
}

}  // namespace

Formulas parse_assignments(std::string_view text) { return Parser(text).assignments(); }
Formulas parse_expression(std::string_view text) { return Parser(text).expression(); }

std::string to_text(const Formulas& f, int i) {
  const Node& n = f.nodes.at(static_cast<std::size_t>(i));
  // an operand, parenthesized where it binds less tightly than its place needs
  const auto operand = [&](int j, int needed) {
    const std::string s = to_text(f, j);
    return precedence(f.nodes[static_cast<std::size_t>(j)].op) < needed ? std::string("(") + s + ")" : s;
  };
  switch (n.op) {
    case Op::number: return number_text(n.number);
    case Op::symbol: return n.name;
    case Op::neg: return std::string("-") + operand(n.a, 4);
    case Op::add: return operand(n.a, 1) + " + " + operand(n.b, 2);
    case Op::sub: return operand(n.a, 1) + " - " + operand(n.b, 2);
    case Op::mul: return operand(n.a, 2) + "*" + operand(n.b, 3);
    case Op::div: return operand(n.a, 2) + "/" + operand(n.b, 3);
    case Op::power: return operand(n.a, 5) + "^" + std::to_string(n.exponent);
    case Op::fma: return std::string("fma(") + to_text(f, n.a) + ", " + to_text(f, n.b) + ", " + to_text(f, n.c) + ")";
    default: break;
  }
  for (const auto& function : functions)
    if (function.op == n.op) return std::string(function.name) + "(" + to_text(f, n.a) + ")";
  return "?";
}

}  // namespace qmaps::formula
