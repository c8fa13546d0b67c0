// scene.K's interface (k_formula.hpp): parse and analyse (k_parser.cpp, k_traits.cpp), and the
// GiNaC reference value of K and its partials used to check the compiled scenes.
#include "formula/k_formula.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <string>
#include <vector>

#include "formula/k_tree.hpp"

namespace cs {

using namespace k_formula;

namespace {

std::vector<std::string> sorted_parameters(const Parsed& parsed) {
  std::vector<std::string> names;
  for (const auto& [name, symbol] : parsed.parameters) names.push_back(name);  // std::map: sorted
  return names;
}

}  // namespace

namespace {

KFormula parse_and_analyse(const std::string& text) {
  Parsed parsed = parse(text);
  KFormula f;
  f.text = text;
  f.parameters = sorted_parameters(parsed);
  for (int i = 0; i < parsed.dof; ++i) {
    f.positions.push_back(parsed.q[i].get_name());
    f.momenta.push_back(parsed.p[i].get_name());
  }
  f.traits = analyse(parsed);
  // Generate once so that every refusal (a constant beyond the double range, ...) happens here.
  return_statement(parsed, field_names(f.parameters));
  return f;
}

}  // namespace

KFormula parse_k(const std::string& text) {
  try {
    return parse_and_analyse(text);
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {  // GiNaC's or CLN's, std::bad_alloc, std::length_error
    throw InputError(std::string("scene.K: could not be analysed: ") + e.what());
  }
}

double evaluate_k(const KFormula& f, const std::map<std::string, double>& values, const std::string& wrt) {
  Parsed parsed = parse(f.text);
  std::vector<std::pair<ex, std::string>> symbols;
  for (int i = 0; i < parsed.dof; ++i) {
    symbols.emplace_back(parsed.q[i], parsed.q[i].get_name());
    symbols.emplace_back(parsed.p[i], parsed.p[i].get_name());
  }
  symbols.emplace_back(parsed.z, "z");
  symbols.emplace_back(parsed.t, "t");
  for (const auto& [name, symbol] : parsed.parameters) symbols.emplace_back(symbol, name);

  ex e = parsed.K;
  if (!wrt.empty()) {
    auto it = std::find_if(symbols.begin(), symbols.end(), [&](const auto& s) { return s.second == wrt; });
    if (it == symbols.end() || parsed.parameters.count(wrt))
      throw InputError("scene.K: " + wrt + " is not a variable of K");
    e = e.diff(ex_to<GiNaC::symbol>(it->first));
  }
  GiNaC::exmap substitutions;
  for (const auto& [symbol, name] : symbols) {
    if (!e.has(symbol)) continue;
    auto value = values.find(name);
    if (value == values.end()) throw InputError("scene.K: no value for " + name);
    if (!std::isfinite(value->second)) return std::numeric_limits<double>::quiet_NaN();
    substitutions[symbol] = exact_of(value->second);
  }
  try {
    const ConstantValue v = constant_value(e.subs(substitutions));
    return v.kind == ConstantValue::finite ? v.value : std::numeric_limits<double>::quiet_NaN();
  } catch (const std::exception&) {
    return std::numeric_limits<double>::quiet_NaN();  // a pole: 1/q at q = 0
  }
}

}  // namespace cs

// CLN, GiNaC's number library, allocates a few bytes at start-up that it never frees; under
// LeakSanitizer that made every program that links GiNaC fail at exit (the sanitizer build's
// test discovery first). The sanitizer runtime looks this hook up by name; other builds ignore it.
// It lives here because this file is linked into every program that links GiNaC.
extern "C" [[gnu::visibility("default"), gnu::used]] const char* __lsan_default_suppressions() {
  return "leak:libcln.so\nleak:libginac.so\n";
}
