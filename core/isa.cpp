#include "core/isa.hpp"

#include <array>

#include "core/error.hpp"

namespace qmaps {
namespace {

constexpr std::array kAllSimd = {
#ifdef QMAPS_HAVE_SSE2
    Isa::sse2,
#endif
#ifdef QMAPS_HAVE_AVX2
    Isa::avx2,
#endif
#ifdef QMAPS_HAVE_AVX512
    Isa::avx512,
#endif
};

}  // namespace

std::string_view isa_name(Isa isa) {
  switch (isa) {
    case Isa::scalar: return "scalar";
    case Isa::sse2: return "sse2";
    case Isa::avx2: return "avx2";
    case Isa::avx512: return "avx512";
  }
  return "?";
}

std::size_t isa_lanes(Isa isa) {
  switch (isa) {
    case Isa::scalar: return 1;
    case Isa::sse2: return 2;
    case Isa::avx2: return 4;
    case Isa::avx512: return 8;
  }
  return 1;
}

Isa parse_isa(std::string_view name) {
  for (Isa isa : {Isa::scalar, Isa::sse2, Isa::avx2, Isa::avx512})
    if (isa_name(isa) == name) return isa;
  throw usage_error("unknown SIMD instruction set '" + std::string(name) +
                    "' (expected auto, scalar, sse2, avx2 or avx512)");
}

std::span<const Isa> compiled_isas() { return kAllSimd; }

bool cpu_supports(Isa isa) {
  __builtin_cpu_init();
  switch (isa) {
    case Isa::scalar: return true;
    case Isa::sse2: return __builtin_cpu_supports("sse2");
    case Isa::avx2: return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
    case Isa::avx512: return __builtin_cpu_supports("avx512f");
  }
  return false;
}

Isa best_isa() {
  Isa best = Isa::scalar;
  for (Isa isa : compiled_isas())
    if (cpu_supports(isa)) best = isa;
  return best;
}

std::vector<Isa> runnable_isas() {
  std::vector<Isa> out;
  for (Isa isa : compiled_isas())
    if (cpu_supports(isa)) out.push_back(isa);
  return out;
}

Isa resolve_isa(std::string_view request) {
  if (request == "auto") return best_isa();
  const Isa isa = parse_isa(request);
  if (isa == Isa::scalar) return isa;
  bool compiled = false;
  for (Isa c : compiled_isas()) compiled = compiled || c == isa;
  if (!compiled)
    throw Error(ExitCode::unsupported,
                "--simd=" + std::string(request) + ": this qmaps binary was built without it");
  if (!cpu_supports(isa))
    throw Error(ExitCode::unsupported,
                "--simd=" + std::string(request) + ": this CPU does not support it (best here: " +
                    std::string(isa_name(best_isa())) + ")");
  return isa;
}

}  // namespace qmaps
