#pragma once
// Numbers recorded as test properties (in CTest's and GoogleTest's XML) at full precision:
// std::to_string's fixed "%f" prints a relative H error of 2.6e-5 as "0.000026".
#include <cstdio>
#include <string>

namespace cs::test {

inline std::string full_precision(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

}  // namespace cs::test
