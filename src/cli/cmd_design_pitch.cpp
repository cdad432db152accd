// `chatter design-pitch`: the pitch angles of a variable-pitch cutter that
// maximise the worst depth limit over a band of spindle speeds, from
// Budak's design rule polished with sdm (docs/design_pitch.md). The work:
// design_pitch (ops, chatter/pitch_design.hpp); the arguments, record, table
// and fragment: chatter/records/pitch.hpp.
#include <filesystem>
#include <iostream>
#include <numbers>
#include <sstream>

#include <nlohmann/json.hpp>

#include "chatter/error.hpp"
#include "chatter/io/plot_pitch.hpp"
#include "chatter/io/table_writer.hpp"
#include "chatter/records/pitch.hpp"
#include "chatter/solvers.hpp"
#include "cli_common.hpp"
#include "commands.hpp"

namespace chatter::cli {

namespace {

constexpr std::size_t kProgressSteps = 1000;

// design-pitch's usage text.
const char* const kDesignPitchUsage =
    "Usage: chatter design-pitch CONFIG --rpm-min R1 --rpm-max R2 [--teeth N] [options]\n\n"
    "Designs the pitch angles of a variable-pitch milling cutter that maximise the\n"
    "worst (smallest) depth limit over the spindle speeds [R1, R2]. Start: Budak's\n"
    "rule, the step dP = 360 n / (60 N f_c) deg (linear family) that cancels the\n"
    "regeneration of the teeth at the equal-pitch cutter's worst speed n and chatter\n"
    "frequency f_c; then a scan of dP over its range and Brent's maximiser, every\n"
    "limit by sdm (or --method analytic). The config gives the equal-pitch cutter\n"
    "(no pitch_angles_deg), the structure and the cut.\n"
    "Output: the summary (angles, worst limits equal vs designed, gain, the rule) on\n"
    "standard output; --table, --json, --plot and --out (the config fragment) add\n"
    "files. docs/design_pitch.md explains the rule, the search and the numbers.\n"
    "Exit status: 0 a design was made, 2 bad input or usage, 1 internal failure.\n";

}  // namespace

int cmd_design_pitch(const std::vector<std::string>& args) {
  Common common;
  std::string table_path, json_path, plot_path, out_path, family = "linear";
  po::options_description d("Options");
  d.add_options()
      ("rpm-min", po::value<double>(), "lowest spindle speed of the band, rev/min (required)")
      ("rpm-max", po::value<double>(), "highest spindle speed of the band, rev/min (required, > --rpm-min)")
      ("teeth", po::value<int>(), "number of teeth, >= 2: must be the config's process.teeth (a check that the "
                                  "cutter is the one meant; default: the config's)")
      ("rpm-points", po::value<int>()->default_value(kDefaultPitchBandPoints),
       "evenly spaced speeds of the band (both ends included), in [2, 100000]: the worst limit is the smallest "
       "over them")
      ("depth-max-mm", po::value<double>(), "deepest cut searched, mm (default: sweep.depth_max_mm or 50)")
      ("family", po::value<std::string>(&family)->default_value("linear"),
       "the pitch family: 'linear' (theta_j = 360/N + (j - (N-1)/2) dP) or 'alternating' (360/N +/- dP/2, even N)")
      ("min-pitch-ratio", po::value<double>()->default_value(kDefaultMinPitchRatio, "0.5"),
       "every pitch angle >= this x 360/N, in [0.1, 1) (bounds dP)")
      ("scan-points", po::value<int>()->default_value(kDefaultPitchScanPoints),
       "steps dP scanned evenly over the family's range besides the rule, in [0, 200] (each costs one band)")
      ("table", po::value<std::string>(&table_path),
       "write spindle_rpm,depth_limit_equal_mm,depth_limit_designed_mm here ('-': standard output)")
      ("json", po::value<std::string>(&json_path),
       "write the record as JSON here ('-': standard output, the summary then goes to standard error)")
      ("plot", po::value<std::string>(&plot_path),
       "draw both cutters' limits over the band to this .png, .svg or .pdf (gnuplot script and data beside it)")
      ("out", po::value<std::string>(&out_path),
       "write the [process] fragment 'pitch_angles_deg = [...]' of the designed cutter here")
      ("progress", "show the progress even when standard error is not a terminal: one line a second");
  add_common(d, common);
  add_solver_options(d);
  po::variables_map vm;
  if (!parse(args, kDesignPitchUsage, d, common, vm)) return 0;
  const bool json_to_stdout = json_path == "-", table_to_stdout = table_path == "-";
  if (json_to_stdout && table_to_stdout)
    throw InputError("--table - and --json -: only one of them can go to standard output");
  if (json_to_stdout) json_path.clear();
  if (table_to_stdout) table_path.clear();
  check_outputs({{"--table", table_path}, {"--json", json_path}, {"--plot", plot_path, true}, {"--out", out_path}});
  const Config cfg = load_checked(common);
  PitchDesignArgs a;
  if (vm.count("rpm-min")) a.rpm_min = vm["rpm-min"].as<double>();
  if (vm.count("rpm-max")) a.rpm_max = vm["rpm-max"].as<double>();
  if (vm.count("teeth")) a.teeth = vm["teeth"].as<int>();
  a.rpm_points = vm["rpm-points"].as<int>();
  if (vm.count("depth-max-mm")) a.depth_max_mm = vm["depth-max-mm"].as<double>();
  a.family = family;
  a.min_pitch_ratio = vm["min-pitch-ratio"].as<double>();
  a.scan_points = vm["scan-points"].as<int>();
  a.method = common.method;
  a.threads = thread_count(vm);
  PitchDesignOptions o = pitch_design_options(cfg, a, ArgStyle::kFlag);
  check_solver_options({o.method}, vm, "--method");
  o.solver_options = solver_option_values(find_lobe_method(o.method), cfg, vm);
  PitchDesign design;
  {
    Progress bar(vm, kProgressSteps, "design-pitch", 1.0);
    o.progress = [&](double f) { bar.tick(static_cast<std::size_t>(f * kProgressSteps)); };
    design = run_pitch_design(cfg, o, ArgStyle::kFlag);
  }

  const std::string csv = pitch_design_csv(design);
  const std::string json_text = json_path.empty() && !json_to_stdout
                                    ? std::string()
                                    : pitch_design_record(design, o, record_source(cfg)).dump(2) + "\n";
  std::vector<std::pair<std::filesystem::path, std::string>> files;
  if (!table_path.empty()) files.emplace_back(table_path, csv);
  if (!json_path.empty()) files.emplace_back(json_path, json_text);
  if (!out_path.empty()) files.emplace_back(out_path, pitch_design_fragment(design, cfg.name));
  write_text_files(files);
  if (json_to_stdout) std::cout << json_text;
  if (table_to_stdout) std::cout << csv;
  std::ostream& info = json_to_stdout || table_to_stdout ? std::cerr : std::cout;
  info << pitch_design_summary(design);
  if (!out_path.empty()) info << "wrote [process] fragment: " << out_path << "\n";
  if (!plot_path.empty()) {
    std::ostringstream label;
    label.precision(4);
    for (std::size_t j = 0; j < design.designed.angles_rad.size(); ++j)
      label << (j ? "/" : "") << design.designed.angles_rad[j] * 180.0 / std::numbers::pi;
    label << " deg";
    const auto plot = plot_pitch_design(plot_path, cfg.name + ": equal vs designed pitch (" + design.method + ")",
                                        design.equal.limits, design.designed.limits, label.str(), o.depth_max_m);
    info << "wrote plot: " << plot.image.string() << " (gnuplot script " << plot.script.string() << ", data "
         << plot.data.string() << ")\n";
  }
  return 0;
}

}  // namespace chatter::cli
