// The traits of scene.K the kernel needs, read off GiNaC's symbolic partials: does z feed back,
// is K_z constant or state-free, do the forces depend on p, does K split for the splittings.
#include <algorithm>
#include <cmath>
#include <exception>
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
    if (n > 1000) return m > 1 ? 1e300 : 1;
    return std::exp(std::lgamma(m + n) - std::lgamma(n + 1) - std::lgamma(m));  // C(m + n − 1, n)
  }
  return 1;
}

// Expanded and normalised, so that cancellations show (z·q − q·z has no z); left as it is when
// expanding would be too big (a K like (q1 + … + q64)^8): the dependencies read off it are then
// only ever too many, which is safe (z integrated, not splittable, ...).
ex simplified(const ex& e) {
  if (expanded_terms(e) > 2e4) return e;
  ex r = e.expand();
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

}  // namespace

KTraits analyse(const Parsed& f) {
  KTraits tr;
  tr.dof = f.dof;
  tr.indexed = f.indexed;
  const ex& K = f.K;
  std::vector<ex> Kq, Kp;
  for (int i = 0; i < f.dof; ++i) {
    Kq.push_back(simplified(K.diff(f.q[i])));
    Kp.push_back(simplified(K.diff(f.p[i])));
  }
  ex Kz = simplified(K.diff(f.z));
  tr.time_dependent = simplified(K).has(f.t);
  auto has_z = [&](const ex& e) { return e.has(f.z); };
  tr.z_feeds_back = std::any_of(Kq.begin(), Kq.end(), has_z) ||
                    std::any_of(Kp.begin(), Kp.end(), has_z) || has_z(Kz);
  tr.kz_state_free = !depends_on_any(Kz, f.q) && !depends_on_any(Kz, f.p) && !Kz.has(f.z);
  tr.kz_constant = tr.kz_state_free && !Kz.has(f.t);
  auto has_p = [&](const ex& e) { return depends_on_any(e, f.p); };
  tr.p_in_forces = std::any_of(Kq.begin(), Kq.end(), has_p) || has_p(Kz);

  // z part: K − Σ p²/2 free of p, then R = c·z + V or c·z² + V with c = c(t).
  ex kinetic = 0;
  for (const auto& p : f.p) kinetic += GiNaC::pow(p, 2) / 2;
  ex R = simplified(K - kinetic);
  if (depends_on_any(R, f.p)) return tr;
  auto free_of_state = [&](const ex& e) { return !depends_on_any(e, f.q) && !e.has(f.z); };
  if (Kz.is_zero()) {
    tr.z_part = ZPart::linear;  // no z at all: c = 0
  } else if (free_of_state(Kz)) {
    if (!simplified(R - Kz * f.z).has(f.z)) tr.z_part = ZPart::linear;
  } else {
    ex Kzz = simplified(Kz.diff(f.z));
    if (!Kzz.is_zero() && free_of_state(Kzz) && simplified(Kz - Kzz * f.z).is_zero() &&
        !simplified(R - Kzz / 2 * GiNaC::pow(f.z, 2)).has(f.z))
      tr.z_part = ZPart::quadratic;
  }
  return tr;
}

}  // namespace cs::k_formula
