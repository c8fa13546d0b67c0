// What a method says about itself, and the list of all methods, generated from the files.
//
// A method is one header in numerics/methods/, `<name>.hpp`, declaring `struct <Name>` in
// namespace cs, where <Name> is <name> in CamelCase (hybrid_leapfrog.hpp: HybridLeapfrog,
// rk4.hpp: Rk4; a `using` alias counts). The type holds the integrator (Coef, coefficients,
// breaks_down, start, step: engine/lane_tile.hpp calls them) and
// `static constexpr MethodDescription description{...}` below. CMake reads the file names alone
// (numerics/method_list.cmake) and generates numerics/method_list.hpp: every file included,
// `using Methods = MethodList<...>`, and each type's C++ name and header (MethodSourceOf) for
// the kernels compiled at run time. From that list come the run-time catalog
// (method_catalog.cpp), the dispatch to built-in kernels (engine/kernel_dispatch.cpp) and the
// run-time kernel source (kernel_build/kernel_source.cpp): nothing else names a method.
#pragma once

#include <span>
#include <string_view>

namespace cs {

struct MethodDescription {
  std::string_view name;  // integrator.method in a spec; the file's name without .hpp
  // Where `contactsweep methods` and the spec errors list the method (ascending, ties by name):
  // a list ordered for the reader (the paper's method first), not by file name.
  int catalog_position = 0;
  int order = 0;                                          // of convergence
  std::string_view properties;                            // one line for `contactsweep methods`
  std::span<const std::string_view> needs_split_parts{};  // empty: works on any scene
  int force_evaluations_per_step = 0;
  std::string_view documentation;  // when to choose it (README, "Which method when")
  // Error-controlled, each lane its own step (integrator.rtol/atol; the type then has
  // `adaptive = true`, Control and attempt: engine/lane_tile.hpp's advance_adaptive).
  bool adaptive = false;
};

// Whether the method steps each lane adaptively (its type says `adaptive = true`).
template <class Method>
constexpr bool adaptive_method() {
  if constexpr (requires { Method::adaptive; }) return Method::adaptive;
  else return false;
}

// A method's C++ type and header, as the run-time kernel source spells them: written for every
// method by the generated numerics/method_list.hpp (the primary template is never defined).
struct MethodSource {
  std::string_view type;    // in namespace cs
  std::string_view header;  // relative to src/, as #include names it
};
template <class Method>
struct MethodSourceOf;

template <class... Method>
struct MethodList {
  // f.template operator()<M>() for the method M whose description.name is `name`: whether there
  // is one. Run-time name to template argument, for the dispatch and the kernel source.
  template <class F>
  static bool with_named(std::string_view name, F&& f) {
    return ((Method::description.name == name && (f.template operator()<Method>(), true)) || ...);
  }
  // f.template operator()<M>() for each method M, in the list's order.
  template <class F>
  static void for_each(F&& f) {
    (f.template operator()<Method>(), ...);
  }
};

}  // namespace cs
