#pragma once
// The SIMD ISAs a test runs: every one compiled and supported here. The build's
// QMAPS_REQUIRE_ISAS (comma-separated here; default: those the building machine's CPU has) must all be among them:
// a required ISA that cannot run fails the test instead of being skipped.
#include <gtest/gtest.h>

#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "core/isa.hpp"

namespace qmaps::testing {

inline std::vector<Isa> isas_to_run() {
  const std::vector<Isa> runnable = runnable_isas();
  std::stringstream required(QMAPS_REQUIRE_ISAS);
  for (std::string name; std::getline(required, name, ',');) {
    if (name.empty()) continue;
    bool runs = false;
    for (Isa isa : runnable) runs |= isa_name(isa) == name;
    EXPECT_TRUE(runs) << "QMAPS_REQUIRE_ISAS names " << name
                      << ", which this build or this CPU cannot run";
  }
  std::string ran;
  for (Isa isa : runnable) ran += std::string(ran.empty() ? "" : " ") += isa_name(isa);
  std::cout << "[ ISAs run ] " << ran << " (required: " << QMAPS_REQUIRE_ISAS << ")\n";
  return runnable;
}

}  // namespace qmaps::testing
