// `chatter detect`: chatter found in a recording of the cut and the classic
// speed correction (issue 18), optionally checked against the model with the
// sdm solver. Reads audio or CSV (include/chatter/io/shop_io.hpp), analyses
// with detect_chatter (include/chatter/shop.hpp). Reference: docs/shop_data.md.
#include <cmath>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "chatter/error.hpp"
#include "chatter/io/plot_shop.hpp"
#include "chatter/io/shop_io.hpp"
#include "chatter/io/table_writer.hpp"
#include "chatter/report.hpp"
#include "chatter/shop.hpp"
#include "chatter/solvers.hpp"
#include "cli_common.hpp"
#include "commands.hpp"

namespace chatter::cli {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// The sdm check searches depths up to this multiple of --depth-mm: a margin
// above it is reported as "at least" this much.
constexpr double kCheckDepthFactor = 4.0;

const char* const kUsage = R"(Usage: chatter detect RECORDING --rpm N --teeth N_t [options]

Listens to a recording of a cut (microphone or accelerometer) and says whether
it chattered, at which frequency, and which spindle speeds should cure it.

RECORDING: a WAV, FLAC or AIFF file (any sample rate; with several channels
pick one with --channel, default 1), or a CSV with time_s,value per line
(uniformly sampled). Record a few seconds of steady cutting: at least 5
spindle revolutions, better 50 or more.

What it does: the spectrum of the recording holds the tooth-passing frequency
(rpm x teeth / 60) and its multiples, and the spindle frequency (rpm / 60) and
its multiples (runout): all forced by the cut, not chatter. The strongest line
that is none of them is the chatter candidate. It is called chatter when it is
at least 0.25 x the strongest forced line (peak ratio) and 20 x above the noise
floor (the median of the spectrum). The report also says how that line grew
over the recording and when it started.

Speed correction: a tooth-passing multiple placed on the chatter frequency,
  N_k = 60 x f_chatter / (teeth x k),  k = 1, 2, ...
inside [--rpm-min, --rpm-max] (default: the config's [sweep] with --config,
else 0.5x to 1.5x the current speed),
nearest to the current speed first. With --config and --depth-mm each speed
is also checked against the model (sdm stability limit at that speed), and
carries its margin = depth limit / depth (above 1: stable).

The recording must show the tooth-passing line of --rpm and --teeth (within
+/-2 %, or its second harmonic): otherwise the speed is probably wrong and
nothing is judged (exit 2, with the speeds the strongest line implies);
--force analyses it anyway. A chatter line present from the first moment at
a steady level gets a warning (chatter grows; a steady line is more likely
forced, or an input error).

Exit status: 0 no chatter, 3 chatter, 2 bad input (nothing written).

Examples:
  chatter detect cut.wav --rpm 9000 --teeth 3
  chatter detect cut.flac --rpm 12000 --teeth 2 --channel 2 --plot spectrum.png --json result.json
  chatter detect cut.wav --rpm 18000 --teeth 2 --config mill.toml --depth-mm 1.5 --rpm-min 10000 --rpm-max 24000
)";

json num_or_null(double x) { return std::isfinite(x) ? json(x) : json(nullptr); }

}  // namespace

int cmd_detect(const std::vector<std::string>& args) {
  std::string rec_path, json_path, plot_path, config_path;
  double rpm = 0.0, rpm_min = 0.0, rpm_max = 0.0, depth_mm = 0.0, ratio = 0.25;
  int teeth = 0, channel = 1;
  po::options_description d("Options");
  d.add_options()
      ("rpm", po::value<double>(&rpm)->required(), "spindle speed during the recording, rev/min (required)")
      ("teeth", po::value<int>(&teeth)->required(), "number of teeth (flutes) of the cutter; 1 for turning (required)")
      ("rpm-min", po::value<double>(&rpm_min), "lowest speed to suggest, rev/min (default 0.5 x --rpm)")
      ("rpm-max", po::value<double>(&rpm_max), "highest speed to suggest, rev/min (default 1.5 x --rpm)")
      ("channel", po::value<int>(&channel)->default_value(1), "channel of a multi-channel recording, from 1")
      ("peak-ratio", po::value<double>(&ratio)->default_value(0.25, "0.25"),
       "chatter when the candidate line is at least this fraction of the strongest forced line")
      ("json", po::value<std::string>(&json_path), "write the result as JSON to this file ('-': standard output, "
                                                  "the report then goes to standard error)")
      ("plot", po::value<std::string>(&plot_path), "draw the spectrum with the harmonics marked and the chatter "
                                                  "line labelled (.png, .svg or .pdf)")
      ("config", po::value<std::string>(&config_path), "a config of this machine and tool: check each suggested "
                                                      "speed against the model (needs --depth-mm)")
      ("depth-mm", po::value<double>(&depth_mm), "depth of cut to check the suggestions at, mm (with --config)")
      ("force", "analyse the recording even when it holds no line at the tooth-passing frequency of --rpm and "
                "--teeth (by default that is refused: the speed or the teeth are probably wrong)");
  po::options_description hidden;
  hidden.add_options()("recording", po::value<std::string>(&rec_path), "RECORDING");
  po::options_description all;
  all.add(d).add(hidden);
  all.add_options()("help,h", "show this help");
  po::positional_options_description pos;
  pos.add("recording", 1);
  po::variables_map vm;
  store_command_line(args, all, pos, vm);
  if (vm.count("help")) {
    std::cout << kUsage << "\n" << d << "  -h [ --help ]            show this help\n";
    return 0;
  }
  if (!vm.count("recording")) throw po::error("missing RECORDING (a .wav, .flac, .aiff or .csv file)");
  po::notify(vm);

  // ---- options, all checked before anything is read or written ----
  check_spindle_rpm(rpm, "--rpm");
  if (teeth < 1 || teeth > 1000) throw InputError("--teeth = " + std::to_string(teeth) + ": must be in [1, 1000]");
  if (vm.count("rpm-min") && !(std::isfinite(rpm_min) && rpm_min > 0.0))
    throw InputError("--rpm-min = " + fmt(rpm_min) + ": must be > 0 rev/min");
  if (!(std::isfinite(ratio) && ratio > 0.0)) throw InputError("--peak-ratio = " + fmt(ratio) + ": must be > 0");
  if (vm.count("config") != vm.count("depth-mm"))
    throw InputError(vm.count("config") ? "--config: give --depth-mm too (the depth to check the speeds at)"
                                        : "--depth-mm: give --config too (the model to check the speeds against)");
  if (vm.count("depth-mm") && !(std::isfinite(depth_mm) && depth_mm > 0.0 && depth_mm <= 1000.0))
    throw InputError("--depth-mm = " + fmt(depth_mm) + ": must be in (0, 1000] mm");
  check_outputs({{"--json", json_path == "-" ? "" : json_path}, {"--plot", plot_path, true}});  // before computing
  std::optional<Config> cfg;
  if (!config_path.empty()) {
    Common c;
    c.config_path = config_path;
    cfg = load_checked(c);
    if (cfg->process.delays_per_revolution() != teeth)
      throw InputError(config_path + ": the process has " + std::to_string(cfg->process.delays_per_revolution()) +
                       " delay period(s) per revolution (teeth; 1 for turning) but --teeth = " + std::to_string(teeth));
  }
  // The speeds to suggest: the flags, else the config's [sweep] (the
  // machine this config describes), else 0.5x to 1.5x the current speed.
  if (!vm.count("rpm-min")) rpm_min = cfg && cfg->sweep.rpm_min ? *cfg->sweep.rpm_min : 0.5 * rpm;
  if (!vm.count("rpm-max")) rpm_max = cfg && cfg->sweep.rpm_max ? *cfg->sweep.rpm_max : 1.5 * rpm;
  if (!(std::isfinite(rpm_max) && rpm_max > rpm_min))
    throw InputError("--rpm-max = " + fmt(rpm_max) + ": must be > --rpm-min (" + fmt(rpm_min) + ")");

  // ---- read and analyse ----
  const Recording rec = read_recording(rec_path, channel);
  DetectOptions o;
  o.spindle_rpm = rpm;
  o.teeth = teeth;
  o.rpm_min = rpm_min;
  o.rpm_max = rpm_max;
  o.peak_ratio_threshold = ratio;
  ChatterDetection det;
  try {
    det = detect_chatter(rec.samples, rec.sample_rate_hz, o);
  } catch (const InputError& e) {
    throw InputError(rec_path + ": " + e.what());
  }
  // A recording without the tooth-passing line of the given speed is the
  // wrong speed (or teeth): refuse to judge it rather than cry wolf.
  if (!det.tooth_passing_found && !vm.count("force")) {
    std::string implied;
    for (std::size_t k = 0; k < det.implied_rpm.size(); ++k)
      implied += (k == 0 ? "the tooth passing at " : k == 1 ? ", its 2nd harmonic at " : ", its 3rd at ") +
                 fmt(std::round(det.implied_rpm[k])) + " rev/min";
    throw InputError(rec_path + ": no line stands within +/-2 % of the tooth-passing frequency " +
                     fmt(rpm * teeth / 60.0) + " Hz (--rpm " + fmt(rpm) + " x --teeth " + std::to_string(teeth) +
                     " / 60) or its second harmonic: is --rpm (or --teeth) right? The strongest line, " +
                     fmt(det.strongest_line_hz) + " Hz, would be " + implied +
                     ". --force analyses the recording anyway.");
  }
  if (!det.tooth_passing_found)
    det.warnings.push_back("no line stands at the tooth-passing frequency of --rpm and --teeth (analysed anyway: "
                           "--force); the verdict assumes a speed the recording does not show");

  // ---- the model's view of each suggestion ----
  struct Checked {
    double limit_mm = NAN, margin = NAN;
    bool bounded = false;
  };
  std::vector<Checked> checked(det.suggestions.size());
  double depth_max_m = 0.0;
  if (cfg) {
    depth_max_m = kCheckDepthFactor * depth_mm * 1e-3;
    const auto solver = make_lobe_solver("sdm", cfg->model, cfg->process, depth_max_m);
    for (std::size_t i = 0; i < det.suggestions.size(); ++i) {
      const StabilityLimit l = solver->limit_at(det.suggestions[i].spindle_rpm);
      checked[i].bounded = l.bounded();
      checked[i].limit_mm = l.depth_limit_m * 1e3;
      checked[i].margin = l.depth_limit_m / (depth_mm * 1e-3);
    }
  }

  // ---- report ----
  std::ostringstream rep;
  rep << rec_path << ": " << rec.format << ", " << fmt(rec.sample_rate_hz) << " Hz, " << fmt(det.duration_s) << " s, channel "
      << rec.channel << " of " << rec.channels << "\n"
      << "  tooth passing " << fmt(det.tooth_passing_hz) << " Hz (spindle " << fmt(det.spindle_hz) << " Hz), resolution "
      << fmt(det.frequency_resolution_hz, 3) << " Hz\n";
  if (std::isfinite(det.candidate_frequency_hz))
    rep << "  strongest other line " << fmt(det.candidate_frequency_hz) << " Hz: " << fmt(det.peak_ratio, 3)
        << " x the strongest forced line (chatter from " << fmt(ratio, 3) << "), " << fmt(det.prominence, 3)
        << " x the noise floor (from 20), grew " << fmt(det.growth_ratio, 3) << " x over the recording\n";
  if (det.chatter) {
    rep << "CHATTER at " << fmt(det.chatter_frequency_hz) << " Hz";
    if (std::isfinite(det.onset_s)) rep << ", from about " << fmt(det.onset_s, 3) << " s";
    rep << "\n";
    if (det.suggestions.empty())
      rep << "  no speed N_k = 60 f_c / (teeth k) lies in " << fmt(rpm_min) << "-" << fmt(rpm_max) << " rev/min\n";
    else
      rep << "  try (nearest first), rev/min:\n";
    for (std::size_t i = 0; i < det.suggestions.size(); ++i) {
      rep << "    " << fmt(std::round(det.suggestions[i].spindle_rpm)) << "  (k = " << det.suggestions[i].k << ")";
      if (cfg) {
        if (checked[i].bounded)
          rep << "  model: depth limit " << fmt(checked[i].limit_mm, 4) << " mm, margin " << fmt(checked[i].margin, 3)
              << (checked[i].margin > 1 ? "" : "  (chatters in the model at this depth)");
        else
          rep << "  model: stable to " << fmt(depth_max_m * 1e3, 4) << " mm, margin > " << fmt(kCheckDepthFactor, 3);
      }
      rep << "\n";
    }
  } else {
    rep << "no chatter\n";
  }

  json j;
  j["recording"] = rec_path;
  j["format"] = rec.format;
  j["sample_rate_hz"] = rec.sample_rate_hz;
  j["duration_s"] = det.duration_s;
  j["channel"] = rec.channel;
  j["channels"] = rec.channels;
  j["spindle_rpm"] = rpm;
  j["teeth"] = teeth;
  j["chatter"] = det.chatter;
  j["chatter_frequency_hz"] = num_or_null(det.chatter_frequency_hz);
  j["tooth_passing_hz"] = det.tooth_passing_hz;
  j["spindle_hz"] = det.spindle_hz;
  j["tooth_passing_found"] = det.tooth_passing_found;
  j["strongest_line_hz"] = num_or_null(det.strongest_line_hz);
  j["implied_rpm"] = det.implied_rpm;
  json sug = json::array(), full = json::array();
  for (std::size_t i = 0; i < det.suggestions.size(); ++i) {
    sug.push_back(det.suggestions[i].spindle_rpm);
    json s{{"rpm", det.suggestions[i].spindle_rpm}, {"k", det.suggestions[i].k}};
    if (cfg) {
      s["depth_limit_mm"] = checked[i].bounded ? json(checked[i].limit_mm) : json(nullptr);
      s["margin"] = checked[i].bounded ? json(checked[i].margin) : json(nullptr);
      if (!checked[i].bounded) s["margin_at_least"] = kCheckDepthFactor;
      s["stable_in_model"] = !checked[i].bounded || checked[i].margin > 1.0;
    }
    full.push_back(s);
  }
  j["suggested_rpm"] = sug;
  j["suggestions"] = full;
  j["rpm_min"] = rpm_min;
  j["rpm_max"] = rpm_max;
  if (cfg) {
    j["config"] = cfg->name;
    j["depth_mm"] = depth_mm;
    j["check_method"] = "sdm";
  }
  j["evidence"] = {{"measure", "chatter when the strongest line that is no spindle or tooth-passing harmonic has "
                               "peak_ratio >= peak_ratio_threshold and prominence >= prominence_threshold"},
                   {"candidate_frequency_hz", num_or_null(det.candidate_frequency_hz)},
                   {"peak_ratio", num_or_null(det.peak_ratio)},
                   {"peak_ratio_threshold", ratio},
                   {"prominence", num_or_null(det.prominence)},
                   {"prominence_threshold", o.prominence_threshold},
                   {"growth_ratio", num_or_null(det.growth_ratio)},
                   {"onset_s", num_or_null(det.onset_s)},
                   {"frequency_resolution_hz", det.frequency_resolution_hz}};
  json peaks = json::array();
  for (const auto& p : det.peaks)
    peaks.push_back({{"frequency_hz", p.frequency_hz}, {"amplitude", p.amplitude}, {"kind", p.kind}, {"harmonic", p.harmonic}});
  j["peaks"] = peaks;
  j["warnings"] = det.warnings;

  // ---- write, then render ----
  if (!json_path.empty() && json_path != "-") write_text_file(json_path, j.dump(2) + "\n");
  std::ostream& os = json_path == "-" ? std::cerr : std::cout;
  os << rep.str();
  for (const auto& w : det.warnings) os << "warning: " << w << "\n";
  if (json_path == "-") std::cout << j.dump(2) << "\n";
  if (!plot_path.empty()) {
    const PlotFiles pf = plot_detection(plot_path, "Spectrum: " + fs::path(rec_path).filename().string() + " at " +
                                                       fmt(rpm) + " rev/min, " + std::to_string(teeth) + " teeth",
                                        det);
    os << "wrote plot: " << pf.image.string() << " (gnuplot script " << pf.script.string() << ", data "
       << pf.data.string() << ")\n";
  }
  return det.chatter ? 3 : 0;
}

}  // namespace chatter::cli
