#include "formula/contact_jacobian.hpp"

#include <cmath>
#include <exception>
#include <limits>
#include <utility>

#include "formula/k_tree.hpp"

namespace cs {

using namespace k_formula;

struct ContactJacobian::Symbolic {
  int n = 0, dof = 0;
  bool q_closed = false;
  std::vector<ex> entries;  // n × n, row-major
  std::vector<ex> field;    // n
  // The symbols and where their values come from: (symbol, index into the parameters, or
  // −1 − k for state component k, or kTime).
  std::vector<std::pair<GiNaC::realsymbol, int>> symbols;
  static constexpr int kTime = std::numeric_limits<int>::min();
};

ContactJacobian::ContactJacobian(const std::string& k, const std::vector<std::string>& parameter_order) {
  const Parsed parsed = parse(k);
  auto s = std::make_shared<Symbolic>();
  const int D = parsed.dof;
  const bool with_z = analyse(parsed).z_feeds_back;
  s->n = 2 * D + (with_z ? 1 : 0);
  std::vector<GiNaC::realsymbol> x;
  for (int d = 0; d < D; ++d) x.push_back(parsed.q[d]);
  for (int d = 0; d < D; ++d) x.push_back(parsed.p[d]);
  if (with_z) x.push_back(parsed.z);
  const ex kz = parsed.K.diff(parsed.z);
  std::vector<ex> field;
  ex p_kp = 0;
  for (int d = 0; d < D; ++d) field.push_back(parsed.K.diff(parsed.p[d]));
  for (int d = 0; d < D; ++d) {
    field.push_back(-parsed.K.diff(parsed.q[d]) + parsed.p[d] * kz);
    p_kp += parsed.p[d] * field[static_cast<std::size_t>(d)];
  }
  if (with_z) field.push_back(parsed.K - p_kp);
  s->field = field;
  for (const ex& f : field)
    for (const auto& xj : x) s->entries.push_back(f.diff(xj));
  s->dof = D;
  s->q_closed = true;
  for (int i = 0; i < D; ++i)
    for (int j = D; j < s->n; ++j)
      s->q_closed = s->q_closed && s->entries[static_cast<std::size_t>(i * s->n + j)].expand().is_zero();
  for (int d = 0; d < D; ++d) s->symbols.emplace_back(parsed.q[d], -1 - d);
  for (int d = 0; d < D; ++d) s->symbols.emplace_back(parsed.p[d], -1 - (D + d));
  s->symbols.emplace_back(parsed.z, -1 - 2 * D);
  s->symbols.emplace_back(parsed.t, Symbolic::kTime);
  for (const auto& [name, symbol] : parsed.parameters) {
    int index = -1;
    for (std::size_t i = 0; i < parameter_order.size(); ++i)
      if (parameter_order[i] == name) index = static_cast<int>(i);
    if (index < 0) fail("the parameter " + name + " has no value");
    s->symbols.emplace_back(symbol, index);
  }
  symbolic_ = std::move(s);
}

int ContactJacobian::size() const { return symbolic_->n; }
int ContactJacobian::dof() const { return symbolic_->dof; }
bool ContactJacobian::q_closed() const { return symbolic_->q_closed; }

namespace {

// Each of `exprs` at the symbols' values: the double nearest its exact value, NaN where it is
// not real or finite (a pole: 1/q at q = 0; 0/0: 2q³/√(q⁴) at q = 0) or where a value is not
// finite.
template <class Symbols>
std::vector<double> evaluated(const std::vector<ex>& exprs, const Symbols& symbols, int time,
                              const std::vector<double>& parameters,
                              const std::vector<double>& state, double t) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  GiNaC::exmap values;
  bool finite = true;
  for (const auto& [symbol, from] : symbols) {
    const double v = from == time ? t
                     : from < 0   ? state.at(static_cast<std::size_t>(-1 - from))
                                  : parameters.at(static_cast<std::size_t>(from));
    finite = finite && std::isfinite(v);
    values[symbol] = exact_of(std::isfinite(v) ? v : 0.0);
  }
  std::vector<double> out(exprs.size(), nan);
  if (!finite) return out;
  for (std::size_t i = 0; i < out.size(); ++i) {
    try {
      const ConstantValue v = constant_value(exprs[i].subs(values));
      if (v.kind == ConstantValue::finite) out[i] = v.value;
    } catch (const std::exception&) {  // a pole, or 0/0
    }
  }
  return out;
}

}  // namespace

std::vector<double> ContactJacobian::at(const std::vector<double>& parameters,
                                        const std::vector<double>& state, double t) const {
  return evaluated(symbolic_->entries, symbolic_->symbols, Symbolic::kTime, parameters, state, t);
}

std::vector<double> ContactJacobian::field(const std::vector<double>& parameters,
                                           const std::vector<double>& state, double t) const {
  return evaluated(symbolic_->field, symbolic_->symbols, Symbolic::kTime, parameters, state, t);
}

}  // namespace cs
