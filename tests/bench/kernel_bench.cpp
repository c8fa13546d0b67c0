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
//
// Before timing anything it runs every case once on every path this CPU has and compares the
// lanes' final states bit for bit (KernelInstance::checksum): the same bits at any vector width
// is what -ffp-contract=off and std::fma buy (docs/architecture.md). Exit status 1 if a path
// differs.
#include <benchmark/benchmark.h>

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

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

// Every case once on every supported path: true when all paths end in the same bits as the first.
bool same_bits_on_every_path(const IsaPath* paths, const bool* supported, int n) {
  int first = -1, compared = 0, differing = 0;
  for (int i = 0; i < n; ++i)
    if (supported[i] && first < 0) first = i;
  const std::vector<KernelCase> reference = paths[first].cases();
  std::vector<std::uint64_t> expected;
  for (const KernelCase& c : reference) {
    auto kernel = c.make();
    kernel->run_trajectory();
    expected.push_back(kernel->checksum());
  }
  for (int i = first + 1; i < n; ++i) {
    if (!supported[i]) continue;
    const std::vector<KernelCase> cases = paths[i].cases();
    if (cases.size() != reference.size()) {
      std::fprintf(stderr, "kernel_bench: FAIL: %s has %zu cases, %s %zu\n", paths[i].name.c_str(),
                   cases.size(), paths[first].name.c_str(), reference.size());
      return false;
    }
    for (std::size_t k = 0; k < cases.size(); ++k) {
      auto kernel = cases[k].make();
      kernel->run_trajectory();
      ++compared;
      if (kernel->checksum() != expected[k]) {
        ++differing;
        std::fprintf(stderr, "kernel_bench: FAIL: %s/%s/%s/W%d: %s ends in other bits than %s\n",
                     cases[k].scene.c_str(), cases[k].method.c_str(), cases[k].state.c_str(),
                     cases[k].width, paths[i].name.c_str(), paths[first].name.c_str());
      }
    }
  }
  std::fprintf(stderr, "kernel_bench: same bits: %d of %d case runs on other paths equal %s's\n",
               compared - differing, compared, paths[first].name.c_str());
  return differing == 0;
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
  const bool same_bits = same_bits_on_every_path(paths, supported, 4);
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
  return same_bits ? 0 : 1;
}
