// A kernel benchmark case: a tile of W lanes of scene S advanced by Method exactly as the block
// runner advances its main tile (engine/lane_tile.hpp's advance, chunks of 32 steps), with the
// runner's screen, refill and output left out: the step loop alone.
//
// Included by kernel_isa.cpp, which is compiled once per ISA path with that path's -m flags and
// CS_BENCH_ISA naming its namespace. Everything here is flattened into the ISA's own functions:
// template code shared between translation units (COMDAT) would otherwise be linked from
// whichever ISA's object came first, and could run AVX-512 code on an AVX2 machine.
#pragma once

#include <cstdint>
#include <cstring>
#include <memory>

#include "engine/lane_tile.hpp"
#include "kernel_instance.hpp"

namespace cs::bench::CS_BENCH_ISA {

// Lane i's coordinate k spread over [-3, 3] like a basin map's grid (a fixed lattice: every ISA
// integrates the same points).
inline double lattice(int i, int w, int k) {
  const double u = static_cast<double>((i * (2 * k + 7) + 3 * k) % w) / (w - 1);
  return -3.0 + 6.0 * u;
}

template <Scene S, class Method, Carry carry, int W>
class TiledCase final : public KernelInstance {
  using Tile = LaneTile<S, Method, W>;
  using Params = ParamsOf<S, double>;
  using Coef = typename Method::template Coef<double>;

 public:
  [[gnu::flatten]] TiledCase(const Params& params, double h, int steps, int chunk)
      : tile_(std::make_unique<Tile>()), initial_(std::make_unique<Tile>()), params_(params),
        h_(h), steps_(steps), chunk_(chunk) {
    Tile& t = *initial_;
    std::memset(static_cast<void*>(&t), 0, sizeof(Tile));
    for (int i = 0; i < W; ++i) {
      LaneState<S::dof> x{};
      for (int d = 0; d < S::dof; ++d) {
        x.q[d] = lattice(i, W, 2 * d);
        x.p[d] = 0.5 * lattice(i, W, 2 * d + 1);
      }
      x.z = 1.0;
      Method::template start<S>(x, params_);
      coef_ = Method::template coefficients<S>(h_, params_, x);
      t.set_lane(i, x);
      t.set_parameters(i, params_, coef_);
    }
    std::memcpy(static_cast<void*>(tile_.get()), initial_.get(), sizeof(Tile));
  }

  [[gnu::flatten]] void run_trajectory() override {
    Tile& t = *tile_;
    for (int done = 0; done < steps_; done += chunk_) {
      kernel_chunk(t, chunk_, params_, coef_, h_);
      for (int i = 0; i < W; ++i) t.steps_done[i] += chunk_;
    }
    hash_ = state_hash(t);
    std::memcpy(static_cast<void*>(tile_.get()), initial_.get(), sizeof(Tile));
  }

  long lane_steps_per_trajectory() const override { return static_cast<long>(W) * steps_; }

  std::uint64_t checksum() const override { return hash_; }

 private:
  // FNV-1a over the bits of every lane's whole state: any lane differing in any bit of q, p, z,
  // ln λ's parts or its breakdown flag changes it.
  static std::uint64_t state_hash(const Tile& t) {
    std::uint64_t h = 1469598103934665603ull;
    auto mix = [&h](const double* v) {
      for (int i = 0; i < W; ++i) {
        std::uint64_t bits;
        std::memcpy(&bits, &v[i], sizeof bits);
        h = (h ^ bits) * 1099511628211ull;
      }
    };
    for (int d = 0; d < S::dof; ++d) mix(t.q[d]), mix(t.p[d]);
    for (const double* v :
         {t.z, t.mu, t.lambda_numerator, t.lambda_denominator, t.lambda_folds, t.broken})
      mix(v);
    return h;
  }

  [[gnu::noinline, gnu::flatten]] static void kernel_chunk(Tile& t, int steps, const Params& c,
                                                           const Coef& k, double h) {
    advance<S, Method, carry, true>(t, steps, c, k, 0.0, h, [](int) {});
  }

  std::unique_ptr<Tile> tile_, initial_;
  Params params_;
  Coef coef_{};
  double h_;
  std::uint64_t hash_ = 0;
  int steps_, chunk_;
};

}  // namespace cs::bench::CS_BENCH_ISA
