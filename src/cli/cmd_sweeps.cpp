// `chatter lobes` and `chatter surface` in one process: the plans and writers
// shared with chatter-mpi (cmd_lobes.cpp, cmd_surface.cpp), with the live
// window of --show, which only the `chatter` executable links (live_plot.hpp).
#include <iostream>
#include <optional>

#include "cmd_lobes.hpp"
#include "cmd_surface.hpp"
#include "commands.hpp"
#include "live_plot.hpp"

namespace chatter::cli {

int cmd_lobes(const std::vector<std::string>& args) {
  const std::optional<LobesPlan> plan = plan_lobes(args);
  if (!plan) return 0;
  const NominalTable nominal = lobes_nominal(*plan, plan->threads);
  std::vector<std::vector<StabilityLimit>> samples;
  if (plan->uncertainty) {
    Progress progress(plan->vm, plan->uncertainty->samples, "Monte Carlo (" + plan->common.method + ")");
    samples = lobes_samples(*plan, 0, plan->uncertainty->samples, plan->threads,
                            [&](std::size_t done) { progress.tick(done); });
  }
  if (!plan->show.requested) return write_lobes(*plan, nominal, samples);
  int status = 0;
  {
    LiveWindow window(plan->show);
    status = write_lobes(*plan, nominal, samples, &window);
  }  // gnuplot has drawn
  report_shown(plan->table_to_stdout || plan->json_to_stdout ? std::cerr : std::cout, plan->show);
  return status;
}

int cmd_surface(const std::vector<std::string>& args) {
  const std::optional<SurfacePlan> plan = plan_surface(args);
  if (!plan) return 0;
  const auto rows = surface_rows(*plan);
  if (!plan->show.requested) return write_surface(*plan, rows);
  int status = 0;
  {
    LiveWindow window(plan->show);
    status = write_surface(*plan, rows, &window);
  }
  report_shown(plan->table_to_stdout ? std::cerr : std::cout, plan->show);
  return status;
}

}  // namespace chatter::cli
