// `chatter lobes --samples N` (src/cli/cmd_uncertainty.hpp, docs/uncertainty.md).
#include "cmd_uncertainty.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include <nlohmann/json.hpp>

#include "chatter/solvers.hpp"

namespace chatter::cli {
namespace {

/// The most limits held in memory: samples × speeds (each StabilityLimit is
/// 32 bytes, so 2.5e7 is 0.8 GB); a larger study is split into ranges
/// (monte_carlo_limits) by a runner that reduces as it goes.
constexpr long long kMaxMonteCarloSolves = 25'000'000;
constexpr int kDefaultDepthPoints = 101;  // steps of 1 % of the grid's top

}  // namespace

void add_uncertainty_options(po::options_description& d) {
  d.add_options()
      ("samples", po::value<long long>(), "Monte Carlo over the config's [uncertainty] spreads: solve this many "
                                          "sampled models (> 0); adds the 5/50/95 % quantile lobes to the table "
                                          "(depth_limit_p05_mm, _p50_mm, _p95_mm) and draws the probability of "
                                          "stability (docs/uncertainty.md)")
      ("seed", po::value<long long>(), "with --samples: the random seed (integer >= 0; default 1); the same seed "
                                       "gives the same table whatever --threads")
      ("depth-points", po::value<int>(), "with --samples: depths of the probability grid, from 0 to the top of the "
                                         "plot's depth axis (--plot-depth-max-mm, or 1.2 x the deepest finite limit of "
                                         "any sample rounded up to 2 digits), both included (>= 2; default 101)")
      ("probability-table", po::value<std::string>(), "with --samples: write the probability of stability as CSV "
                                                      "spindle_rpm,depth_mm,probability_stable");
}

std::optional<UncertaintyRequest> uncertainty_request(const po::variables_map& vm, bool adaptive, int rpm_points) {
  if (!vm.count("samples")) {
    for (const char* flag : {"seed", "depth-points", "probability-table"})
      if (vm.count(flag))
        throw InputError(std::string("--") + flag + ": only with --samples N (the Monte Carlo it configures)");
    return std::nullopt;
  }
  UncertaintyRequest r;
  const long long n = vm["samples"].as<long long>();
  if (n < 1) throw InputError("--samples = " + std::to_string(n) + ": must be >= 1");
  if (n > kMaxMonteCarloSolves || n * static_cast<long long>(std::max(rpm_points, 1)) > kMaxMonteCarloSolves)
    throw InputError("--samples x --rpm-points = " + std::to_string(n) + " x " + std::to_string(rpm_points) +
                     ": at most " + std::to_string(kMaxMonteCarloSolves) +
                     " limits are held in memory (32 bytes each); use fewer samples or speeds");
  r.samples = static_cast<std::uint64_t>(n);
  if (vm.count("seed")) {
    const long long seed = vm["seed"].as<long long>();
    if (seed < 0) throw InputError("--seed = " + std::to_string(seed) + ": must be an integer >= 0");
    r.seed = static_cast<std::uint64_t>(seed);
  }
  if (vm.count("depth-points")) {
    r.depth_points = vm["depth-points"].as<int>();
    if (r.depth_points < 2 || r.depth_points > 10000)
      throw InputError("--depth-points = " + std::to_string(r.depth_points) + ": must be in [2, 10000]");
  } else {
    r.depth_points = kDefaultDepthPoints;
  }
  if (static_cast<long long>(r.depth_points) * rpm_points > kMaxMapPoints)
    throw InputError("--rpm-points x --depth-points = " + std::to_string(rpm_points) + " x " +
                     std::to_string(r.depth_points) + ": at most " + std::to_string(kMaxMapPoints) + " grid points");
  if (adaptive) throw InputError("--samples: only with --rpm-spacing even (every sample is solved at the same speeds)");
  if (vm.count("probability-table")) {
    r.probability_table = vm["probability-table"].as<std::string>();
    if (r.probability_table.empty() || r.probability_table == "-")
      throw InputError("--probability-table: give a file name");
  }
  return r;
}

void check_uncertainty_config(const Config& cfg) {
  if (!cfg.uncertainty)
    throw InputError("--samples: " + cfg.source.string() +
                     ": no [uncertainty] table (give the 1-sigma spreads in percent; docs/config.md)");
  if (const std::string why = cfg.uncertainty->validate(cfg.model, cfg.process); !why.empty())
    throw InputError(cfg.source.string() + ": uncertainty: " + why);
}

std::vector<std::vector<StabilityLimit>> sample_limits(const UncertaintyRequest& request, const Config& cfg,
                                                       const std::string& method, double depth_max_mm,
                                                       const po::variables_map& vm, const std::vector<double>& speeds,
                                                       std::uint64_t begin, std::uint64_t end, unsigned threads,
                                                       const std::function<void(std::size_t)>& per_sample) {
  check_uncertainty_config(cfg);
  const double depth_max_m = depth_max_mm * 1e-3;
  const SolverRecipe recipe{method, solver_option_values(find_lobe_method(method), cfg, vm)};
  const SampleSolverFactory factory = [&](const StructuralModel& model, const Process& process) {
    return recipe.build(model, process, depth_max_m);
  };
  return with_flag("--samples", [&] {
    return monte_carlo_limits(cfg.model, cfg.process, *cfg.uncertainty, request.seed, begin, end, speeds, factory,
                              threads, per_sample);
  });
}

UncertaintyOutputs reduce_uncertainty(const UncertaintyRequest& request, double depth_max_mm,
                                      const po::variables_map& vm, const std::vector<double>& speeds,
                                      const std::vector<StabilityLimit>& nominal,
                                      const std::vector<std::vector<StabilityLimit>>& rows) {
  UncertaintyOutputs out;
  // The probability grid: 0 to the plot's depth axis (given, or 1.2 x the
  // deepest finite limit of any sample, at most the searched depth).
  std::optional<double> given_top;
  if (vm.count("plot-depth-max-mm")) given_top = vm["plot-depth-max-mm"].as<double>();
  const ProbabilityDepthGrid grid = probability_depth_grid(rows, depth_max_mm, request.depth_points, given_top);
  out.depth_grid_top_mm = grid.top_mm;
  const std::vector<double>& depths_m = grid.depths_m;
  out.lobes = reduce_monte_carlo(rows, depths_m,
                                 std::vector<double>(std::begin(kUncertaintyLevels), std::end(kUncertaintyLevels)));

  for (std::size_t l = 0; l < out.lobes.levels.size(); ++l) {
    ExtraColumn c;
    c.name = quantile_column_name(out.lobes.levels[l]);
    c.numeric = true;
    for (const double v : out.lobes.quantile_depth_m[l]) c.values.push_back(table_number(v * 1e3));
    out.columns.push_back(std::move(c));
  }
  std::ostringstream csv;
  csv << "spindle_rpm,depth_mm,probability_stable\n";
  for (std::size_t s = 0; s < speeds.size(); ++s)
    for (std::size_t d = 0; d < depths_m.size(); ++d)
      csv << table_number(speeds[s]) << ',' << table_number(depths_m[d] * 1e3) << ','
          << table_number(out.lobes.probability_stable[s][d]) << '\n';
  out.probability_csv = csv.str();

  // The speed whose 5 % quantile (95 % of samples stable below it) is deepest.
  const std::vector<double>& p05 = out.lobes.quantile_depth_m.front();
  std::size_t best = 0;
  for (std::size_t s = 1; s < p05.size(); ++s)
    if (p05[s] > p05[best]) best = s;
  auto depth_text = [&](double m) {
    return std::isfinite(m) ? fmt(m * 1e3, 5) + " mm" : "the searched depth (" + fmt(depth_max_mm) + " mm)";
  };
  std::ostringstream summary;
  summary << "uncertainty (" << request.samples << " samples, seed " << request.seed << "): 95 % of samples stable below "
          << depth_text(p05[best]) << " at " << fmt(speeds[best]) << " rev/min (nominal there: "
          << depth_text(nominal[best].depth_limit_m) << "; 50 %: " << depth_text(out.lobes.quantile_depth_m[1][best])
          << ")";
  out.summary = summary.str();
  return out;
}

}  // namespace chatter::cli
