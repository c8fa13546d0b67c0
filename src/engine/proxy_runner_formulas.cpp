// The proxy scene's runners with measures as formulas (proxy_runner.hpp).
#include "engine/proxy_runner.hpp"

namespace cs {

void run_proxy_with_formulas(const RunPlan& plan, BlockResults& results) {
  run_proxy<true>(plan, results);
}

}  // namespace cs
