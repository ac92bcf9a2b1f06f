// Prints the ISAs of core/isa_list.hpp that the configuring machine's CPU has, as a CMake list:
// the default of QMAPS_REQUIRE_ISAS.
#include <cstdio>

#include "core/isa_list.hpp"

int main() {
  __builtin_cpu_init();
#define QMAPS_PRINT_IF_SUPPORTED(name, arch, lanes, supported, ...) \
  if (supported) std::printf("%s;", #name);
  QMAPS_FOR_EACH_ISA(QMAPS_PRINT_IF_SUPPORTED)
  return 0;
}
