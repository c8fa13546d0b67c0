// What the spec-parser fuzzer (fuzz_spec_parser.cpp) and its regression test
// (test_fuzz_regressions.cpp) do with one input, shared so that a file found by the fuzzer fails
// the unit test in the same way.
//
// Input layout: the TOML text, then up to two --set overrides, separated by NUL bytes:
//   TOML [ \0 OVERRIDE_1 [ \0 OVERRIDE_2 ] ]
// OVERRIDE_2 is the whole rest, further NULs included (so NULs inside --set are fuzzed too).
//
// Accepted outcomes: parse_run_spec returns a RunSpec, or throws cs::InputError. Anything else is
// a finding, and so is a RunSpec whose spec_text does not read back to the same RunSpec
// (spec_parser.hpp: spec_text "reads back to the same RunSpec").
#pragma once

#include <bit>
#include <cstdint>
#include <exception>
#include <string>
#include <string_view>
#include <typeinfo>
#include <vector>

#include "io/spec_parser.hpp"

namespace cs::fuzz {

struct SpecInput {
  std::string toml;
  std::vector<std::string> overrides;
};

inline SpecInput split_input(std::string_view bytes) {
  SpecInput input;
  const std::size_t first = bytes.find('\0');
  input.toml = std::string(bytes.substr(0, first));
  if (first == std::string_view::npos) return input;
  const std::string_view rest = bytes.substr(first + 1);
  const std::size_t second = rest.find('\0');
  input.overrides.emplace_back(rest.substr(0, second));
  if (second != std::string_view::npos) input.overrides.emplace_back(rest.substr(second + 1));
  return input;
}

namespace detail {

inline void diff(std::string& out, std::string_view field, bool same) {
  if (!same) out += std::string(out.empty() ? "" : ", ") + std::string(field);
}

inline bool same_bits(double a, double b) {
  return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b);
}

inline bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (!same_bits(a[i], b[i])) return false;
  return true;
}

template <class Map>
bool same_values(const Map& a, const Map& b) {
  if (a.size() != b.size()) return false;
  for (auto i = a.begin(), j = b.begin(); i != a.end(); ++i, ++j)
    if (i->first != j->first || !same_bits(i->second, j->second)) return false;
  return true;
}

// Fields of a and b that differ (doubles bit for bit), comma-separated; empty when equal.
inline std::string differences(const RunSpec& a, const RunSpec& b) {
  std::string out;
  diff(out, "title", a.title == b.title);
  diff(out, "scene", a.scene == b.scene);
  diff(out, "parameters", same_values(a.parameters, b.parameters));
  diff(out, "initial", same_values(a.initial, b.initial));
  diff(out, "method", a.method == b.method);
  diff(out, "h", same_bits(a.h, b.h));
  diff(out, "t_end", same_bits(a.t_end, b.t_end));
  diff(out, "steps", a.steps == b.steps);
  bool axes = a.axes.size() == b.axes.size();
  for (std::size_t i = 0; axes && i < a.axes.size(); ++i)
    axes = a.axes[i].name == b.axes[i].name && a.axes[i].target == b.axes[i].target &&
           a.axes[i].is_parameter == b.axes[i].is_parameter &&
           a.axes[i].is_step_size == b.axes[i].is_step_size &&
           same_bits(a.axes[i].values, b.axes[i].values);
  diff(out, "axes", axes);
  const Measures& m = a.measures;
  const Measures& n = b.measures;
  diff(out, "measures.final_state",
       m.final_state.has_value() == n.final_state.has_value() &&
           (!m.final_state || m.final_state->vars == n.final_state->vars));
  diff(out, "measures.trajectory",
       m.trajectory.has_value() == n.trajectory.has_value() &&
           (!m.trajectory || m.trajectory->every == n.trajectory->every));
  diff(out, "measures.basin",
       m.basin.has_value() == n.basin.has_value() &&
           (!m.basin || m.basin->early_stop == n.basin->early_stop));
  diff(out, "measures.sync",
       m.sync.has_value() == n.sync.has_value() &&
           (!m.sync || (same_bits(m.sync->window_from, n.sync->window_from) &&
                        same_bits(m.sync->window_to, n.sync->window_to))));
  diff(out, "spec_text", a.spec_text == b.spec_text);
  return out;
}

inline std::string unexpected(std::string_view stage, const std::exception* error) {
  return std::string(stage) + ": unexpected exception " +
         (error != nullptr ? std::string(typeid(*error).name()) + ": " + error->what()
                           : std::string("(not derived from std::exception)"));
}

}  // namespace detail

// Runs one input through cs::parse_run_spec; returns what is wrong (empty: nothing).
inline std::string check(const SpecInput& input) {
  RunSpec spec;
  try {
    spec = parse_run_spec(input.toml, input.overrides, "fuzz.toml");
  } catch (const InputError&) {
    return "";
  } catch (const std::exception& error) {
    return detail::unexpected("parse_run_spec", &error);
  } catch (...) {
    return detail::unexpected("parse_run_spec", nullptr);
  }
  RunSpec again;
  try {
    again = parse_run_spec(spec.spec_text, {}, "spec_text");
  } catch (const InputError& error) {
    return "spec_text does not read back: " + std::string(error.what()) + "\nspec_text:\n" +
           spec.spec_text;
  } catch (const std::exception& error) {
    return detail::unexpected("re-reading spec_text", &error);
  } catch (...) {
    return detail::unexpected("re-reading spec_text", nullptr);
  }
  const std::string differ = detail::differences(spec, again);
  if (!differ.empty())
    return "spec_text reads back to a different RunSpec (" + differ + ")\nspec_text:\n" +
           spec.spec_text;
  return "";
}

}  // namespace cs::fuzz
