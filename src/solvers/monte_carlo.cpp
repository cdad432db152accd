// Monte Carlo over uncertain inputs: the depth limits of a range of samples
// (include/chatter/uncertainty.hpp).
#include <string>
#include <utility>

#include "chatter/error.hpp"
#include "chatter/uncertainty.hpp"

namespace chatter {

std::vector<std::vector<StabilityLimit>> monte_carlo_limits(
    const StructuralModel& model, const Process& process, const UncertaintySpreads& spreads, std::uint64_t seed,
    std::uint64_t begin, std::uint64_t end, const std::vector<double>& speeds_rpm, const SampleSolverFactory& make_solver,
    unsigned threads, const std::function<void(std::size_t done)>& per_sample) {
  if (end < begin)
    throw InputError("Monte Carlo samples [" + std::to_string(begin) + ", " + std::to_string(end) +
                     "): end must be >= begin");
  if (const std::string why = spreads.validate(model, process); !why.empty())
    throw InputError("uncertainty spreads: " + why);
  // Every sample's inputs built (and so checked) before the first solve.
  std::vector<UncertainSample> samples;
  samples.reserve(static_cast<std::size_t>(end - begin));
  for (std::uint64_t i = begin; i < end; ++i) samples.push_back(sample_inputs(model, process, spreads, seed, i));
  std::vector<std::vector<StabilityLimit>> rows(samples.size());
  parallel_for(
      samples.size(), threads,
      [&](std::size_t k) {
        const std::unique_ptr<LobeSolver> solver = make_solver(samples[k].model, samples[k].process);
        std::vector<StabilityLimit> row(speeds_rpm.size());
        for (std::size_t s = 0; s < speeds_rpm.size(); ++s) row[s] = solver->limit_at(SpindleSpeed(speeds_rpm[s]));
        rows[k] = std::move(row);
      },
      per_sample);
  return rows;
}

}  // namespace chatter
