// core/ops.hpp, every op: each lane of every ISA's batch (those compiled and supported here, each
// ISA's half compiled from tests/ops_isa.cpp.in with that ISA's flags alone; and xsimd::avx2, which
// takes the ops' fallback) against the scalar op on the same inputs, compared as bit patterns:
// random inputs (fixed seed) and special values (±0, subnormals, ±inf, NaNs, huge and tiny, values
// near 1 and near the log's and floor's thresholds).
#include <gtest/gtest.h>

#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "isas_run.hpp"
#include "ops_lanes.hpp"

namespace qmaps::testing::ops_lanes {

void PrintTo(Op op, std::ostream* os) { *os << op_names[static_cast<int>(op)]; }

namespace {

std::string hex(std::uint64_t bits) {
  char text[64];
  std::snprintf(text, sizeof text, "0x%016" PRIx64 " (%a)", bits, std::bit_cast<double>(bits));
  return text;
}
std::string hex(double x) { return hex(std::bit_cast<std::uint64_t>(x)); }

// The batch paths to test: every ISA compiled and supported here, and the fallback where an ISA's
// unit has it.
std::vector<Path> paths_to_run() {
  std::vector<Path> out;
  for (Isa isa : isas_to_run()) {
    std::array<Path, max_paths> p;
    std::size_t n = 0;
    switch (isa) {
#define QMAPS_OPS_CASE(name) \
  case Isa::name: n = paths_##name(p.data()); break;
      QMAPS_FOR_EACH_COMPILED_ISA(QMAPS_OPS_CASE)
#undef QMAPS_OPS_CASE
      default: break;
    }
    out.insert(out.end(), p.begin(), p.begin() + static_cast<std::ptrdiff_t>(n));
  }
  std::string ran;
  for (const Path& p : out) ran += std::string(ran.empty() ? "" : ", ") + p.name;
  std::cout << "[ ops paths ] " << ran << "\n";
  return out;
}

double bits_of(std::uint64_t b) { return std::bit_cast<double>(b); }

// ±0, subnormals, the normal range's ends, ±inf, quiet and signalling NaNs of either sign and with
// payloads, values near 1, log's thresholds (√½, 2^-1000), floor's (halves, 2^52).
std::vector<double> specials() {
  const double inf = std::numeric_limits<double>::infinity();
  const double max = std::numeric_limits<double>::max();
  std::vector<double> out = {
      0.0, -0.0, 0x1p-1074, -0x1p-1074, 0x1p-1060, 0x0.fffffffffffffp-1022,
      -0x0.fffffffffffffp-1022, 0x1p-1022, -0x1p-1022, 0x1.0000000000001p-1022, 0x1p-1000,
      std::nextafter(0x1p-1000, 0.0), 1e-300, -1e-300, max, -max, 1e300, -1e300, 0x1p1023,
      inf, -inf, bits_of(0x7ff8000000000000), bits_of(0xfff8000000000000),
      bits_of(0x7ff8000000000123), bits_of(0x7ff0000000000001), bits_of(0xfff4000000000000),
      1.0, -1.0, std::nextafter(1.0, 0.0), std::nextafter(1.0, 2.0), 1.0 + 1e-9, 1.0 - 1e-9,
      0.70710678118654752440, std::nextafter(0.70710678118654752440, 0.0),
      std::nextafter(0.70710678118654752440, 1.0), 1.4142135623730951, 0.5, -0.5, 2.0, 3.0,
      2.5, -2.5, 0x1p52, -0x1p52, 0x1p52 - 0.5, -(0x1p52 - 0.5), 0x1p53, 0x1p52 + 1.0, 1e-5,
      -7.25, 0.1};
  return out;
}

// Random bit patterns (every kind of value) and random magnitudes in [2^-64, 2^64) of either sign.
std::vector<double> randoms(std::mt19937_64& rng, std::size_t n) {
  std::vector<double> out;
  for (std::size_t i = 0; i < n; ++i) {
    if (i % 2 == 0) {
      out.push_back(std::bit_cast<double>(rng()));
    } else {
      const double unit = static_cast<double>(rng() >> 11) * 0x1p-53;
      const int exponent = static_cast<int>(rng() % 128) - 64;
      out.push_back((rng() & 1 ? -1.0 : 1.0) * std::ldexp(unit, exponent));
    }
  }
  return out;
}

bool two_nans_differ(double a, double b) {
  return std::isnan(a) && std::isnan(b) &&
         std::bit_cast<std::uint64_t>(a) != std::bit_cast<std::uint64_t>(b);
}
// An FMA whose NaN result's bits the compiler's choice of instruction decides, not the op: two
// NaN operands of different bits (which one passes on depends on the operand order encoded), and
// fms's NaN c (std::fma(a, b, −c) in the C library flips its sign, vfmsub keeps it).
bool nan_bits_unspecified(Op op, double a, double b, double c) {
  return two_nans_differ(a, b) || two_nans_differ(a, c) || two_nans_differ(b, c) ||
         (op == Op::fms && std::isnan(c));
}
// A signalling NaN, which no arithmetic makes: the floor GCC writes for x86-64 passes it on,
// roundpd quiets it.
bool signalling(double x) {
  return std::isnan(x) && !(std::bit_cast<std::uint64_t>(x) >> 51 & 1);
}

struct Inputs {
  std::vector<double> a, b, c, m;
  void add(double x, double y = 1.0, double z = 1.0) {
    a.push_back(x);
    b.push_back(y);
    c.push_back(z);
  }
};

// Each op's inputs: its domain's special values, combined in pairs or triples for the binary and
// ternary ops, and random ones; masks random; padded to a multiple of every lane count.
Inputs inputs_for(Op op) {
  std::mt19937_64 rng(20240611 + static_cast<unsigned>(op));
  const std::vector<double> s = specials();
  std::vector<double> values = s;
  for (double x : randoms(rng, 4096)) values.push_back(x);
  Inputs in;
  switch (op) {
    case Op::fma:
    case Op::fms:
      for (double x : s)
        for (double y : s)
          for (double z : s)
            if (!nan_bits_unspecified(op, x, y, z)) in.add(x, y, z);
      for (std::size_t i = 0; i + 2 < values.size(); i += 3)
        if (!nan_bits_unspecified(op, values[i], values[i + 1], values[i + 2]))
          in.add(values[i], values[i + 1], values[i + 2]);
      // c = ∓ the rounded a·b: a fused result is the product's rounding error, an unfused one 0.
      for (const double x : randoms(rng, 2048)) {
        const double y = std::bit_cast<double>(rng() >> 12 | 0x3ff0000000000000);
        if (std::isfinite(x * y)) in.add(x, y, op == Op::fma ? -(x * y) : x * y);
      }
      break;
    case Op::select:
    case Op::max:
    case Op::min:
      for (double x : s)
        for (double y : s) in.add(x, y);
      for (std::size_t i = 0; i + 1 < values.size(); i += 2) {
        in.add(values[i], values[i + 1]);
        in.add(values[i], values[i]);
        in.add(values[i], -values[i]);
      }
      break;
    case Op::split_mantissa:
    case Op::split_exponent:  // documented for positive normal values
      for (double x : values)
        if (std::isnormal(x) && x > 0) in.add(x);
      for (int e = -1022; e <= 1023; ++e) {
        in.add(std::ldexp(1.0, e));
        if (e > -1022) in.add(std::nextafter(std::ldexp(1.0, e), 0.0));
      }
      break;
    case Op::integer_lanes:  // documented for integers in [0, 2^52)
      for (double x : {0.0, -0.0, 1.0, 2.0, 0x1p32, 0x1p51, 0x1p52 - 1.0, 0x1p52 - 2.0})
        in.add(x);
      for (int i = 0; i < 4096; ++i) in.add(static_cast<double>(rng() >> (12 + i % 40)));
      break;
    case Op::floor:
      for (double x : values)
        if (!signalling(x)) in.add(x);
      for (int k = -8; k <= 8; ++k) {  // integers and the values next to them
        in.add(std::nextafter(static_cast<double>(k), -9.0));
        in.add(static_cast<double>(k));
        in.add(std::nextafter(static_cast<double>(k), 9.0));
      }
      break;
    case Op::log:
      for (double x : values) in.add(x);
      for (int k = 1; k <= 64; ++k) {  // 1 ± k ulp, 1 ± 2^-k
        in.add(1.0 + k * 0x1p-52);
        in.add(1.0 - k * 0x1p-53);
        in.add(1.0 + std::ldexp(1.0, -k));
        in.add(1.0 - std::ldexp(1.0, -k - 1));
      }
      break;
    default:
      for (double x : values) in.add(x);
      break;
  }
  for (std::size_t k = 0; in.a.size() % 8 != 0; ++k) in.add(in.a[k], in.b[k], in.c[k]);
  for (std::size_t i = 0; i < in.a.size(); ++i) in.m.push_back(static_cast<double>(rng() & 1));
  return in;
}

class LaneOps : public ::testing::TestWithParam<Op> {};

TEST_P(LaneOps, EveryLaneOfEveryBatchHasTheBitsOfTheScalarOp) {
  const Op op = GetParam();
  const char* name = op_names[static_cast<int>(op)];
  const Inputs in = inputs_for(op);
  const std::size_t n = in.a.size();
  std::vector<std::uint64_t> scalar(n);
  lane_op<double>(op, n, in.a.data(), in.b.data(), in.c.data(), in.m.data(), scalar.data());

  const std::vector<Path> paths = paths_to_run();
  ASSERT_FALSE(paths.empty());
  for (const Path& path : paths) {
    std::vector<std::uint64_t> batch(n);
    path.lane_op(op, n, in.a.data(), in.b.data(), in.c.data(), in.m.data(), batch.data());
    std::size_t differ = 0;
    for (std::size_t i = 0; i < n; ++i) {
      if (batch[i] == scalar[i]) continue;
      if (++differ <= 8)
        ADD_FAILURE() << "ISA " << path.name << ", op " << name << ", lane " << i % path.lanes
                      << " (input " << i << ": a " << hex(in.a[i]) << ", b " << hex(in.b[i])
                      << ", c " << hex(in.c[i]) << ", mask " << in.m[i] << "): batch "
                      << hex(batch[i]) << " vs scalar " << hex(scalar[i]);
    }
    EXPECT_EQ(differ, 0u) << "ISA " << path.name << ", op " << name << ": lanes that differ, of "
                          << n;
  }
}

INSTANTIATE_TEST_SUITE_P(
    Ops, LaneOps,
    ::testing::Values(Op::fma, Op::fms, Op::neg, Op::sqrt, Op::abs, Op::floor, Op::split_mantissa,
                      Op::split_exponent, Op::log, Op::select, Op::max, Op::min, Op::square,
                      Op::load_store, Op::lanes_of, Op::lanes_of_mask, Op::negate,
                      Op::integer_lanes),
    [](const auto& info) { return std::string(op_names[static_cast<int>(info.param)]); });

// any, all, bits and compress of every mask pattern of a batch, against the scalar ops lane by
// lane; compress writes within a batch's room.
TEST(OpsMasks, EveryMaskPatternGivesTheScalarOpsLaneByLane) {
  std::mt19937_64 rng(7);
  std::vector<double> values = specials();
  for (double x : randoms(rng, 64)) values.push_back(x);
  const std::vector<Path> paths = paths_to_run();
  ASSERT_FALSE(paths.empty());
  for (const Path& path : paths) {
    const std::size_t lanes = path.lanes;
    for (std::size_t first = 0; first + lanes <= values.size(); first += lanes) {
      const double* v = values.data() + first;
      for (std::uint64_t pattern = 0; pattern < (std::uint64_t{1} << lanes); ++pattern) {
        MaskOps batch;
        path.mask_ops(pattern, v, batch);
        bool any = false, all = true;
        std::uint64_t bits = 0;
        std::array<double, 8> packed;
        std::size_t count = 0;
        for (std::size_t l = 0; l < lanes; ++l) {
          const bool m = pattern >> l & 1;
          any = any || ops::any(m);
          all = all && ops::all(m);
          bits |= ops::bits(m) << l;
          count += ops::compress(&packed[count], m, v[l]);
        }
        const std::string where = std::string("ISA ") + path.name + ", mask pattern " +
                                  std::to_string(pattern) + ", values from " +
                                  std::to_string(first);
        EXPECT_EQ(batch.any, any) << where << ": any";
        EXPECT_EQ(batch.all, all) << where << ": all";
        EXPECT_EQ(batch.bits, bits) << where << ": bits";
        ASSERT_EQ(batch.count, count) << where << ": compress's count";
        for (std::size_t l = 0; l < count; ++l)
          EXPECT_EQ(hex(batch.stored[l]), hex(packed[l]))
              << where << ": compress, lane " << l << " (batch vs scalar)";
        for (std::size_t l = lanes; l < batch.stored.size(); ++l)
          EXPECT_EQ(hex(batch.stored[l]), hex(guard)) << where << ": compress wrote past a batch";
      }
    }
  }
}

TEST(OpsLaneIndex, LaneLOfEveryBatchIsL) {
  const std::vector<Path> paths = paths_to_run();
  ASSERT_FALSE(paths.empty());
  for (const Path& path : paths) {
    std::array<double, 8> index;
    path.lane_index(index.data());
    for (std::size_t l = 0; l < path.lanes; ++l) {
      const double scalar = ops::lane_index<double>() + static_cast<double>(l);
      EXPECT_EQ(hex(index[l]), hex(scalar)) << "ISA " << path.name << ", lane " << l;
    }
  }
}

}  // namespace
}  // namespace qmaps::testing::ops_lanes
