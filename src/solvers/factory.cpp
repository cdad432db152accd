#include <algorithm>

#include "chatter/error.hpp"
#include "chatter/solvers.hpp"
#include "chatter/semi_discretization.hpp"
#include "chatter/time_domain.hpp"
#include "chatter/transfer_function.hpp"

namespace chatter {

std::vector<std::string> lobe_methods() { return {"analytic", "coupled", "sdm", "time-domain"}; }

bool has_lobe_method(const std::string& method) {
  const auto m = lobe_methods();
  return std::find(m.begin(), m.end(), method) != m.end();
}

std::unique_ptr<LobeSolver> make_lobe_solver(const std::string& method, const StructuralModel& model,
                                             const Process& process, double depth_max_m) {
  if (method == "analytic" || method == "coupled") {
    TransferFunctionOptions o;
    o.depth_max_m = depth_max_m;
    return make_transfer_function_solver(method, model, process, o);
  }
  if (method == "sdm") {
    SemiDiscretizationOptions o;
    o.depth_max_m = depth_max_m;
    return std::make_unique<SemiDiscretizationSolver>(model, process, o);
  }
  if (method == "time-domain") {
    TimeDomainOptions o;
    o.depth_max_m = depth_max_m;
    return std::make_unique<TimeDomainSolver>(model, process, o);
  }
  std::string known;
  for (const auto& m : lobe_methods()) known += (known.empty() ? "" : ", ") + m;
  throw InputError("--method " + method + ": unknown method (this build has: " + known + ")");
}

}  // namespace chatter
