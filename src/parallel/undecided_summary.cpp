#include "parallel/undecided_summary.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cstdint>

#include "engine/recurrence/recurrence_search.hpp"
#include "mpi/comm.hpp"

namespace cs {

std::string undecided_reasons(const RunPlan& whole, std::vector<std::int64_t> counts,
                              RefusedLanes refused, MPI_Comm comm) {
  // Every rank has the same table, hence refused points or none: all or none reduce.
  if (!refused.points.empty()) allreduce(comm, &refused.lanes, 1, MPI_INT64_T, MPI_SUM);
  if (whole.map.undecided_reason < 0 && refused.lanes == 0) return "";
  if (whole.map.undecided_reason >= 0)
    allreduce(comm, counts.data(), kUndecidedReasons, MPI_INT64_T, MPI_SUM);
  static const char* const what[kUndecidedReasons] = {
      "settled on no attractor in the table",
      "no recurrence by t_end (a longer t_end, larger cells: measures.basin.cell_size, or fewer "
      "measures.basin.recurrences)",
      "recurred but not located by t_end (a longer t_end or fewer measures.basin.locate)",
      "left the box (a larger measures.basin.box; it is the grid's range widened by half)",
      "visited measures.basin.max_cells cells without recurring (larger cells or a larger "
      "max_cells)",
      "diverged or failed (see status)",
      "not looked at by the recurrence mapper: the energy trap's lanes that stopped on an "
      "unstable equilibrium"};
  std::int64_t total = 0;
  std::vector<std::string> parts;
  for (int r = 0; r < kUndecidedReasons; ++r) {
    if (counts[r] == 0) continue;
    total += counts[r];
    parts.push_back(fmt::format("{} {}", counts[r], what[r]));
  }
  if (refused.lanes > 0) {
    total += refused.lanes;
    parts.push_back(fmt::format(
        "{} settled on an unstable fixed point, refused as an attractor: its exact lambda_1 "
        "(K's Jacobian) is positive: {}",
        refused.lanes, refused.points));
  }
  if (total == 0) return "";  // nothing to explain: the file stays as it was without the mapper
  std::string text = fmt::format("{} cells: {}", total, fmt::join(parts, "; "));
  if (whole.recurrence.period_on_autonomous)
    text +=
        "; measures.basin.period is given but K does not depend on t: the system is "
        "autonomous, and its samples one period apart meet a limit cycle at another phase "
        "each time (no cycle of the stroboscopic map): leave period out to sample at every "
        "look";
  return text;
}

}  // namespace cs
