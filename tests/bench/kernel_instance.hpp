// What the benchmark driver (kernel_bench.cpp) sees of a kernel case, whatever ISA it was
// compiled for: one ISA path's compiled kernel on its own tile of lanes.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace cs::bench {

class KernelInstance {
 public:
  virtual ~KernelInstance() = default;
  // Advances every lane through one whole trajectory (in chunks, as the block runner does), then
  // puts the initial states back: the benchmark repeats real trajectories, so values stay in the
  // range a run sees (no decay into subnormals over millions of steps).
  virtual void run_trajectory() = 0;
  virtual long lane_steps_per_trajectory() const = 0;
  virtual double checksum() const = 0;  // keeps the results observable
};

struct KernelCase {
  std::string scene, method, state;  // state: "qp" (q, p only) or "full" (q, p, z, ln λ)
  int width;                         // lanes per tile
  // Floating-point operations per lane-step that occupy the FMA pipes (add, sub, mul, fma, min,
  // max: one each), counted in the compiled step loop (README, "Benchmarks"); 0 = not counted.
  double fma_pipe_ops;
  std::function<std::unique_ptr<KernelInstance>()> make;
};

// One ISA path: its cases and its measured FMA peak, compiled with its own -m flags.
struct IsaPath {
  std::string name;
  int vector_lanes;  // doubles per vector register the path uses
  std::vector<KernelCase> (*cases)();
  // Fused multiply-adds per second, counted per double lane, on one core: `vector_lanes` times
  // the rate of independent vector FMAs (enough in flight to cover their latency).
  double (*fma_peak)(double seconds);
};

const std::vector<IsaPath>& isa_paths();

}  // namespace cs::bench
