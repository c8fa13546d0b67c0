// libFuzzer harness for cs::parse_run_spec (GitHub issue 5). Built and run by .ci/fuzz:
//   bash .ci/fuzz [SECONDS]
// Each input is a spec's TOML text plus 0-2 --set overrides, separated by NUL bytes
// (spec_input.hpp). Only a RunSpec or a cs::InputError is accepted; another exception, a failed
// spec_text round trip, a crash, a sanitizer report, a leak, a timeout or running out of memory
// is a finding. A finding goes into tests/fuzz/regressions/ (test_fuzz_regressions.cpp).
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>

#include "spec_input.hpp"

// The parser refuses grids whose coordinates and results exceed the memory budget before it
// fills any axis (memory_budget.hpp). The machine's free memory is far above -rss_limit_mb, so
// the budget is set below it here: a grid the parser accepts fits the fuzzer's memory and its
// time. (This fuzzer first found `q_0 = { from = 0, to = 1, n = 4294963648 }` filling 32 GiB
// before any check; regressions/huge_n_axis_memory holds it. At a budget of 1G it then found
// n = 92238070 accepted: the round trip holds the axis twice, 2 × 738 MB, and filling and
// comparing them under the fuzzer's instrumentation took past its 5 s timeout. 128M keeps an
// accepted axis under 16M points, a fraction of a second; the parser's checks are the same.)
extern "C" int LLVMFuzzerInitialize(int*, char***) {
  setenv("CONTACTSWEEP_MEMORY_LIMIT", "128M", 1);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const cs::fuzz::SpecInput input =
      cs::fuzz::split_input(std::string_view(reinterpret_cast<const char*>(data), size));
  const std::string problem = cs::fuzz::check(input);
  if (!problem.empty()) {
    std::fprintf(stderr, "\n==fuzz_spec_parser== FINDING: %s\n", problem.c_str());
    std::abort();  // libFuzzer writes the input to an artifact file
  }
  return 0;
}
