// The exact energy trap of a dissipative mechanical scene, K = Σpᵢ²/2 + V(q) + k·z with k < 0
// and no time: E = T + V = K(q, p, 0) obeys dE/dt = k·|p|² ≤ 0. The sublevel set {V < E} splits
// into one component per minimum of V as long as E stays below every other critical value of V
// (saddles, maxima: Morse theory), so a lane whose E is below the lowest of them can never leave
// its well and ends at its minimum: its basin is decided, exactly. The double well's trap
// (E < a⁴/2) is the case V = (q² − a²)²/2.
//
// The critical points are found numerically: Newton's method on ∇V from a grid of starts over a
// box around the map's positions (BasinBox), Hessians by central differences, classified by their
// eigenvalues. The trap level is also kept below V on the box's boundary, so that a component
// reaching out of the box (where a critical point could hide, or V could fall without bound) never
// counts as a well. The integrator's energy error is covered by a margin h²·κ·ΔE (κ the largest
// curvature at a critical point, ΔE the depth of the deepest well below the level): for the
// double well that is 2h²a⁶, twice the largest rise measured (test_basin.cpp).
//
// Small dense algebra (D×D, D the scene's dof) is written out here rather than taken from Eigen:
// this header is compiled into every kernel built at run time, and Eigen's headers made that
// build four times slower (10 s against 2.5 s).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include "numerics/split_flows.hpp"
#include "physics/partials.hpp"
#include "physics/scene_concept.hpp"

namespace cs {

// Whether the trap's code is compiled for S. A scene that stands for another at run time (a step
// kernel's proxy, engine/proxy_scene.hpp) compiles it, and answers energy_trap_at_run_time.
template <Scene S>
constexpr bool has_energy_trap() {
  if constexpr (requires { S::may_have_energy_trap; })
    return S::may_have_energy_trap;
  else if constexpr (requires { S::z_part; })
    return S::z_part == ZPart::linear && !time_dependent<S>();
  else
    return false;
}

// Whether S's K has an energy trap: known at compile time, but for a proxy scene.
template <Scene S>
bool energy_trap_at_run_time() {
  if constexpr (requires { S::run_time_energy_trap(); }) return S::run_time_energy_trap();
  else return has_energy_trap<S>();
}

// Where the map's positions lie: each q's range over the grid, widened by half its width (at
// least 1) on either side.
template <int D>
struct BasinBox {
  std::array<double, D> lo{}, hi{};
};

// Whether the trap decides a lane's basin, and if not why (the `energy_trap` attribute,
// basin_summary.cpp). Counted per block (RunPlan's internal column trap_verdict: how many lanes
// had each verdict), as numbers: the values never change.
enum class TrapVerdict : int {
  not_applicable = 0,  // K is not Σp²/2 + V(q) + k·z without t, or exact_trap = false
  used = 1,
  no_dissipation = 2,  // k ≥ 0: E never falls
  no_minimum = 3,      // Newton found no minimum of V in the box
  boundary_too_low = 4,  // V on the box's boundary is nowhere above the lowest minimum
  margin_too_large = 5   // the lowest saddle, less the integrator's margin, is not above it
};
inline constexpr int kTrapVerdicts = 6;

template <int D>
struct Wells {
  bool usable = false;  // k < 0 and a trap level below which some well exists
  TrapVerdict verdict = TrapVerdict::not_applicable;
  BasinBox<D> box{};             // where the critical points were looked for
  bool boundary_limited = false;  // the level is V's least value on the box's boundary
  double trap_energy = -std::numeric_limits<double>::infinity();  // E < this: trapped (margin in)
  std::vector<std::array<double, D>> minima;
  std::vector<std::array<double, D>> unstable;  // the other critical points: saddles, maxima
  double highest_minimum = INFINITY;              // V's largest value at a minimum
  double confinement = -INFINITY;  // E below it never reaches the box's boundary (as the level)
  double curvature = 1.0;  // the largest |eigenvalue| of V's Hessian at a critical point
};

template <Scene S>
class WellFinder {
  static constexpr int D = S::dof;
  using Point = std::array<double, D>;
  using Params = ParamsOf<S, double>;

 public:
  WellFinder(const Params& c, const BasinBox<D>& box, double h) : c_(c), box_(box), h_(h) {}

  // Cold: once per run and parameter set, so compiled for size (kernels of K compile it).
  [[gnu::cold]] Wells<D> find() const {
    Wells<D> wells;
    wells.box = box_;
    if constexpr (has_energy_trap<S>()) {
      wells.verdict = TrapVerdict::no_dissipation;
      if (!(z_coefficient<S>(c_, 0.0) < 0.0)) return wells;  // no dissipation: E is not a trap
      wells.verdict = TrapVerdict::no_minimum;
      std::vector<Point> minima, others;
      for (const Point& start : starts()) {
        Point x = start;
        if (!newton(x)) continue;
        auto& list = is_minimum(x) ? minima : others;
        bool known = false;
        for (const Point& y : list) known = known || distance(x, y) <= 1e-6 * (1.0 + norm(x));
        if (!known) list.push_back(x);
      }
      if (minima.empty()) return wells;
      double level = boundary_minimum(), curvature = 0.0, lowest = INFINITY;
      wells.confinement = level;
      double saddle = INFINITY;
      for (const Point& y : others) saddle = std::min(saddle, V(y));
      wells.boundary_limited = !(saddle <= level);
      level = std::min(level, saddle);
      wells.highest_minimum = -INFINITY;
      for (const Point& y : minima) {
        lowest = std::min(lowest, V(y));
        wells.highest_minimum = std::max(wells.highest_minimum, V(y));
      }
      for (const auto* list : {&minima, &others})
        for (const Point& y : *list) curvature = std::max(curvature, largest_curvature(y));
      const double margin = h_ * h_ * curvature * std::max(0.0, level - lowest);
      wells.usable = level - margin > lowest;
      wells.verdict = wells.usable            ? TrapVerdict::used
                      : wells.boundary_limited ? TrapVerdict::boundary_too_low
                                               : TrapVerdict::margin_too_large;
      wells.trap_energy = level - margin;
      std::sort(minima.begin(), minima.end());
      wells.minima = minima;
      wells.unstable = others;
      wells.curvature = std::max(curvature, 1e-12);
    }
    return wells;
  }

  // V's least value on the box's boundary (sampled densely: 512 points along each edge), less
  // 1% of V's range there: a component of {V < E} below it stays inside the box.
  static constexpr int kBoundarySamples = 512;
  double boundary_minimum() const {
    constexpr int n = kBoundarySamples;
    double least = INFINITY, most = -INFINITY;
    for (int face = 0; face < D; ++face)
      for (int side = 0; side < 2; ++side)
        for (const Point& start : starts_on_face(face, side, n)) {
          least = std::min(least, V(start));
          most = std::max(most, V(start));
        }
    return least - 0.01 * (most - least);
  }

  // V's least value on one face of the box (the lower one if side = 0), as boundary_minimum()
  // samples it.
  double face_minimum(int face, int side) const {
    double least = INFINITY;
    for (const Point& x : starts_on_face(face, side, kBoundarySamples)) least = std::min(least, V(x));
    return least;
  }

  // The minimum at the bottom of the well holding q (a trapped lane's). One well: nothing to
  // find. One q: read off the critical points (bottom_on_line). Else steepest descent with
  // steps 1/κ, halved until V falls (so it never hops over a ridge into a lower well), then the
  // nearest of the minima found.
  // False when the descent ends at no minimum found at set-up (one was missed): the lane is
  // then not trapped, and settles on line instead. (An out parameter rather than an optional:
  // copying the optional's flag and point through the stack stalled every trapped lane's look.)
  bool bottom(const double* q, const Wells<D>& wells, Point& minimum) const {
    const Point* known = wells.minima.size() == 1 ? &wells.minima.front() : nullptr;
    if constexpr (D == 1)
      if (known == nullptr) known = bottom_on_line(q[0], wells);
    if (known == nullptr) return descend(q, wells, minimum);
    minimum = *known;
    return true;
  }

  // One q (exact, no descent): a trapped lane's E is below V at every unstable critical point,
  // so the interval of {V < E} that holds it lies strictly between the nearest unstable points
  // on either side and inside the box (V is above the level on its ends), and holds no other
  // critical point than its one minimum: V is monotone on either side of it. Empty when that
  // interval holds no minimum or several (critical points missed at set-up): null, and the
  // descent decides, as before.
  static const Point* bottom_on_line(double q, const Wells<D>& wells) requires(D == 1) {
    double left = wells.box.lo[0], right = wells.box.hi[0];
    for (const Point& u : wells.unstable) {
      if (u[0] < q) left = std::max(left, u[0]);
      else if (u[0] > q) right = std::min(right, u[0]);
      else return nullptr;  // on an unstable point: never below the level
    }
    const Point* found = nullptr;
    for (const Point& m : wells.minima)
      if (m[0] > left && m[0] < right) {
        if (found != nullptr) return nullptr;
        found = &m;
      }
    return found;
  }

  // The steepest descent of bottom() (any D).
  bool descend(const double* q, const Wells<D>& wells, Point& minimum) const {
    Point x;
    std::copy(q, q + D, x.begin());
    const double step = 1.0 / wells.curvature;
    double vx = V(x);
    for (int k = 0; k < 100000; ++k) {
      const Point g = gradient(x);
      double s = step;
      Point y;
      for (int i = 0; i < D; ++i) y[i] = x[i] - s * g[i];
      double vy = V(y);
      while (!(vy < vx) && s > 1e-6 * step) {
        s *= 0.5;
        for (int i = 0; i < D; ++i) y[i] = x[i] - s * g[i];
        vy = V(y);
      }
      if (!(vy < vx)) break;
      x = y, vx = vy;
      if (nearest(x, wells).second < kSettled) break;
    }
    const auto [m, d] = nearest(x, wells);
    if (!(d < kSettled)) return false;
    minimum = m;
    return true;
  }

 private:
  static constexpr double kSettled = 1e-3;  // near enough to a minimum to tell which one

  static std::pair<Point, double> nearest(const Point& x, const Wells<D>& wells) {
    Point best = x;
    double d = INFINITY;
    for (const Point& m : wells.minima)
      if (distance(m, x) < d) d = distance(m, x), best = m;
    return {best, d};
  }

  double V(const Point& x) const {
    if constexpr (has_energy_trap<S>()) return potential<S>(x.data(), c_, 0.0);
    else return 0.0;
  }
  Point gradient(const Point& x) const {
    Point g{};
    if constexpr (has_energy_trap<S>())
      for_each_dof<D>([&](auto i) { g[i] = potential_force<S, decltype(i)::value>(x.data(), c_, 0.0); });
    return g;
  }
  using Matrix = std::array<std::array<double, D>, D>;

  Matrix hessian(const Point& x) const {
    Matrix H;
    for (int j = 0; j < D; ++j) {
      const double d = 1e-5 * (1.0 + std::fabs(x[j]));
      Point a = x, b = x;
      a[j] += d, b[j] -= d;
      const Point ga = gradient(a), gb = gradient(b);
      for (int i = 0; i < D; ++i) H[i][j] = (ga[i] - gb[i]) / (2.0 * d);
    }
    for (int i = 0; i < D; ++i)
      for (int j = 0; j < i; ++j) H[i][j] = H[j][i] = 0.5 * (H[i][j] + H[j][i]);
    return H;
  }

  // The eigenvalues of a symmetric matrix by cyclic Jacobi rotations.
  static Point eigenvalues(Matrix a) {
    for (int sweep = 0; sweep < 64; ++sweep) {
      double off = 0.0;
      for (int i = 0; i < D; ++i)
        for (int j = i + 1; j < D; ++j) off += a[i][j] * a[i][j];
      if (off < 1e-30) break;
      for (int p = 0; p < D; ++p)
        for (int q = p + 1; q < D; ++q) {
          if (a[p][q] == 0.0) continue;
          const double theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
          const double t = std::copysign(1.0, theta) / (std::fabs(theta) + std::sqrt(theta * theta + 1.0));
          const double c = 1.0 / std::sqrt(t * t + 1.0), s = t * c;
          for (int k = 0; k < D; ++k) {  // columns p, q
            const double akp = a[k][p], akq = a[k][q];
            a[k][p] = c * akp - s * akq, a[k][q] = s * akp + c * akq;
          }
          for (int k = 0; k < D; ++k) {  // rows p, q
            const double apk = a[p][k], aqk = a[q][k];
            a[p][k] = c * apk - s * aqk, a[q][k] = s * apk + c * aqk;
          }
        }
    }
    Point lambda;
    for (int i = 0; i < D; ++i) lambda[i] = a[i][i];
    return lambda;
  }

  // Solves A x = b by Gaussian elimination with partial pivoting; false if A is singular.
  static bool solve(Matrix a, Point b, Point& x) {
    for (int col = 0; col < D; ++col) {
      int pivot = col;
      for (int r = col + 1; r < D; ++r)
        if (std::fabs(a[r][col]) > std::fabs(a[pivot][col])) pivot = r;
      if (!(std::fabs(a[pivot][col]) > 0.0)) return false;
      std::swap(a[col], a[pivot]);
      std::swap(b[col], b[pivot]);
      for (int r = col + 1; r < D; ++r) {
        const double f = a[r][col] / a[col][col];
        for (int k = col; k < D; ++k) a[r][k] -= f * a[col][k];
        b[r] -= f * b[col];
      }
    }
    for (int r = D - 1; r >= 0; --r) {
      double v = b[r];
      for (int k = r + 1; k < D; ++k) v -= a[r][k] * x[k];
      x[r] = v / a[r][r];
    }
    for (double v : x)
      if (!std::isfinite(v)) return false;
    return true;
  }

  bool is_minimum(const Point& x) const {
    const Point lambda = eigenvalues(hessian(x));
    return *std::min_element(lambda.begin(), lambda.end()) > 0.0;
  }
  double largest_curvature(const Point& x) const {
    double k = 0.0;
    for (double l : eigenvalues(hessian(x))) k = std::max(k, std::fabs(l));
    return k;
  }

  // Newton's method on ∇V = 0, damped: a step is halved until |∇V| falls, and never longer
  // than a twentieth of the box (sharp wells, like the magnetic pendulum's, throw an undamped
  // Newton step far off from a start a little outside their concave core).
  bool newton(Point& x) const {
    double gx = norm(gradient(x));
    for (int k = 0; k < 200 && gx > 0.0; ++k) {
      Point minus_g = gradient(x), dx;
      for (double& v : minus_g) v = -v;
      if (!solve(hessian(x), minus_g, dx)) return false;
      const double longest = norm(dx), cap = 0.05 * box_width();
      if (longest > cap)
        for (double& v : dx) v *= cap / longest;
      double s = 1.0;
      Point y;
      double gy = INFINITY;
      for (; s > 1e-6; s *= 0.5) {
        for (int i = 0; i < D; ++i) y[i] = x[i] + s * dx[i];
        gy = norm(gradient(y));
        if (gy < gx) break;
      }
      if (!(gy < gx)) break;  // no progress: a critical point, or a dead end
      const double moved = s * norm(dx);
      x = y, gx = gy;
      if (!inside(x, 2.0)) return false;
      if (moved <= 1e-14 * (1.0 + norm(x))) break;
    }
    return gx <= 1e-8 * (1.0 + std::fabs(V(x)));
  }

  // A grid of starts over the box: 64 for one q, 32² for two, fewer per axis as D grows.
  std::vector<Point> starts() const {
    const int n = D == 1 ? 64 : D == 2 ? 32 : D == 3 ? 12 : 6;
    std::vector<Point> out;
    std::array<int, D> index{};
    while (true) {
      Point x;
      for (int i = 0; i < D; ++i)
        x[i] = box_.lo[i] + (index[i] + 0.5) / n * (box_.hi[i] - box_.lo[i]);
      out.push_back(x);
      int i = 0;
      while (i < D && ++index[i] == n) index[i++] = 0;
      if (i == D) break;
    }
    return out;
  }

  double box_width() const {
    double w = 0.0;
    for (int i = 0; i < D; ++i) w = std::max(w, box_.hi[i] - box_.lo[i]);
    return w;
  }
  std::vector<Point> starts_on_face(int face, int side, int n) const {
    std::vector<Point> out;
    const int others = D - 1;
    const int count = others == 0 ? 1 : others == 1 ? n : others == 2 ? 64 * 64 : 16 * 16 * 16;
    const int per_axis = others == 0 ? 1 : others == 1 ? n : others == 2 ? 64 : 16;
    for (int k = 0; k < count; ++k) {
      Point x;
      int rest = k;
      for (int i = 0; i < D; ++i) {
        if (i == face) {
          x[i] = side ? box_.hi[i] : box_.lo[i];
          continue;
        }
        const int j = rest % per_axis;
        rest /= per_axis;
        x[i] = box_.lo[i] + (per_axis == 1 ? 0.5 : j / (per_axis - 1.0)) * (box_.hi[i] - box_.lo[i]);
      }
      out.push_back(x);
    }
    return out;
  }

  bool inside(const Point& x, double widen) const {
    for (int i = 0; i < D; ++i) {
      const double mid = 0.5 * (box_.lo[i] + box_.hi[i]), half = 0.5 * (box_.hi[i] - box_.lo[i]);
      if (!(std::fabs(x[i] - mid) <= widen * half)) return false;
    }
    return true;
  }
  static double norm(const Point& x) {
    double n = 0.0;
    for (double v : x) n = std::max(n, std::fabs(v));
    return n;
  }
  static double distance(const Point& x, const Point& y) {
    double n = 0.0;
    for (int i = 0; i < D; ++i) n = std::max(n, std::fabs(x[i] - y[i]));
    return n;
  }

  Params c_;
  BasinBox<D> box_;
  double h_;
};

// The wells of K over the map's box, found as above. A box whose face lands on or near a
// minimum of V (a pendulum, V = −cos q, over q ∈ [−3π, 3π]: the box [−6π, 6π] ends at minima)
// puts the trap level at that minimum, where it traps nothing. When the boundary is what limits
// the level, each face is moved, one at a time, within ±3/16 of the box's width (so the grid
// stays inside), to where V's least value on it is highest, scanning outwards from where it was;
// the moved box is kept if it gives the higher trap level. A box the boundary does not limit is
// never moved: its wells, and every lane's bits, are what they were.
template <Scene S>
Wells<S::dof> find_wells(const ParamsOf<S, double>& c, const BasinBox<S::dof>& box, double h) {
  constexpr int D = S::dof;
  Wells<D> wells = WellFinder<S>(c, box, h).find();
  if (!wells.boundary_limited) return wells;
  constexpr int kSteps = 24, kPerWidth = 128;
  BasinBox<D> moved = box;
  for (int face = 0; face < D; ++face)
    for (int side = 0; side < 2; ++side) {
      const double step = (box.hi[face] - box.lo[face]) / kPerWidth;
      double& edge = side ? moved.hi[face] : moved.lo[face];
      const double start = edge;
      double best = WellFinder<S>(c, moved, h).face_minimum(face, side);
      double best_edge = start;
      for (int k = 1; k <= 2 * kSteps; ++k) {
        const int j = k % 2 ? (k + 1) / 2 : -(k / 2);  // 1, −1, 2, −2, ...
        edge = start + j * step;
        const double v = WellFinder<S>(c, moved, h).face_minimum(face, side);
        if (v > best) best = v, best_edge = edge;
      }
      edge = best_edge;
    }
  if (moved.lo == box.lo && moved.hi == box.hi) return wells;
  Wells<D> other = WellFinder<S>(c, moved, h).find();
  const bool better = other.usable > wells.usable ||
                      (other.usable == wells.usable && other.trap_energy > wells.trap_energy);
  return better ? other : wells;
}

// The box to look for the wells in, for lanes of one parameter set whose positions lie in
// `positions` and whose energies E = K(q, p, 0) start at most at e0: the positions widened by
// `widen` on either side (BasinBox), or, when V on that box's boundary is not above e0, widened
// by 2, 4, … 2⁶ times as much, the first box whose boundary is. E never rises, so no such lane
// ever reaches that boundary, and every critical point of V it could meet is inside: a map
// that does not span the wells (one initial point, q0 ∈ [1.5, 2.5] for the double well) still
// finds them. No such box (V bounded, or unbounded below; the wells too far): the first box.
// A box whose boundary is already above e0 is kept as it is: its wells are what they were.
template <Scene S>
BasinBox<S::dof> confining_box(const ParamsOf<S, double>& c, const BasinBox<S::dof>& positions,
                               const std::array<double, S::dof>& widen, double e0, double h) {
  constexpr int D = S::dof;
  constexpr int kDoublings = 6;
  auto widened = [&](double factor) {
    BasinBox<D> box;
    for (int d = 0; d < D; ++d)
      box.lo[d] = positions.lo[d] - factor * widen[d], box.hi[d] = positions.hi[d] + factor * widen[d];
    return box;
  };
  const BasinBox<D> first = widened(1.0);
  if (!std::isfinite(e0)) return first;
  for (int k = 0; k <= kDoublings; ++k) {
    const BasinBox<D> box = widened(std::ldexp(1.0, k));
    if (WellFinder<S>(c, box, h).boundary_minimum() > e0) return box;
  }
  return first;
}

// The trap's uses of K (engine/mappers/energy_trap.hpp): the box and the wells for one parameter
// set, the minimum at the bottom of the well holding q (WellFinder::bottom), and V(q). A proxy
// scene answers them through its step kernel's table, which computes them with the scene's code.
template <Scene S>
BasinBox<S::dof> trap_box(const ParamsOf<S, double>& c, const BasinBox<S::dof>& positions,
                          const std::array<double, S::dof>& widen, double e0, double h) {
  if constexpr (requires { S::confining_box(c, positions, widen, e0, h); })
    return S::confining_box(c, positions, widen, e0, h);
  else
    return confining_box<S>(c, positions, widen, e0, h);
}
template <Scene S>
Wells<S::dof> trap_wells(const ParamsOf<S, double>& c, const BasinBox<S::dof>& box, double h) {
  if constexpr (requires { S::find_wells(c, box, h); }) return S::find_wells(c, box, h);
  else return find_wells<S>(c, box, h);
}
template <Scene S>
bool well_bottom(const ParamsOf<S, double>& c, const BasinBox<S::dof>& box, double h,
                 const double* q, const Wells<S::dof>& wells, std::array<double, S::dof>& minimum) {
  if constexpr (requires { S::well_bottom(c, box, h, q, wells, minimum); })
    return S::well_bottom(c, box, h, q, wells, minimum);
  else
    return WellFinder<S>(c, box, h).bottom(q, wells, minimum);
}
template <Scene S>
double trap_potential(const double* q, const ParamsOf<S, double>& c) {
  if constexpr (requires { S::trap_potential(q, c); }) return S::trap_potential(q, c);
  else return potential<S>(q, c, 0.0);
}

}  // namespace cs
