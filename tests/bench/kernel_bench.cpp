// The kernel benchmark: lane-steps per second of each scene × method × carried state on each
// ISA path this CPU can run, and the fraction of the FMA roofline it reaches, against an FMA peak
// measured right before each run. One core (the kernel is per-core work; ranks and threads multiply).
//
//   build/tests/bench/kernel_bench [--benchmark_filter=double_well] [--benchmark_repetitions=5]
//
// Counters: lane_steps/s; roofline = lane_steps/s × floating-point ops per lane-step ÷ the path's
// peak (FMAs per second per core, a vector FMA counted once per lane) measured just before, and
// roofline_fma_units the same with multiplies and FMAs alone (kernel_instance.hpp, StepOps).
// jobs/bench_kernel.sh runs it with repetitions and prints the medians as a table.
#include <benchmark/benchmark.h>

#include <cstdio>
#include <string>

#include "kernel_instance.hpp"

namespace cs::bench {
namespace avx2 { IsaPath path(); }
namespace avx512_256 { IsaPath path(); }
namespace avx512 { IsaPath path(); }
namespace native { IsaPath path(); }

namespace {

bool has_avx2() { return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma"); }
bool has_avx512() {
  return has_avx2() && __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
         __builtin_cpu_supports("avx512dq");
}

// The peak is measured again right before each run (50 ms): these machines are shared and their
// clock moves, and a fraction against a peak taken minutes earlier moved with it (66-99 % for the
// same kernel); paired, run and peak see the same clock and the same neighbours.
void run_case(benchmark::State& state, const KernelCase& c, double (*fma_peak)(double)) {
  auto kernel = c.make();
  kernel->run_trajectory();  // warm: tile in cache, pages touched
  const double peak = fma_peak(0.05);
  for (auto _ : state) {
    kernel->run_trajectory();
    benchmark::DoNotOptimize(kernel->checksum());
  }
  const double lane_steps = static_cast<double>(kernel->lane_steps_per_trajectory());
  using benchmark::Counter;
  state.counters["lane_steps/s"] = Counter(lane_steps, Counter::kIsIterationInvariantRate);
  state.counters["peak"] = peak;
  if (c.ops.counted()) {
    state.counters["roofline"] =
        Counter(lane_steps * c.ops.all() / peak, Counter::kIsIterationInvariantRate);
    state.counters["roofline_fma_units"] =
        Counter(lane_steps * c.ops.fma_unit / peak, Counter::kIsIterationInvariantRate);
  }
}

void peak_run(benchmark::State& state, double (*fma_peak)(double)) {
  double peak = 0.0;
  for (auto _ : state) peak = fma_peak(0.05);
  state.counters["peak"] = peak;
}

}  // namespace
}  // namespace cs::bench

int main(int argc, char** argv) {
  using namespace cs::bench;
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  // "native" is the product's build (-march=native): what contactsweep runs on this machine.
  const IsaPath paths[] = {avx2::path(), avx512_256::path(), avx512::path(), native::path()};
  const bool supported[] = {has_avx2(), has_avx512(), has_avx512(), true};
  for (int i = 0; i < 4; ++i) {
    const IsaPath& path = paths[i];
    if (!supported[i]) {
      std::fprintf(stderr, "kernel_bench: this CPU cannot run the %s path; skipped\n",
                   path.name.c_str());
      continue;
    }
    benchmark::RegisterBenchmark(("fma_peak/" + path.name).c_str(), peak_run, path.fma_peak)
        ->Iterations(3);
    for (const KernelCase& c : path.cases()) {
      const std::string name = c.scene + "/" + c.method + "/" + c.state + "/W" +
                               std::to_string(c.width) + "/" + path.name;
      benchmark::RegisterBenchmark(name.c_str(), run_case, c, path.fma_peak)
          ->Unit(benchmark::kMillisecond);
    }
  }
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
