// The formulas (kernels/formula/): the parser's trees and its errors' positions, the lowering's
// shared subexpressions, folded constants and refusals, its chained results, the program over
// double and over a batch (the same bytes), and the functions against long double.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <random>
#include <string>
#include <vector>

#include "core/dual.hpp"
#include "core/ops_exp.hpp"
#include "kernels/formula/evaluate.hpp"
#include "kernels/formula/expression.hpp"
#include "kernels/formula/program.hpp"

namespace qmaps::formula {
namespace {

using Parameters = std::vector<std::pair<std::string, double>>;

// The error of parsing and lowering `text` over inputs x, y with parameters a = 2, zero = 0.
std::string error_of(const std::string& text) {
  try {
    const Formulas f = parse_assignments(text);
    Lowering lowering(f, {"x", "y"}, Parameters{{"a", 2.0}, {"zero", 0.0}});
    lowering.assign_all();
  } catch (const FormulaError& e) {
    return e.what();
  }
  return "";
}

// The program of `text`'s assignments over x, y whose outputs are x, y.
Program program_of(const std::string& text, const Parameters& parameters = {{"a", 2.0}}) {
  const Formulas f = parse_assignments(text);
  Lowering lowering(f, {"x", "y"}, parameters);
  lowering.assign_all();
  return lowering.finish({lowering.value_of("x", {}), lowering.value_of("y", {})});
}

std::vector<double> run_double(const Program& p, double x, double y) {
  std::vector<double> r(p.registers());
  r[0] = x;
  r[1] = y;
  load_constants(p, r.data(), 1);
  run<double, 1>(p, r.data());
  return {r[p.outputs[0]], r[p.outputs[1]]};
}

TEST(FormulaParser, PrecedenceAndAssociativityFollowTheGrammar) {
  const auto text_of = [](const std::string& e) {
    const Formulas f = parse_expression(e);
    return to_text(f, f.assignments[0].root);
  };
  EXPECT_EQ(text_of("a - b - c"), "a - b - c");
  EXPECT_EQ(text_of("a - (b - c)"), "a - (b - c)");
  EXPECT_EQ(text_of("a / b / c"), "a/b/c");
  EXPECT_EQ(text_of("a / (b * c)"), "a/(b*c)");
  EXPECT_EQ(text_of("-x^2"), "-x^2");
  EXPECT_EQ(text_of("(-x)^2"), "(-x)^2");
  EXPECT_EQ(text_of("x**-3"), "x^-3");
  EXPECT_EQ(text_of("2*x + 3*y^4/z"), "2*x + 3*y^4/z");
  EXPECT_EQ(text_of("fma(a, b, -c) + sqrt(s)"), "fma(a, b, -c) + sqrt(s)");
  EXPECT_EQ(text_of("1.5e-3 * .25"), "0.0015*0.25");
  EXPECT_EQ(text_of("+ - + x"), "-x");
}

TEST(FormulaParser, AssignmentsAreLinesOrSemicolonsWithComments) {
  const Formulas f = parse_assignments("# a kick\n  p = p - h*q^3   # the force\n\nq = q + h*p; r = q\n");
  ASSERT_EQ(f.assignments.size(), 3u);
  EXPECT_EQ(f.assignments[0].name, "p");
  EXPECT_EQ(f.assignments[0].at.line, 2);
  EXPECT_EQ(f.assignments[0].at.column, 3);
  EXPECT_EQ(f.assignments[2].name, "r");
  EXPECT_EQ(f.assignments[2].at.column, 14);
}

TEST(FormulaParser, ErrorsNameTheLineAndColumn) {
  EXPECT_EQ(error_of("x = a*(y + 1"), "line 1, column 13: expected ')' to close the '(' at column 7, found the end");
  EXPECT_EQ(error_of("x = y\ny = x +* 2"), "line 2, column 8: expected a number, a name or '(', found '*'");
  EXPECT_EQ(error_of("x = y 2"), "line 1, column 7: unexpected '2' after the expression");
  EXPECT_EQ(error_of("x = 2y"), "line 1, column 6: a name runs into a number (write '*')");
  EXPECT_EQ(error_of("x = tan(y)"), "line 1, column 5: unknown function 'tan' (fma, sqrt, sin, cos, exp, log)");
  EXPECT_EQ(error_of("x = fma(y, y)"), "line 1, column 5: fma takes 3 arguments, not 2");
  EXPECT_EQ(error_of("x = y^1.5"), "line 1, column 7: a power's exponent must be an integer (write exp(y·log(x)) for another)");
  EXPECT_EQ(error_of("x = y^2^3"), "line 1, column 8: a power of a power: write the parentheses, (x^a)^b");
  EXPECT_EQ(error_of("x = y^65"), "line 1, column 7: a power's exponent is at most 64 in size");
  EXPECT_EQ(error_of("x = 1e400"), "line 1, column 5: the number 1e400 is not a finite double");
  EXPECT_EQ(error_of("= y"), "line 1, column 1: expected a name to assign, found '='");
  EXPECT_EQ(error_of("x y"), "line 1, column 3: expected '=' after 'x', found 'y'");
  EXPECT_EQ(error_of("   \n # nothing\n"), "line 3, column 1: no assignment");
  EXPECT_EQ(error_of("x = y\t\x01"), "line 1, column 7: a character that is not printable ASCII");
}

TEST(FormulaParser, LimitsAreStatedAndEnforced) {
  EXPECT_EQ(error_of("x = " + std::string(65, '(') + "y" + std::string(65, ')')),
            "line 1, column 69: nested more than 64 deep");
  EXPECT_EQ(error_of("x = " + std::string(64, '(') + "y" + std::string(64, ')')), "");
  EXPECT_EQ(error_of("x = " + std::string(63, '(') + "sqrt(y" + std::string(64, ')')), "");
  EXPECT_EQ(error_of("x = " + std::string(64, '(') + "sqrt(y" + std::string(65, ')')),
            "line 1, column 69: nested more than 64 deep");
  EXPECT_EQ(error_of("x = " + std::string(70, '-') + "y"), "line 1, column 69: nested more than 64 deep");
  EXPECT_EQ(error_of("x = y" + std::string(max_text, ' ')),
            "line 1, column 1: the formulas are 16389 characters long; at most 16384");
  std::string many;
  for (std::size_t k = 0; k <= max_assignments; ++k) many += "x = y\n";
  EXPECT_EQ(error_of(many), "line 257, column 1: more than 256 assignments");
  std::string wide;  // 256 × 17 values, none shared: x changes on every line
  for (int k = 0; k < 256; ++k) wide += "x = x*x*x*x*x*x*x*x*x*x*x*x*x*x*x*x*x + y\n";
  EXPECT_EQ(error_of(wide), "line 241, column 34: the formulas need more than 4096 values");
}

TEST(FormulaLowering, SymbolsAndParametersAreCheckedWhereWritten) {
  EXPECT_EQ(error_of("x = y + b"), "line 1, column 9: unknown symbol 'b' (known here: x, y, a, zero)");
  EXPECT_EQ(error_of("a = x"), "line 1, column 1: 'a' is a parameter; it cannot be assigned");
  EXPECT_EQ(error_of("x = y / zero"), "line 1, column 7: a division by zero: the parameters make the divisor 0");
  EXPECT_EQ(error_of("x = y / (a - 2)"), "line 1, column 7: a division by zero: the parameters make the divisor 0");
  EXPECT_EQ(error_of("x = y * log(zero)"), "line 1, column 9: the parameters make this value -inf");
  EXPECT_EQ(error_of("t = y\nx = t + u"), "line 2, column 9: unknown symbol 'u' (known here: x, y, a, zero)");
  EXPECT_EQ(error_of("x = y / zero^0"), "");  // zero^0 = 1
}

TEST(FormulaLowering, SharesSubexpressionsFoldsConstantsAndDropsTheUnneeded) {
  // x·y and y·x are one product; a² + 1 is a constant; t is never needed
  const Program p = program_of("t = sin(x)\nx = x*y + y*x*(a^2 + 1)\ny = y^5");
  EXPECT_EQ(p.inputs, 2u);
  EXPECT_EQ(p.constants, std::vector<double>{5.0});
  // x·y, (x·y)·5, their sum; y², y⁴, y⁴·y
  ASSERT_EQ(p.code.size(), 6u);
  EXPECT_EQ(p.code[0].code, Code::mul);
  const auto out = run_double(p, 3.0, 2.0);
  EXPECT_EQ(out[0], 6.0 + 30.0);
  EXPECT_EQ(out[1], 32.0);
  // a negative power is the reciprocal of the positive one; x^0 is 1
  const Program q = program_of("x = x^-2\ny = y^0");
  EXPECT_EQ(run_double(q, 4.0, 7.0), (std::vector<double>{1.0 / 16.0, 1.0}));
}

TEST(FormulaLowering, KeepsTheRoundingsAsWritten) {
  // a·b + c rounds twice, fma(a, b, c) once: 1 + 2^-52 squared minus its rounded square
  const double e = 1 + 0x1p-52;
  const Program two = program_of("x = x*x - y");
  const Program one = program_of("x = fma(x, x, -y)");
  const double rounded = e * e;
  EXPECT_EQ(run_double(two, e, rounded)[0], 0.0);
  EXPECT_EQ(run_double(one, e, rounded)[0], 0x1p-104);
}

// The equations e1 = 0, e2 = 0 of `text` over q, r (known) and unknowns u, v, solved: u, v and
// the determinant at (q, r), with parameters a = 2, h = 0.1.
std::vector<double> solved(const std::string& text, double q, double r) {
  const Formulas f = parse_assignments(text);
  Lowering lowering(f, {"q", "r", "u", "v"}, Parameters{{"a", 2.0}, {"h", 0.1}});
  lowering.assign_all();
  std::uint16_t determinant = 0;
  const auto u = lowering.solve_linear({lowering.value_of("e1", {}), lowering.value_of("e2", {})},
                                       {lowering.value_of("u", {}), lowering.value_of("v", {})},
                                       "q_{n+1}", {1, 1}, determinant);
  const Program p = lowering.finish({u[0], u[1], determinant});
  std::vector<double> regs(p.registers(), 0.0);
  regs[0] = q;
  regs[1] = r;
  load_constants(p, regs.data(), 1);
  run<double, 1>(p, regs.data());
  return {regs[p.outputs[0]], regs[p.outputs[1]], regs[p.outputs[2]]};
}

std::string solve_error(const std::string& text) {
  try {
    solved(text, 0.3, -0.2);
  } catch (const FormulaError& e) {
    return e.what();
  }
  return "";
}

TEST(FormulaLowering, SolvesEquationsLinearInTheUnknowns) {
  // a Kahan-like pair: linear in (u, v) with coefficients that depend on q and r
  const std::string kahan =
      "k = 1 + a*h^2*(q^2 + r^2)\n"
      "e1 = (u - 2*q + r)/h^2 + a*q*(u + r)/k - q*v\n"
      "e2 = fma(q, u, v) - (2*r - q)*sin(q)/k";
  for (const auto& [q, r] : {std::pair{0.3, -0.2}, std::pair{-1.1, 0.7}, std::pair{2.0, 0.01}}) {
    const auto x = solved(kahan, q, r);
    const double k = 1 + 2.0 * 0.01 * (q * q + r * r);
    const double e1 = (x[0] - 2 * q + r) / 0.01 + 2.0 * q * (x[0] + r) / k - q * x[1];
    const double e2 = q * x[0] + x[1] - (2 * r - q) * std::sin(q) / k;
    EXPECT_LT(std::fabs(e1), 1e-10) << q << ", " << r;
    EXPECT_LT(std::fabs(e2), 1e-12) << q << ", " << r;
    EXPECT_NE(x[2], 0.0);
  }
  // a determinant that vanishes at some states only: that state's own fault, not an error
  const auto at_zero = solved("e1 = q*u + v - 1\ne2 = u + v/q", 1.0, 0.0);  // det = q·(1/q) − 1
  EXPECT_EQ(at_zero[2], 0.0);
}

TEST(FormulaLowering, RefusesEquationsThatAreNotLinearWhereTheyStopBeing) {
  EXPECT_EQ(solve_error("e1 = u*v - q\ne2 = u"), "line 1, column 7: not linear in q_{n+1}");
  EXPECT_EQ(solve_error("e1 = u - q\ne2 = sin(v)"), "line 2, column 6: not linear in q_{n+1}");
  EXPECT_EQ(solve_error("e1 = q/(u + 1)\ne2 = v"), "line 1, column 7: not linear in q_{n+1}");
  EXPECT_EQ(solve_error("e1 = u^2\ne2 = v"), "line 1, column 7: not linear in q_{n+1}");
  EXPECT_EQ(solve_error("e1 = u + v - q\ne2 = a*u + 2*v"),
            "line 1, column 1: the equations for q_{n+1} are singular whatever the state");
}

TEST(FormulaEvaluation, EveryLaneOfABatchIsTheDoublePath) {
  using V = xsimd::batch<double>;
  constexpr std::size_t W = V::size, lanes = 3;
  const Program p = program_of(
      "r = sqrt(x^2 + y^2)\nx = exp(-r) * cos(a*x) + log(1 + r^2)/(1 + y^4)\ny = fma(x, sin(y), r)");
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-3, 3);
  std::vector<V> r(p.registers() * lanes);
  alignas(64) double xs[lanes][W], ys[lanes][W];
  for (std::size_t l = 0; l < lanes; ++l) {
    for (std::size_t w = 0; w < W; ++w) {
      xs[l][w] = u(rng);
      ys[l][w] = u(rng);
    }
    r[0 * lanes + l] = V::load_aligned(xs[l]);
    r[1 * lanes + l] = V::load_aligned(ys[l]);
  }
  load_constants(p, r.data(), lanes);
  run<V, lanes>(p, r.data());
  for (std::size_t l = 0; l < lanes; ++l) {
    alignas(64) double x_out[W], y_out[W];
    r[p.outputs[0] * lanes + l].store_aligned(x_out);
    r[p.outputs[1] * lanes + l].store_aligned(y_out);
    for (std::size_t w = 0; w < W; ++w) {
      const auto expected = run_double(p, xs[l][w], ys[l][w]);
      EXPECT_EQ(std::bit_cast<std::uint64_t>(x_out[w]), std::bit_cast<std::uint64_t>(expected[0]));
      EXPECT_EQ(std::bit_cast<std::uint64_t>(y_out[w]), std::bit_cast<std::uint64_t>(expected[1]));
    }
  }
}

TEST(FormulaLowering, ChainsEachResultToTheNextInstructionAndStoresOnlyWhatIsReadAgain) {
  // Suris' step as its kernel writes it: fma(…, −x1) is one fms; of its 8 results only 1/(1 + g n)
  // (read twice) and the two outputs are stored, the rest passed to the next instruction
  const Formulas f = parse_assignments(
      "n = fma(y1, y1, y2*y2)\ninv = 1/fma(g, n, 1)\nz1 = fma(2*(1 - A*h^2)*y1, inv, -x1)\n"
      "z2 = fma(2*(1 - B*h^2)*y2, inv, -x2)");
  Lowering lowering(f, {"x1", "x2", "y1", "y2"},
                    Parameters{{"A", 0.7}, {"B", 0.3}, {"g", 0.018}, {"h", 0.1}});
  lowering.assign_all();
  const Program p = lowering.finish({lowering.value_of("z1", {}), lowering.value_of("z2", {})});
  ASSERT_EQ(p.code.size(), 8u);
  int stored = 0, fms = 0;
  for (const Instruction& i : p.code) {
    stored += i.stored;
    fms += i.code == Code::fms;
  }
  EXPECT_EQ(stored, 3);
  EXPECT_EQ(fms, 2);
  EXPECT_EQ(p.code[0].chained, Chained::none);
  EXPECT_EQ(p.code[1].chained, Chained::c);  // fma(y1, y1, y2·y2)
}

TEST(FormulaEvaluation, ChainedResultsGiveTheBytesOfResultsAllStored) {
  // every operand read from its register and every result written: the same bytes, in the lanes
  // of a batch and over double, for programs with chains of every kind
  using V = xsimd::batch<double>;
  constexpr std::size_t W = V::size, lanes = 4;
  for (const char* text : {"t = x*y\nx = t*t - x/t\ny = fma(y, t, t) + sqrt(t*t)",
                           "x = fma(x, y, -(x - y)/(y*y + 1))\ny = exp(x)*y - (y - x*x)",
                           "t = -(x*x)\nx = t/(1 + t*t)\ny = (y - t) - (t - y)*(x + t)"}) {
    const Program chained = program_of(text);
    Program plain = chained;
    for (Instruction& i : plain.code) {
      i.chained = Chained::none;
      i.stored = true;
    }
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(-2, 2);
    std::vector<V> a(chained.registers() * lanes), b(plain.registers() * lanes);
    for (std::size_t l = 0; l < lanes; ++l) {
      alignas(64) double xs[W], ys[W];
      for (std::size_t w = 0; w < W; ++w) {
        xs[w] = u(rng);
        ys[w] = u(rng);
      }
      a[l] = b[l] = V::load_aligned(xs);
      a[lanes + l] = b[lanes + l] = V::load_aligned(ys);
    }
    load_constants(chained, a.data(), lanes);
    load_constants(plain, b.data(), lanes);
    run<V, lanes>(chained, a.data());
    run<V, lanes>(plain, b.data());
    for (const std::uint16_t o : chained.outputs)
      for (std::size_t l = 0; l < lanes; ++l) {
        alignas(64) double x[W], y[W];
        a[o * lanes + l].store_aligned(x);
        b[o * lanes + l].store_aligned(y);
        for (std::size_t w = 0; w < W; ++w)
          EXPECT_EQ(std::bit_cast<std::uint64_t>(x[w]), std::bit_cast<std::uint64_t>(y[w])) << text;
      }
    int kept = 0;
    for (const Instruction& i : chained.code) kept += i.stored;
    EXPECT_LT(kept, static_cast<int>(chained.code.size())) << text;
  }
}

// The program in long double with the C library's functions: the reference for differences.
std::vector<long double> run_long_double(const Program& p, long double x, long double y) {
  std::vector<long double> r(p.registers());
  r[0] = x;
  r[1] = y;
  for (std::size_t k = 0; k < p.constants.size(); ++k) r[p.inputs + k] = p.constants[k];
  for (const Instruction& i : p.code) {
    const long double a = r[i.a], b = r[i.b], c = r[i.c];
    long double v = 0;
    switch (i.code) {
      case Code::add: v = a + b; break;
      case Code::sub: v = a - b; break;
      case Code::mul: v = a * b; break;
      case Code::div: v = a / b; break;
      case Code::neg: v = -a; break;
      case Code::fma: v = a * b + c; break;
      case Code::fms: v = a * b - c; break;
      case Code::sqrt: v = std::sqrt(a); break;
      case Code::sin: v = std::sin(a); break;
      case Code::cos: v = std::cos(a); break;
      case Code::exp: v = std::exp(a); break;
      case Code::log: v = std::log(a); break;
    }
    r[i.out] = v;
  }
  return {r[p.outputs[0]], r[p.outputs[1]]};
}

TEST(FormulaEvaluation, DualsGiveTheJacobianOfCentralDifferences) {
  // the independent reference: central differences of the long double program, step 1e-6
  constexpr double tangent_vs_central_difference = 1e-8;  // relative to the Jacobian's norm
  const Program p = program_of(
      "r = sqrt(x^2 + y^2)\nx = exp(-r) * cos(a*x) + log(1 + r^2)/(1 + y^4)\ny = fma(x, sin(y), r)");
  using D = Dual<double, 2>;
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-2, 2);
  for (int trial = 0; trial < 100; ++trial) {
    const double x = u(rng), y = u(rng);
    std::vector<D> r(p.registers());
    r[0] = D(x, {1.0, 0.0});
    r[1] = D(y, {0.0, 1.0});
    load_constants(p, r.data(), 1);
    run<D, 1>(p, r.data());
    const D out[2] = {r[p.outputs[0]], r[p.outputs[1]]};
    // the values are the plain program's, bit for bit
    const auto plain = run_double(p, x, y);
    EXPECT_EQ(std::bit_cast<std::uint64_t>(out[0].v), std::bit_cast<std::uint64_t>(plain[0]));
    EXPECT_EQ(std::bit_cast<std::uint64_t>(out[1].v), std::bit_cast<std::uint64_t>(plain[1]));
    const long double h = 1e-6L;
    long double jacobian[2][2], norm = 0;
    for (int j = 0; j < 2; ++j) {
      const auto up = run_long_double(p, x + (j == 0 ? h : 0), y + (j == 1 ? h : 0));
      const auto down = run_long_double(p, x - (j == 0 ? h : 0), y - (j == 1 ? h : 0));
      for (int i = 0; i < 2; ++i) {
        jacobian[i][j] = (up[i] - down[i]) / (2 * h);
        norm = std::max(norm, std::fabs(jacobian[i][j]));
      }
    }
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j)
        EXPECT_LT(std::fabs(out[i].d[j] - jacobian[i][j]), tangent_vs_central_difference * norm)
            << "d out" << i << "/d in" << j << " at (" << x << ", " << y << ")";
  }
}

// ulps between a double and a long double reference
double ulps(double got, long double exact) {
  const double nearest = static_cast<double>(exact);
  const double ulp = std::nextafter(std::fabs(nearest), INFINITY) - std::fabs(nearest);
  return static_cast<double>(std::fabs(static_cast<long double>(got) - exact) / ulp);
}

TEST(FormulaFunctions, ExpIsWithinOneUlpOfLongDouble) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> wide(-708, 709), narrow(-1, 1);
  double worst = 0;
  for (int k = 0; k < 200000; ++k) {
    const double x = k % 2 ? wide(rng) : narrow(rng);
    worst = std::max(worst, ulps(ops::exp(x), std::exp(static_cast<long double>(x))));
  }
  EXPECT_LT(worst, 1.0) << "exp's worst error against long double: " << worst << " ulp";
  EXPECT_EQ(ops::exp(0.0), 1.0);
  EXPECT_EQ(ops::exp(710.0), INFINITY);
  EXPECT_EQ(ops::exp(INFINITY), INFINITY);
  EXPECT_EQ(ops::exp(-INFINITY), 0.0);
  EXPECT_EQ(ops::exp(-746.0), 0.0);
  EXPECT_GT(ops::exp(-744.0), 0.0);  // subnormal
  EXPECT_TRUE(std::isnan(ops::exp(NAN)));
  for (const double x : {709.7, -708.3, 1e-300, -1e-17})
    EXPECT_LT(ulps(ops::exp(x), std::exp(static_cast<long double>(x))), 1.0) << x;
}

}  // namespace
}  // namespace qmaps::formula

namespace qmaps::formula {
namespace {

TEST(FormulaFunctions, SinCosAndLogAreWithinTheirStatedUlpsOfLongDouble) {
  // The stated accuracy (docs/formulas.md): measured over random points of each range.
  constexpr double sin_cos_bound = 2.5, log_bound = 2.0;
  std::mt19937_64 rng(12);
  std::uniform_real_distribution<double> angle(-0x1p20, 0x1p20), small(-4, 4), mantissa(1, 2);
  std::uniform_int_distribution<int> binade(-500, 500);
  double worst_sin = 0, worst_cos = 0, worst_log = 0;
  for (int k = 0; k < 200000; ++k) {
    const double x = k % 2 ? angle(rng) : small(rng);
    double s, c;
    sin_cos_within(x, s, c);
    worst_sin = std::max(worst_sin, ulps(s, std::sin(static_cast<long double>(x))));
    worst_cos = std::max(worst_cos, ulps(c, std::cos(static_cast<long double>(x))));
    const double y = std::ldexp(mantissa(rng), binade(rng));
    worst_log = std::max(worst_log, ulps(ops::log(y), std::log(static_cast<long double>(y))));
  }
  std::cout << "worst ulps against long double: sin " << worst_sin << ", cos " << worst_cos
            << ", log " << worst_log << "\n";
  EXPECT_LT(worst_sin, sin_cos_bound);
  EXPECT_LT(worst_cos, sin_cos_bound);
  EXPECT_LT(worst_log, log_bound);
  // beyond the reduction's range: NaN, the orbit's escape
  double s, c;
  sin_cos_within(0x1p20 * 1.5, s, c);
  EXPECT_TRUE(std::isnan(s) && std::isnan(c));
  sin_cos_within(0x1p20, s, c);
  EXPECT_FALSE(std::isnan(s) || std::isnan(c));
}

}  // namespace
}  // namespace qmaps::formula
