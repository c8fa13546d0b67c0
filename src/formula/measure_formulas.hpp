// Measures written as formulas (INTERFACE.md, "Observables, events and Lyapunov exponents"):
// [measures] observe = { E = "p^2/2 + q^2/2" } and stop = { when = "q1^2 + q2^2 > 4" }.
//
// A measure's formula is read with K's parser (k_parser.cpp: K's grammar, exact numbers,
// constants folded to their nearest double) and printed with K's code generator
// (scene_codegen.cpp: one operation per operation, in the order written). It may read q, p (as
// the scene writes them: q or q1..qN), z, t, lambda (λ = exp(ln λ), ln λ as final_log_lambda
// gives it) and the scene's parameters; any other name is refused.
//
// A condition (stop.when, stop.exits) is comparisons `<  <=  >  >=` of two formulas, joined by
// `and` / `or` (`and` binds tighter), grouped with parentheses where a parenthesised part holds a
// comparison: "(q1 > 1 or q2 > 1) and p1 > 0". NaN compares false.
//
// The generated code is a struct (measures_source) that the run-time kernel is compiled with
// (kernel_build/kernel_source.cpp; engine/measures/observables.hpp evaluates it). Not thread-
// safe (GiNaC): call from one thread, as parse_k.
#pragma once

#include <string>

#include "model/run_spec.hpp"
#include "physics/scene_catalog.hpp"

namespace cs {

// What a formula reads besides q, p and parameters: the kernel must then carry z or ln λ.
struct FormulaReads {
  bool z = false, lambda = false, t = false;
  FormulaReads& operator|=(const FormulaReads& o) {
    z |= o.z, lambda |= o.lambda, t |= o.t;
    return *this;
  }
};

// Checks a formula of the scene's state and parameters; throws InputError "<key>: ..." naming
// the symbol or column at fault.
FormulaReads check_measure_formula(const std::string& key, const std::string& text,
                                   const SceneInfo& scene);

// Checks a condition (comparisons joined by and/or); throws InputError "<key>: ...".
FormulaReads check_condition(const std::string& key, const std::string& text,
                             const SceneInfo& scene);

// What the spec's observe and stop read, all formulas together.
FormulaReads measure_formula_reads(const Measures& m, const SceneInfo& scene);

// Whether a run needs the generated measures (observe or stop asked for).
inline bool has_measure_formulas(const Measures& m) { return m.observe || m.stop; }

// The C++ of struct `struct_name` in namespace cs: observe(x, c, v) (v[k]: observable k in the
// spec's order), stops(x, c) and exit(x, c) (the stop's exit channel), for the scene whose
// parameters are `scene.parameters` (Params fields as scene_header names them).
std::string measures_source(const Measures& m, const SceneInfo& scene,
                            const std::string& struct_name);

}  // namespace cs
