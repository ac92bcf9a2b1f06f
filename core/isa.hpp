#pragma once
// Instruction sets: which were compiled into this binary, which the CPU has, and the choice made
// for a run (--simd auto|scalar|sse2|avx2|avx512). `scalar` is the reference path.
#include <cstddef>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace qmaps {

enum class Isa { scalar, sse2, avx2, avx512 };

std::string_view isa_name(Isa isa);
Isa parse_isa(std::string_view name);        // throws qmaps::Error on an unknown name
std::span<const Isa> compiled_isas();        // SIMD ISAs built into this binary, narrowest first
bool cpu_supports(Isa isa);                  // scalar: always true
Isa best_isa();                              // the widest ISA compiled and supported
std::vector<Isa> runnable_isas();            // SIMD ISAs compiled and supported here
Isa resolve_isa(std::string_view request);   // "auto" → best_isa(); else checked: compiled and supported
std::size_t isa_lanes(Isa isa);              // doubles per register: 1, 2, 4, 8

}  // namespace qmaps
