// `chatter coefficients`: cutting coefficients from cutting tests (issue 18).
// Reads TESTS.csv (include/chatter/io/shop_io.hpp), fits K_tc, K_rc, K_te,
// K_re (include/chatter/shop.hpp), prints them with their uncertainty,
// writes JSON, a [process] fragment and a plot. Reference: docs/shop_data.md.
#include <cmath>
#include <filesystem>
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
#include "chatter/shop.hpp"
#include "cli_common.hpp"
#include "commands.hpp"

namespace chatter::cli {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

const char* const kUsage = R"(Usage: chatter coefficients TESTS.csv --teeth N --radial-immersion R --milling-direction down|up [options]

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

Examples:
  chatter coefficients tests.csv --teeth 3 --radial-immersion 0.5 --milling-direction down \
      --out coefficients.toml --plot fit.png
  chatter coefficients power.csv --teeth 4 --radial-immersion 1 --milling-direction down \
      --diameter-mm 16 --json -
)";

json num_or_null(double x) { return std::isfinite(x) ? json(x) : json(nullptr); }

std::string route_name(CoefficientRoute r) {
  switch (r) {
    case CoefficientRoute::kForces: return "average forces";
    case CoefficientRoute::kSeries: return "force series averaged over whole revolutions";
    case CoefficientRoute::kPower: return "net spindle power";
  }
  return "?";
}

}  // namespace

int cmd_coefficients(const std::vector<std::string>& args) {
  std::string tests_path, direction, json_path, out_path, plot_path;
  int teeth = 0;
  double immersion = 0.0, diameter_mm = 0.0;
  po::options_description d("Options");
  d.add_options()
      ("teeth", po::value<int>(&teeth)->required(), "number of teeth (flutes) of the test cutter (required)")
      ("radial-immersion", po::value<double>(&immersion)->required(),
       "radial width of cut / tool diameter, in (0, 1]; 1 = slot (required)")
      ("milling-direction", po::value<std::string>(&direction)->required(), "down (climb) or up (conventional) (required)")
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

  // ---- options, all checked before anything is read or written ----
  MillingEngagement e;
  e.teeth = teeth;
  if (teeth < 1 || teeth > 1000) throw InputError("--teeth = " + std::to_string(teeth) + ": must be in [1, 1000]");
  if (!(immersion > 0.0 && immersion <= 1.0))
    throw InputError("--radial-immersion = " + fmt(immersion) + ": must be in (0, 1] (width of cut / diameter)");
  e.radial_immersion = immersion;
  if (direction == "down" || direction == "climb") e.direction = MillingDirection::kDown;
  else if (direction == "up" || direction == "conventional") e.direction = MillingDirection::kUp;
  else throw InputError("--milling-direction '" + direction + "': use down or up");
  if (vm.count("diameter-mm") && !(std::isfinite(diameter_mm) && diameter_mm > 0.0))
    throw InputError("--diameter-mm = " + fmt(diameter_mm) + ": must be > 0 mm");
  check_outputs({{"--json", json_path == "-" ? "" : json_path}, {"--out", out_path}, {"--plot", plot_path, true}});

  // ---- read and fit ----
  const CoefficientTests tests = read_coefficient_tests(tests_path);
  const bool power = tests.route == CoefficientRoute::kPower;
  if (power && !vm.count("diameter-mm"))
    throw InputError(tests_path + ": power tests need the tool diameter: give --diameter-mm");
  if (power && !out_path.empty())
    throw InputError("--out: " + tests_path + " holds power tests, which give the tangential coefficients only; a "
                     "[process] table needs the radial coefficient too: measure forces, or write the table by hand");
  CoefficientFit fit;
  try {
    fit = power ? fit_coefficients_from_power(tests.power, e, diameter_mm * 1e-3)
                : fit_coefficients_from_forces(tests.forces, e);
  } catch (const InputError& err) {
    throw InputError(tests_path + ": " + err.what());
  }

  // ---- report ----
  std::ostringstream rep;
  const char* names[4] = {"tangential_coefficient", "radial_coefficient", "tangential_edge_coefficient",
                          "radial_edge_coefficient"};
  const double vals[4] = {fit.tangential_coefficient_n_per_m2, fit.radial_coefficient_n_per_m2,
                          fit.tangential_edge_coefficient_n_per_m, fit.radial_edge_coefficient_n_per_m};
  const double to_shop[4] = {1e-6, 1e-6, 1e-3, 1e-3};  // N/m^2 -> N/mm^2, N/m -> N/mm
  const char* shop_unit[4] = {"N/mm^2", "N/mm^2", "N/mm", "N/mm"};
  rep << tests_path << ": " << tests.line.size() << " tests (" << route_name(tests.route) << "), " << teeth
      << " teeth, radial immersion " << fmt(immersion) << ", " << (e.direction == MillingDirection::kDown ? "down" : "up")
      << "-milling\n";
  for (int i = 0; i < 4; ++i) {
    if (!std::isfinite(vals[i])) continue;
    char line[200];
    std::snprintf(line, sizeof line, "  %-28s %12.5g %-7s +- %.3g (95 %%)\n", names[i], vals[i] * to_shop[i],
                  shop_unit[i], fit.confidence_95[i] * to_shop[i]);
    rep << line;
  }
  rep << "  R^2 = " << fmt(fit.r_squared, 6);
  if (!power) rep << " (fx " << fmt(fit.r_squared_x, 6) << ", fy " << fmt(fit.r_squared_y, 6) << ")";
  rep << ", " << fit.degrees_of_freedom << " degrees of freedom\n  residuals (measured - fitted) per test:\n";
  for (std::size_t i = 0; i < tests.line.size(); ++i) {
    rep << "    line " << tests.line[i] << ": ";
    if (power) rep << fmt(fit.residual_x_n[i], 4) << " W\n";
    else rep << "fx " << fmt(fit.residual_x_n[i], 4) << " N, fy " << fmt(fit.residual_y_n[i], 4) << " N\n";
  }

  json j;
  j["tests_file"] = tests_path;
  j["route"] = power ? "power" : tests.route == CoefficientRoute::kSeries ? "series" : "forces";
  j["teeth"] = teeth;
  j["radial_immersion"] = immersion;
  j["milling_direction"] = e.direction == MillingDirection::kDown ? "down" : "up";
  j["tangential_coefficient_n_per_m2"] = fit.tangential_coefficient_n_per_m2;
  j["radial_coefficient_n_per_m2"] = num_or_null(fit.radial_coefficient_n_per_m2);
  j["tangential_edge_coefficient_n_per_m"] = fit.tangential_edge_coefficient_n_per_m;
  j["radial_edge_coefficient_n_per_m"] = num_or_null(fit.radial_edge_coefficient_n_per_m);
  const char* keys[4] = {"tangential_coefficient_n_per_m2", "radial_coefficient_n_per_m2",
                         "tangential_edge_coefficient_n_per_m", "radial_edge_coefficient_n_per_m"};
  for (int i = 0; i < 4; ++i) {
    j["standard_error"][keys[i]] = num_or_null(fit.standard_error[i]);
    j["confidence_95"][keys[i]] = num_or_null(fit.confidence_95[i]);
  }
  j["degrees_of_freedom"] = fit.degrees_of_freedom;
  j["r_squared"] = fit.r_squared;
  j["r_squared_fx"] = num_or_null(fit.r_squared_x);
  j["r_squared_fy"] = num_or_null(fit.r_squared_y);
  json res = json::array();
  for (std::size_t i = 0; i < tests.line.size(); ++i) {
    json t;
    t["line"] = tests.line[i];
    if (power) {
      t["feed_per_tooth_mm"] = tests.power[i].feed_per_tooth_m * 1e3;
      t["depth_mm"] = tests.power[i].depth_m * 1e3;
      t["power_w"] = tests.power[i].power_w;
      t["residual_power_w"] = fit.residual_x_n[i];
    } else {
      t["feed_per_tooth_mm"] = tests.forces[i].feed_per_tooth_m * 1e3;
      t["depth_mm"] = tests.forces[i].depth_m * 1e3;
      t["fx_mean_n"] = tests.forces[i].fx_mean_n;
      t["fy_mean_n"] = tests.forces[i].fy_mean_n;
      t["residual_fx_n"] = fit.residual_x_n[i];
      t["residual_fy_n"] = fit.residual_y_n[i];
      if (tests.route == CoefficientRoute::kSeries) {
        t["series"] = tests.series_file[i];
        t["revolutions_averaged"] = tests.series_average[i].revolutions;
      }
    }
    res.push_back(t);
  }
  j["tests"] = res;
  j["warnings"] = fit.warnings;

  // ---- write (all or nothing), then render ----
  std::vector<std::pair<fs::path, std::string>> files;
  if (!json_path.empty() && json_path != "-") files.emplace_back(json_path, j.dump(2) + "\n");
  if (!out_path.empty()) {
    std::ostringstream t;
    t << "# Cutting coefficients fitted by `chatter coefficients` (chatter " << version() << ") from " << tests_path
      << ":\n# " << tests.line.size() << " tests, R^2 = " << fmt(fit.r_squared, 6)
      << ". Append modes ([[tool.modes]], e.g. from `chatter fit`) to make a config.\n"
      << "# Edge (rubbing) coefficients, not used by the stability model:\n"
      << "#   tangential_edge_coefficient_n_per_m = " << table_number(fit.tangential_edge_coefficient_n_per_m)
      << "\n#   radial_edge_coefficient_n_per_m = " << table_number(fit.radial_edge_coefficient_n_per_m) << "\n"
      << "[process]\noperation = \"milling\"\nteeth = " << teeth << "\n"
      << "tangential_coefficient_n_per_m2 = " << table_number(fit.tangential_coefficient_n_per_m2) << "   # +- "
      << table_number(fit.confidence_95[0]) << " (95 %)\n"
      << "radial_coefficient_n_per_m2 = " << table_number(fit.radial_coefficient_n_per_m2) << "   # +- "
      << table_number(fit.confidence_95[1]) << " (95 %)\n"
      << "radial_immersion = " << table_number(immersion) << "\n"
      << "milling_direction = \"" << (e.direction == MillingDirection::kDown ? "down" : "up") << "\"\n";
    if (!(fit.tangential_coefficient_n_per_m2 > 0.0) || fit.radial_coefficient_n_per_m2 < 0.0)
      throw InputError("--out: the fitted coefficients (K_tc = " + fmt(fit.tangential_coefficient_n_per_m2) +
                       ", K_rc = " + fmt(fit.radial_coefficient_n_per_m2) +
                       " N/m^2) are not a valid [process] table (K_tc > 0, K_rc >= 0): check the tests");
    files.emplace_back(out_path, t.str());
  }
  write_text_files(files);
  std::ostream& os = json_path == "-" ? std::cerr : std::cout;
  os << rep.str();
  for (const auto& w : fit.warnings) os << "warning: " << w << "\n";
  if (json_path == "-") std::cout << j.dump(2) << "\n";
  if (!out_path.empty()) os << "wrote [process] table: " << out_path << "\n";
  if (!plot_path.empty()) {
    const PlotFiles pf = plot_coefficient_fit(plot_path, "Cutting coefficients: " + fs::path(tests_path).filename().string(),
                                              tests, fit, e, diameter_mm * 1e-3);
    os << "wrote plot: " << pf.image.string() << " (gnuplot script " << pf.script.string() << ", data "
       << pf.data.string() << ")\n";
  }
  return 0;
}

}  // namespace chatter::cli
