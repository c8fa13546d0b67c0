#include "numerics/method_catalog.hpp"

#include <algorithm>

namespace cs {

const std::vector<MethodInfo>& method_catalog() {
  static const std::vector<MethodInfo> catalog{
      {"hybrid_leapfrog", 2,
       "Sogo & Ohnishi's hybrid leap-frog (paper, sec. 3.1), explicit; (q, lambda p) conformally "
       "symplectic; H = lambda K drifts linearly",
       {}, 1},
  };
  return catalog;
}

const MethodInfo* find_method(std::string_view name) {
  const auto& all = method_catalog();
  auto it = std::find_if(all.begin(), all.end(), [&](const MethodInfo& m) { return m.name == name; });
  return it == all.end() ? nullptr : &*it;
}

}  // namespace cs
