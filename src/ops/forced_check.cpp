// The forced vibration of one checked operation (include/chatter/operations.hpp,
// forced_check; issue 27, docs/forced.md): the row's process, speed, depth
// and feed through ForcedResponseSolver, and the part's tolerance.
#include <cmath>
#include <limits>

#include "chatter/forced.hpp"
#include "chatter/operations.hpp"
#include "ops_internal.hpp"

namespace chatter {

std::optional<OperationForced> forced_check(const StructuralModel& model, const Process& base,
                                            const OperationRow& row) {
  if (!row.feed_per_tooth_m) return std::nullopt;
  const Process p = process_for(base, row);
  const ForcedResponseSolver solver(model, p);
  ForcedSettings st;
  st.spindle_rpm = row.spindle_rpm;
  st.depth_m = row.depth_m;
  st.feed_m = *row.feed_per_tooth_m;
  st.record_path = false;
  OperationForced out;
  out.response = solver.response(st);
  const ForcedResponse& r = out.response;
  out.part_error_m = detail::ops::part_error_m(r);
  if (r.stable) out.within_tolerance = !row.max_error_m || out.part_error_m <= *row.max_error_m;
  return out;
}

}  // namespace chatter
