// The lobe surface a_lim(position, speed) (include/chatter/position.hpp).
#include <utility>

#include "chatter/position.hpp"

namespace chatter {

std::vector<std::vector<StabilityLimit>> lobe_surface(const StructuralModel& base, const PositionDependence& dep,
                                                      const std::vector<double>& positions_m,
                                                      const std::vector<double>& speeds_rpm,
                                                      const SolverFactory& make_solver, unsigned threads,
                                                      const std::function<void(std::size_t done)>& per_position) {
  // Every position checked (and its model built) before the first solve.
  std::vector<StructuralModel> models;
  models.reserve(positions_m.size());
  for (const double x : positions_m) models.push_back(model_at_position(base, dep, x));
  std::vector<std::vector<StabilityLimit>> rows(positions_m.size());
  parallel_for(
      positions_m.size(), threads,
      [&](std::size_t p) {
        const std::unique_ptr<LobeSolver> solver = make_solver(models[p]);
        std::vector<StabilityLimit> row(speeds_rpm.size());
        for (std::size_t s = 0; s < speeds_rpm.size(); ++s) row[s] = solver->limit_at(SpindleSpeed(speeds_rpm[s]));
        rows[p] = std::move(row);
      },
      per_position);
  return rows;
}

}  // namespace chatter
