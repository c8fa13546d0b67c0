// What the benchmark driver (kernel_bench.cpp) sees of a kernel case, whatever ISA it was
// compiled for: one ISA path's compiled kernel on its own tile of lanes.
#pragma once

#include <cstdint>
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
  // The bits of every lane's state after the last trajectory: the same on every ISA path (and
  // keeps the results observable).
  virtual std::uint64_t checksum() const = 0;
};

// Floating-point operations per lane-step in the compiled step loop, counted with objdump
// (docs/performance.md, "The kernel against its roofline"), by the units that can run them. Multiplies and FMAs need an
// FMA unit on every CPU; adds and subtracts share those units on Intel's 512-bit path but have
// pipes of their own on AMD Zen 4 and 5. So all ops against the FMA peak is the roofline where
// adds share (the model), and the multiplies and FMAs alone the roofline where they do not.
struct StepOps {
  double fma_unit = 0;  // mul, fma
  double add = 0;       // add, sub
  double all() const { return fma_unit + add; }
  bool counted() const { return all() > 0; }
};

struct KernelCase {
  std::string scene, method, state;  // state: "qp" (q, p only) or "full" (q, p, z, ln λ)
  int width;                         // lanes per tile
  StepOps ops;                       // {} = not counted
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
