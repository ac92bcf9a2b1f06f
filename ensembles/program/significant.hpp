#pragma once
// A number as the commands print it: `digits` significant digits (printf's %g).
#include <cstdio>
#include <string>

namespace qmaps {

inline std::string significant(double x, int digits = 3) {
  char text[40];
  std::snprintf(text, sizeof text, "%.*g", digits, x);
  return text;
}

}  // namespace qmaps
