// The traits of scene.K the kernel needs, read off GiNaC's symbolic partials: does z feed back,
// is K_z constant or state-free, do the forces depend on p, does K split for the splittings.
#include <algorithm>
#include <cmath>
#include <exception>
#include <map>
#include <optional>
#include <vector>

#include "formula/k_tree.hpp"

namespace cs::k_formula {
namespace {

// An upper bound on the number of terms of e.expand(), saturating (doubles).
double expanded_terms(const ex& e) {
  if (is_a<GiNaC::add>(e)) {
    double n = 0;
    for (std::size_t i = 0; i < e.nops(); ++i) n += expanded_terms(e.op(i));
    return n;
  }
  if (is_a<GiNaC::mul>(e)) {
    double n = 1;
    for (std::size_t i = 0; i < e.nops(); ++i) n *= expanded_terms(e.op(i));
    return n;
  }
  if (is_a<GiNaC::power>(e) && is_a<numeric>(e.op(1)) && ex_to<numeric>(e.op(1)).is_pos_integer()) {
    double m = expanded_terms(e.op(0)), n = ex_to<numeric>(e.op(1)).to_double();
    if (m <= 1) return 1;
    // C(m + n − 1, n) ≤ (m + n − 1)^n / n!, in logarithms: a difference of two lgamma of 1e37
    // loses every digit, and ((q+1)^64 + 1)^64 passed for small (its expand then threw).
    return std::exp(std::min(700.0, n * std::log(m + n - 1) - std::lgamma(n + 1)));
  }
  return 1;
}

// Terms after expansion beyond which K is not expanded, and, separately, the size up to which
// GiNaC's normal form (common denominators: polynomial gcds) is tried. Both only ever hide a
// cancellation, which makes the dependencies read off the result too many: safe (z integrated,
// not splittable, ...). normal() of 200 poles 1/(q − k) took 68 s (its cost grows as N^2.2).
constexpr double kMaxExpandedTerms = 2e4;
constexpr std::size_t kMaxNormalTerms = 64;
constexpr int kMaxNormalDenominators = 4;
// A fraction inside a denominator, or denominators that expand to many terms, make normal()'s
// polynomial gcds explode: 1/(a + 1/(q − 2) + 1/(q − 3) + 1/(q − 4) + c(p + 1)(q + 2)(q + 3)(q + 4)
// + ((b + 1)^4 + 1)^4), which the fuzzer found, took 61 s to analyse; so did
// (a + c(p + 1)(q + 2)(q + 3)(b + 4) + (b + 1)^4 + 1)^(−4), whose denominator expands to 14 950
// terms.
constexpr double kMaxDenominatorTerms = 64;

bool negative_power(const ex& e) {
  return is_a<GiNaC::power>(e) && is_a<numeric>(e.op(1)) && ex_to<numeric>(e.op(1)).is_negative() &&
         !is_a<numeric>(e.op(0));
}

// Would GiNaC's normal form of e (terms of an expanded K) cost too much? Too many terms, more
// than kMaxNormalDenominators distinct denominators (bases of negative powers), a denominator
// that holds a fraction, or denominators of more than kMaxDenominatorTerms terms in all.
bool normal_too_costly(const ex& e) {
  if ((is_a<GiNaC::add>(e) ? e.nops() : 1) > kMaxNormalTerms) return true;
  GiNaC::exset bases;
  double terms = 0;
  for (GiNaC::const_preorder_iterator it = e.preorder_begin(); it != e.preorder_end(); ++it) {
    if (!negative_power(*it) || !bases.insert(it->op(0)).second) continue;
    if (static_cast<int>(bases.size()) > kMaxNormalDenominators) return true;
    const ex& base = it->op(0);
    for (GiNaC::const_preorder_iterator in = base.preorder_begin(); in != base.preorder_end(); ++in)
      if (negative_power(*in)) return true;
    // A whole power b^(-n) is a denominator of b^n's terms (normal() expands it); a fractional
    // one is kept as a symbol.
    const numeric& n = ex_to<numeric>(it->op(1));
    terms += n.is_integer() ? expanded_terms(GiNaC::pow(base, -n)) : expanded_terms(base);
    if (terms > kMaxDenominatorTerms) return true;
  }
  return false;
}

// Expanded and normalised, so that cancellations show (z·q − q·z has no z); left as it is when
// expanding would be too big (a K like (q1 + … + q64)^8), and not normalised when it has many
// terms or denominators.
ex simplified(const ex& e) {
  if (expanded_terms(e) > kMaxExpandedTerms) return e;
  ex r = e.expand();
  if (normal_too_costly(r)) return r;
  try {
    r = GiNaC::normal(r);
  } catch (const std::exception&) {
    // normal() may give up on some functions; expand() alone decides then
  }
  return r;
}

bool depends_on_any(const ex& e, const std::vector<GiNaC::realsymbol>& symbols) {
  return std::any_of(symbols.begin(), symbols.end(), [&](const auto& s) { return e.has(s); });
}

// The z part from K's terms with p or z (the others, V(q, t), cannot change it): K − Σ p²/2
// free of p, then R = c·z + V or c·z² + V with c = c(t).
std::optional<ZPart> z_part_of(const ex& K, const Parsed& f) {
  ex kinetic = 0;
  for (const auto& p : f.p) kinetic += GiNaC::pow(p, 2) / 2;
  ex R = simplified(K - kinetic);
  if (depends_on_any(R, f.p)) return std::nullopt;
  ex Kz = simplified(K.diff(f.z));
  auto free_of_state = [&](const ex& e) { return !depends_on_any(e, f.q) && !e.has(f.z); };
  if (Kz.is_zero()) return ZPart::linear;  // no z at all: c = 0
  if (free_of_state(Kz)) {
    if (!simplified(R - Kz * f.z).has(f.z)) return ZPart::linear;
    return std::nullopt;
  }
  ex Kzz = simplified(Kz.diff(f.z));
  if (!Kzz.is_zero() && free_of_state(Kzz) && simplified(Kz - Kzz * f.z).is_zero() &&
      !simplified(R - Kzz / 2 * GiNaC::pow(f.z, 2)).has(f.z))
    return ZPart::quadratic;
  return std::nullopt;
}

// GiNaC's derivative of a product of n factors is n products of n − 1: a K of 1100 factors
// (q + 1)(q + 2)… took 1.1 s per partial, 35 s at 30 kB. This estimates that work.
double derivative_cost(const ex& e) {
  double cost = 0;
  for (GiNaC::const_preorder_iterator it = e.preorder_begin(); it != e.preorder_end(); ++it) {
    cost += 1;
    if (is_a<GiNaC::mul>(*it)) cost += static_cast<double>(it->nops()) * static_cast<double>(it->nops());
  }
  return cost;
}
constexpr double kMaxDerivativeCost = 1e5;

void symbols_of(const ex& e, GiNaC::exset& out) {
  for (GiNaC::const_preorder_iterator it = e.preorder_begin(); it != e.preorder_end(); ++it)
    if (is_a<GiNaC::symbol>(*it)) out.insert(*it);
}

// A superset of the symbols of ∂e/∂x, without differentiating: a sum's terms one by one, the
// other factors of a product with x in one factor only, b^k as b, anything else all of e.
void partial_symbols(const ex& e, const ex& x, GiNaC::exset& out) {
  if (!e.has(x) || e.is_equal(x)) return;
  if (is_a<GiNaC::add>(e)) {
    for (std::size_t i = 0; i < e.nops(); ++i) partial_symbols(e.op(i), x, out);
    return;
  }
  if (is_a<GiNaC::mul>(e)) {
    std::size_t with_x = 0, last = 0;
    for (std::size_t i = 0; i < e.nops(); ++i)
      if (e.op(i).has(x)) ++with_x, last = i;
    if (with_x == 1) {
      for (std::size_t i = 0; i < e.nops(); ++i)
        if (i != last) symbols_of(e.op(i), out);
      partial_symbols(e.op(last), x, out);
      return;
    }
  } else if (is_a<GiNaC::power>(e) && is_a<numeric>(e.op(1))) {
    symbols_of(e.op(0), out);
    partial_symbols(e.op(0), x, out);
    return;
  }
  symbols_of(e, out);
}

// Traits of a K too big to differentiate: read off partial_symbols, so a dependency may be
// reported that a cancellation would remove (safe: z integrated, ...); the z part from the
// terms with p or z, when those are small.
KTraits structural_traits(const Parsed& f) {
  KTraits tr;
  tr.dof = f.dof;
  tr.indexed = f.indexed;
  const ex& K = f.K;
  auto partial = [&](const ex& x) {
    GiNaC::exset s;
    partial_symbols(K, x, s);
    return s;
  };
  auto has_any = [](const GiNaC::exset& s, const std::vector<GiNaC::realsymbol>& symbols) {
    return std::any_of(symbols.begin(), symbols.end(), [&](const auto& x) { return s.count(x) > 0; });
  };
  const GiNaC::exset Kz = partial(f.z);
  tr.time_dependent = K.has(f.t);
  tr.z_feeds_back = Kz.count(f.z) > 0;
  for (int i = 0; i < f.dof; ++i) {
    const GiNaC::exset Kq = partial(f.q[i]), Kp = partial(f.p[i]);
    tr.z_feeds_back = tr.z_feeds_back || Kq.count(f.z) > 0 || Kp.count(f.z) > 0;
    tr.p_in_forces = tr.p_in_forces || has_any(Kq, f.p);
  }
  tr.kz_state_free = !has_any(Kz, f.q) && !has_any(Kz, f.p) && !Kz.count(f.z);
  tr.kz_constant = tr.kz_state_free && !Kz.count(f.t);
  tr.p_in_forces = tr.p_in_forces || has_any(Kz, f.p);
  GiNaC::exvector terms;
  for (std::size_t i = 0; i < (is_a<GiNaC::add>(K) ? K.nops() : 1); ++i) {
    const ex term = is_a<GiNaC::add>(K) ? K.op(i) : K;
    if (term.has(f.z) || depends_on_any(term, f.p)) terms.push_back(term);
  }
  const ex pz = GiNaC::add(terms);
  if (derivative_cost(pz) <= kMaxDerivativeCost) tr.z_part = z_part_of(pz, f);
  return tr;
}

}  // namespace

// ∂K/∂x from the terms of K that contain x: with 64 degrees of freedom K has 129 partials, and
// differentiating every term for each took 4 s for 2000 terms.
class Partials {
 public:
  explicit Partials(const ex& K) {
    const std::size_t n = is_a<GiNaC::add>(K) ? K.nops() : 1;
    for (std::size_t i = 0; i < n; ++i) {
      const ex term = is_a<GiNaC::add>(K) ? K.op(i) : K;
      GiNaC::exset symbols;
      symbols_of(term, symbols);
      for (const ex& s : symbols) terms_with_[s].push_back(term);
    }
  }
  ex operator()(const ex& x) const {
    auto it = terms_with_.find(x);
    if (it == terms_with_.end()) return 0;
    GiNaC::exvector parts;
    for (const ex& term : it->second) parts.push_back(term.diff(ex_to<GiNaC::symbol>(x)));
    return GiNaC::add(parts);
  }

 private:
  std::map<ex, GiNaC::exvector, GiNaC::ex_is_less> terms_with_;
};

KTraits analyse(const Parsed& f) {
  if (derivative_cost(f.K) > kMaxDerivativeCost) return structural_traits(f);
  KTraits tr;
  tr.dof = f.dof;
  tr.indexed = f.indexed;
  const ex& K = f.K;
  const Partials partial(K);
  std::vector<ex> Kq, Kp;
  for (int i = 0; i < f.dof; ++i) {
    Kq.push_back(simplified(partial(f.q[i])));
    Kp.push_back(simplified(partial(f.p[i])));
  }
  ex Kz = simplified(partial(f.z));
  tr.time_dependent = simplified(K).has(f.t);
  auto has_z = [&](const ex& e) { return e.has(f.z); };
  tr.z_feeds_back = std::any_of(Kq.begin(), Kq.end(), has_z) ||
                    std::any_of(Kp.begin(), Kp.end(), has_z) || has_z(Kz);
  tr.kz_state_free = !depends_on_any(Kz, f.q) && !depends_on_any(Kz, f.p) && !Kz.has(f.z);
  tr.kz_constant = tr.kz_state_free && !Kz.has(f.t);
  auto has_p = [&](const ex& e) { return depends_on_any(e, f.p); };
  tr.p_in_forces = std::any_of(Kq.begin(), Kq.end(), has_p) || has_p(Kz);
  tr.z_part = z_part_of(K, f);
  return tr;
}

}  // namespace cs::k_formula
