// Which basin mappers a runner is compiled with. The mappers a run uses follow from its plan
// alone (mappers_of); a kernel built at run time is compiled with those and no others, so a run
// without a basin map compiles none: the energy trap's wells, the anchor test, the stroboscopic
// cycles and the recurrences were most of a new K's compile (a one-point K kernel: 2.1–2.3 s of
// compiler CPU with them, 0.8–1.1 s without; docs/performance.md). A mapper left out is one the
// plan never activates, so the results are the same bits either way; the built-in kernels are
// compiled with every mapper (kEveryMapper) and serve every plan.
#pragma once

#include "engine/run_plan.hpp"

namespace cs {

struct MapperChoice {
  bool anchors = true;  // the anchor test: an autonomous scene's map
  bool trap = true;     // the energy trap (measures.basin.exact_trap)
  bool strobe = true;   // the stroboscopic cycles: a map with measures.basin.period
  bool recur = true;    // the recurrences (RunPlan::recurrence)
};

inline constexpr MapperChoice kEveryMapper{};

// The mappers the plan activates (MapperSet's constructor reads this): none without a basin map.
// The energy trap activates only where K has one (has_energy_trap), which MapperSet knows from
// the scene's type: it compiles the trap only there, whatever this says.
inline MapperChoice mappers_of(const RunPlan& plan) {
  if (plan.map.basin < 0) return {false, false, false, false};
  const auto& basin = *plan.spec.measures.basin;
  const bool autonomous = !basin.period.has_value();
  return {autonomous, basin.exact_trap, !autonomous, plan.recurrence.enabled};
}

// Whether a runner compiled with `compiled` serves a plan that uses `used`.
constexpr bool covers(MapperChoice compiled, MapperChoice used) {
  return (compiled.anchors || !used.anchors) && (compiled.trap || !used.trap) &&
         (compiled.strobe || !used.strobe) && (compiled.recur || !used.recur);
}

constexpr MapperChoice operator|(MapperChoice a, MapperChoice b) {
  return {a.anchors || b.anchors, a.trap || b.trap, a.strobe || b.strobe, a.recur || b.recur};
}

}  // namespace cs
