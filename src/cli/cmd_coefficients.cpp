// `chatter coefficients`: cutting coefficients from cutting tests (issue 18).
// The reading, fit, report, record and [process] fragment are
// fit_cutting_coefficients and its records (chatter/records/shop.hpp, shared
// with Python's chatter.coefficients); here: the options, the files and the
// plot. Reference: docs/shop_data.md.
#include <cmath>
#include <filesystem>
#include <functional>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "chatter/error.hpp"
#include "chatter/io/config.hpp"
#include "chatter/io/plot_shop.hpp"
#include "chatter/io/shop_io.hpp"
#include "chatter/io/table_writer.hpp"
#include "chatter/records/shop.hpp"
#include "chatter/shop.hpp"
#include "cli_common.hpp"
#include "commands.hpp"

namespace chatter::cli {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

const char* const kUsage = R"(Usage: chatter coefficients TESTS.csv --teeth N --radial-immersion R --milling-direction down|up [options]
       chatter coefficients TURNING_TESTS.csv [--lead-angle-deg K] [options]

Works out the cutting coefficients of a tool and material from a few test
cuts, for the [process] table of a config. Cut with the same tool, radial
immersion and direction at three or more feeds per tooth (more is better, two
depths help), and write one line per cut in TESTS.csv. The first line names
the columns; pick one way of measuring:

  average forces (dynamometer, averaged over whole revolutions):
    feed_per_tooth_mm,depth_mm,fx_mean_n,fy_mean_n[,fz_mean_n]
  dynamometer recordings, averaged here over whole revolutions:
    feed_per_tooth_mm,depth_mm,spindle_rpm,series
    (series names a CSV time_s,fx_n,fy_n[,fz_n], relative to TESTS.csv)
  net spindle power (cutting power minus idle power at the same speed; gives
  the tangential coefficients only, needs --diameter-mm):
    feed_per_tooth_mm,depth_mm,spindle_rpm,power_w

Axes: X along the feed, Y across it in the cutting plane (as the dynamometer
usually sits: check the signs). The fit is a straight line of average force
against feed: its slope gives the cutting coefficients (N/mm^2), its value at
zero feed the edge (rubbing) coefficients (N/mm). The report gives each with
a 95 % interval, R^2 (1 = perfect; below 0.9 something is off) and each cut's
residual; negative coefficients or a poor R^2 are warned about by name.

Turning (Kienzle's law F = k_1.1 b h^(1-m) per direction, the size effect):
cut at two or more feeds (three or more give standard errors), same insert,
and name the columns
    feed_mm_per_rev,depth_mm,tangential_force_n,feed_force_n[,radial_force_n]
No --teeth, --radial-immersion or --milling-direction then; --lead-angle-deg
if the edge is not perpendicular to the feed. --out writes force_law,
specific_force_n_per_mm2 and exponent for the [process] of a turning config.

Examples:
  chatter coefficients tests.csv --teeth 3 --radial-immersion 0.5 --milling-direction down \
      --out coefficients.toml --plot fit.png
  chatter coefficients power.csv --teeth 4 --radial-immersion 1 --milling-direction down \
      --diameter-mm 16 --json -
  chatter coefficients turning_tests.csv --out kienzle.toml
)";

// Both routes' outputs: the record and the fragment written all or nothing
// (`fragment` is built first: it may refuse), then the report and warnings
// (to standard error when the record goes to standard output). Returns the
// report's stream.
std::ostream& write_fit(const json& j, const std::string& json_path, const std::string& out_path,
                        const std::function<std::string()>& fragment, const std::string& report,
                        const std::vector<std::string>& warnings, const char* wrote) {
  std::vector<std::pair<fs::path, std::string>> files;
  if (!json_path.empty() && json_path != "-") files.emplace_back(json_path, j.dump(2) + "\n");
  if (!out_path.empty()) files.emplace_back(out_path, fragment());
  write_text_files(files);
  std::ostream& os = json_path == "-" ? std::cerr : std::cout;
  os << report;
  for (const auto& w : warnings) os << "warning: " << w << "\n";
  if (json_path == "-") std::cout << j.dump(2) << "\n";
  if (!out_path.empty()) os << "wrote " << wrote << ": " << out_path << "\n";
  return os;
}

// The turning route: Kienzle's law from a table with feed_mm_per_rev.
int kienzle_route(const po::variables_map& vm, const std::string& tests_path, double lead_angle_deg,
                  const std::string& json_path, const std::string& out_path, const std::string& plot_path) {
  for (const char* milling : {"teeth", "radial-immersion", "milling-direction", "diameter-mm"})
    if (vm.count(milling))
      throw InputError(std::string("--") + milling + ": for milling tests; " + tests_path +
                       " holds turning tests (feed_mm_per_rev): Kienzle's law takes --lead-angle-deg only");
  if (!plot_path.empty())
    throw InputError("--plot: drawn for milling tests only; the turning fit's residuals are in the report and --json");
  check_outputs({{"--json", json_path == "-" ? "" : json_path}, {"--out", out_path}});
  const KienzleResult r = fit_kienzle_tests(tests_path, lead_angle_deg, ArgStyle::kFlag);
  write_fit(kienzle_record(r), json_path, out_path, [&] { return kienzle_fragment(r, ArgStyle::kFlag); },
            kienzle_report(r), r.fit.warnings, "[process] keys");
  return 0;
}

}  // namespace

int cmd_coefficients(const std::vector<std::string>& args) {
  std::string tests_path, direction, json_path, out_path, plot_path;
  int teeth = 0;
  double immersion = 0.0, diameter_mm = 0.0, lead_angle_deg = 90.0;
  po::options_description d("Options");
  d.add_options()
      ("teeth", po::value<int>(&teeth), "number of teeth (flutes) of the test cutter (required for milling tests)")
      ("radial-immersion", po::value<double>(&immersion),
       "radial width of cut / tool diameter, in (0, 1]; 1 = slot (required for milling tests)")
      ("milling-direction", po::value<std::string>(&direction),
       "down (climb) or up (conventional) (required for milling tests)")
      ("lead-angle-deg", po::value<double>(&lead_angle_deg),
       "turning tests: the insert's lead angle, deg, in (0, 90]; 90 = edge perpendicular to the feed (default 90)")
      ("diameter-mm", po::value<double>(&diameter_mm), "tool diameter, mm (needed for power tests)")
      ("json", po::value<std::string>(&json_path), "write the result as JSON to this file ('-': standard output, "
                                                  "the report then goes to standard error)")
      ("out", po::value<std::string>(&out_path), "write a [process] table with the coefficients (TOML) for a config")
      ("plot", po::value<std::string>(&plot_path), "draw measured averages against feed with the fitted lines "
                                                  "(.png, .svg or .pdf; script and data beside it)");
  po::options_description hidden;
  hidden.add_options()("tests", po::value<std::string>(&tests_path), "TESTS.csv");
  po::options_description all;
  all.add(d).add(hidden);
  all.add_options()("help,h", "show this help");
  po::positional_options_description pos;
  pos.add("tests", 1);
  po::variables_map vm;
  store_command_line(args, all, pos, vm);
  if (vm.count("help")) {
    std::cout << kUsage << "\n" << d << "  -h [ --help ]            show this help\n";
    return 0;
  }
  if (!vm.count("tests")) throw po::error("missing TESTS.csv (one cutting test per line)");
  po::notify(vm);
  print_flag_warnings(vm, false);
  if (is_turning_tests_table(tests_path))
    return kienzle_route(vm, tests_path, lead_angle_deg, json_path, out_path, plot_path);
  if (vm.count("lead-angle-deg"))
    throw InputError("--lead-angle-deg: for turning tests (a table with feed_mm_per_rev); " + tests_path +
                     " holds milling tests");
  for (const char* needed : {"teeth", "radial-immersion", "milling-direction"})
    if (!vm.count(needed))
      throw po::error(std::string("the option '--") + needed + "' is required but missing (milling tests; a turning "
                      "table names feed_mm_per_rev)");

  // ---- options, all checked before anything is read or written ----
  CoefficientArgs a;
  a.tests = tests_path;
  a.teeth = teeth;
  a.radial_immersion = immersion;
  a.milling_direction = direction;
  if (vm.count("diameter-mm")) a.diameter_mm = diameter_mm;
  coefficient_engagement(a, ArgStyle::kFlag);
  check_outputs({{"--json", json_path == "-" ? "" : json_path}, {"--out", out_path}, {"--plot", plot_path, true}});

  // ---- read and fit ----
  const CoefficientResult r = fit_cutting_coefficients(a, ArgStyle::kFlag);

  // ---- write (all or nothing), then render ----
  std::ostream& os = write_fit(coefficients_record(r), json_path, out_path,
                               [&] { return coefficients_fragment(r, ArgStyle::kFlag); }, coefficients_report(r),
                               r.fit.warnings, "[process] table");
  if (!plot_path.empty()) {
    const PlotFiles pf = plot_coefficient_fit(plot_path, "Cutting coefficients: " + fs::path(tests_path).filename().string(),
                                              r.tests, r.fit, r.engagement, r.diameter_mm * 1e-3);
    os << "wrote plot: " << pf.image.string() << " (gnuplot script " << pf.script.string() << ", data "
       << pf.data.string() << ")\n";
  }
  return 0;
}

}  // namespace chatter::cli
