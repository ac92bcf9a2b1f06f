#include "core/isa.hpp"

#include <array>

#include "core/compiled_isas.hpp"
#include "core/error.hpp"

namespace qmaps {
namespace {

struct IsaFacts {
  Isa isa;
  std::string_view name;
  std::size_t lanes;
};

#define QMAPS_ISA_FACTS(name, arch, lanes, ...) IsaFacts{Isa::name, #name, lanes},
constexpr std::array kFacts = {IsaFacts{Isa::scalar, "scalar", 1},
                               QMAPS_FOR_EACH_ISA(QMAPS_ISA_FACTS)};
#undef QMAPS_ISA_FACTS

#define QMAPS_ISA_VALUE(name, ...) Isa::name,
constexpr std::array kAll = {QMAPS_FOR_EACH_ISA(QMAPS_ISA_VALUE)};
#undef QMAPS_ISA_VALUE

#define QMAPS_COMPILED_VALUE(name) Isa::name,
constexpr Isa kCompiled[] = {QMAPS_FOR_EACH_COMPILED_ISA(QMAPS_COMPILED_VALUE) Isa::scalar};
#undef QMAPS_COMPILED_VALUE

const IsaFacts& facts(Isa isa) { return kFacts[static_cast<std::size_t>(isa)]; }

}  // namespace

std::string_view isa_name(Isa isa) { return facts(isa).name; }
std::size_t isa_lanes(Isa isa) { return facts(isa).lanes; }

Isa parse_isa(std::string_view name) {
  std::string known = "auto";
  for (const auto& f : kFacts) {
    if (f.name == name) return f.isa;
    known += (&f == &kFacts.back() ? " or " : ", ") + std::string(f.name);
  }
  throw usage_error("unknown SIMD instruction set '" + std::string(name) + "' (expected " +
                    known + ")");
}

std::span<const Isa> all_isas() { return kAll; }

// The last element of kCompiled is a sentinel (an array may not be empty).
std::span<const Isa> compiled_isas() { return std::span(kCompiled).first(std::size(kCompiled) - 1); }
std::string_view kernel_flags() { return QMAPS_COMPILED_KERNEL_FLAGS; }

bool cpu_supports(Isa isa) {
  __builtin_cpu_init();
  switch (isa) {
    case Isa::scalar: return true;
#define QMAPS_ISA_SUPPORTED(name, arch, lanes, supported, ...) \
  case Isa::name: return supported;
    QMAPS_FOR_EACH_ISA(QMAPS_ISA_SUPPORTED)
#undef QMAPS_ISA_SUPPORTED
  }
  return false;
}

Isa best_isa() {
  Isa best = Isa::scalar;
  for (Isa isa : compiled_isas())
    if (cpu_supports(isa)) best = isa;
  return best;
}

std::optional<Isa> missing_wider_isa() {
  std::optional<Isa> wider;
  for (Isa isa : all_isas())
    if (isa > best_isa() && cpu_supports(isa)) wider = isa;
  return wider;
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
