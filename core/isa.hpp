#pragma once
// Instruction sets: which were compiled into this binary, which the CPU has, and the choice made
// for a run (--simd auto, scalar or an ISA of core/isa_list.hpp). `scalar` is the reference path.
#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/isa_list.hpp"

namespace qmaps {

#define QMAPS_ISA_ENUMERATOR(name, ...) name,
enum class Isa { scalar, QMAPS_FOR_EACH_ISA(QMAPS_ISA_ENUMERATOR) };
#undef QMAPS_ISA_ENUMERATOR

std::string_view isa_name(Isa isa);
Isa parse_isa(std::string_view name);        // throws qmaps::Error on an unknown name
std::span<const Isa> all_isas();             // every SIMD ISA of the list, narrowest first
std::span<const Isa> compiled_isas();        // SIMD ISAs built into this binary, narrowest first
std::string_view kernel_flags();             // "isa: flags; ...": what their kernel units add
bool cpu_supports(Isa isa);                  // scalar: always true
Isa best_isa();                              // the widest ISA compiled and supported
// The widest ISA this CPU has but this binary was built without, where wider than best_isa():
// the binary then runs best_isa() (a copy built for another machine), and says so.
std::optional<Isa> missing_wider_isa();
std::vector<Isa> runnable_isas();            // SIMD ISAs compiled and supported here
Isa resolve_isa(std::string_view request);   // "auto" → best_isa(); else checked: compiled and supported
std::size_t isa_lanes(Isa isa);              // doubles per register: 1, 2, 4, 8

}  // namespace qmaps
