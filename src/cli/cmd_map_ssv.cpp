// `chatter map CONFIG --ssv-map` (cmd_map_ssv.hpp, docs/ssv.md).
#include "cmd_map_ssv.hpp"

#include <iostream>
#include <vector>

#include "chatter/error.hpp"
#include "chatter/io/config.hpp"
#include "chatter/io/plot_ssv.hpp"
#include "chatter/io/table_writer.hpp"
#include "chatter/report.hpp"
#include "chatter/semi_discretization.hpp"
#include "chatter/ssv_map.hpp"

namespace chatter::cli {
namespace {

constexpr const char* kOnlyWith[] = {"depth-mm", "ssv-amplitude-max", "ssv-amplitude-points",
                                     "ssv-frequency-min", "ssv-frequency-max", "ssv-frequency-points"};
constexpr const char* kNotWith[] = {"rpm-min", "rpm-max",          "rpm-points",       "depth-points",    "json",
                                    "show",    "immersion-min",    "immersion-max",    "immersion-points", "axes"};

std::vector<double> evenly(double lo, double hi, int n) {
  std::vector<double> v;
  for (int i = 0; i < n; ++i) v.push_back(n == 1 ? lo : lo + (hi - lo) * i / (n - 1));
  return v;
}

}  // namespace

void add_ssv_map_options(po::options_description& d) {
  d.add_options()
      ("ssv-map", "map the spindle speed variation instead: spectral radius per revolution over amplitude ratio x "
       "frequency ratio at --rpm and --depth-mm (docs/ssv.md)")
      ("depth-mm", po::value<double>(), "with --ssv-map: the depth of cut, mm (required)")
      ("ssv-amplitude-max", po::value<double>()->default_value(0.3, "0.3"), "with --ssv-map: largest amplitude ratio "
       "R_VA, in (0, 1); the grid runs from 0 (constant speed)")
      ("ssv-amplitude-points", po::value<int>()->default_value(7), "with --ssv-map: amplitude ratios (>= 2)")
      ("ssv-frequency-min", po::value<double>()->default_value(0.05, "0.05"), "with --ssv-map: smallest frequency ratio "
       "R_VF (> 0)")
      ("ssv-frequency-max", po::value<double>()->default_value(0.5), "with --ssv-map: largest frequency ratio "
       "R_VF (>= --ssv-frequency-min)")
      ("ssv-frequency-points", po::value<int>()->default_value(10), "with --ssv-map: frequency ratios (>= 1)");
}

void check_no_ssv_map_options(const po::variables_map& vm) {
  for (const char* o : kOnlyWith)
    if (vm.count(o) && !vm[o].defaulted()) throw InputError(std::string("--") + o + ": only with --ssv-map");
}

int run_ssv_map(const po::variables_map& vm, const Common& common, const std::string& method,
                const std::string& out_arg, const std::string& plot_path) {
  // '-' or nothing else asked: the CSV on standard output.
  const bool to_stdout = out_arg == "-" || (out_arg.empty() && plot_path.empty());
  const std::string out_path = out_arg == "-" ? std::string() : out_arg;
  for (const char* o : kNotWith)
    if (vm.count(o) && !vm[o].defaulted())
      throw InputError(std::string("--") + o + ": not with --ssv-map (it writes the CSV with --out and draws with --plot)");
  if (!vm.count("rpm") || !vm.count("depth-mm")) throw InputError("--ssv-map: needs --rpm and --depth-mm");
  const double rpm = vm["rpm"].as<double>(), depth_mm = vm["depth-mm"].as<double>();
  check_spindle_rpm(rpm, "--rpm");
  check_depth_mm(depth_mm, "--depth-mm");
  const double amax = vm["ssv-amplitude-max"].as<double>(), fmin = vm["ssv-frequency-min"].as<double>(),
               fmax = vm["ssv-frequency-max"].as<double>();
  const int na = vm["ssv-amplitude-points"].as<int>(), nf = vm["ssv-frequency-points"].as<int>();
  if (!(amax > 0.0 && amax < 1.0)) throw InputError("--ssv-amplitude-max = " + fmt(amax) + ": must be in (0, 1)");
  if (na < 2) throw InputError("--ssv-amplitude-points = " + std::to_string(na) + ": must be >= 2");
  if (!(std::isfinite(fmin) && fmin > 0.0)) throw InputError("--ssv-frequency-min = " + fmt(fmin) + ": must be > 0");
  if (!(std::isfinite(fmax) && fmax >= fmin))
    throw InputError("--ssv-frequency-max = " + fmt(fmax) + ": must be >= --ssv-frequency-min (" + fmt(fmin) + ")");
  if (nf < 1) throw InputError("--ssv-frequency-points = " + std::to_string(nf) + ": must be >= 1");
  if (static_cast<long long>(na) * nf > kMaxMapPoints)
    throw InputError("--ssv-amplitude-points x --ssv-frequency-points: at most " + std::to_string(kMaxMapPoints) + " points");
  check_outputs({{"--out", out_path}, {"--plot", plot_path, true}});
  const Config cfg = load_checked(common);
  const BuiltSolver built = build_solver(method, cfg, 2.0 * depth_mm * 1e-3, vm);
  const auto* sdm = dynamic_cast<const SemiDiscretizationSolver*>(built.solver.get());
  if (!sdm) throw InputError("--method " + method + ": this method draws no spectral-radius map");
  SsvMapGrid grid;
  {
    Progress progress(vm, static_cast<std::size_t>(na) * static_cast<std::size_t>(nf), "ssv map (sdm)");
    grid = ssv_stability_map(cfg.model, cfg.process, rpm, depth_mm * 1e-3, evenly(0.0, amax, na),
                             evenly(fmin, fmax, nf), sdm->options(), thread_count(vm),
                             [&](std::size_t done, std::size_t) { progress.tick(done); });
  }
  const std::string csv = ssv_map_csv(grid);
  if (!out_path.empty()) write_text_files({{out_path, csv}});
  if (to_stdout) std::cout << csv;
  std::size_t unstable = 0;
  for (double r : grid.rho_per_revolution) unstable += r >= 1.0 ? 1 : 0;
  std::ostream& info = to_stdout ? std::cerr : std::cout;
  info << cfg.name << " (sdm, speed variation at " << fmt(rpm) << " rev/min, " << fmt(depth_mm) << " mm): " << na
       << " x " << nf << " points, " << unstable << " unstable" << (out_path.empty() ? "" : "; wrote map: " + out_path)
       << "\n";
  if (!plot_path.empty()) {
    const auto pf = plot_ssv_map(plot_path, cfg.name + ": spectral radius per revolution with speed variation (sdm)", grid);
    info << "wrote plot: " << pf.image.string() << " (gnuplot script " << pf.script.string() << ", data "
         << pf.data.string() << ")\n";
  }
  return 0;
}

}  // namespace chatter::cli
