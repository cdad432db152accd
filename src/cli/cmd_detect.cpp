// `chatter detect`: chatter found in a recording of the cut and the classic
// speed correction (issue 18), optionally checked against the model with the
// sdm solver. The reading, analysis, checks, report and record are
// detect_recording and its records (chatter/records/shop.hpp, shared with
// Python's chatter.detect); here: the options, the files and the plot.
// Reference: docs/shop_data.md.
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
#include "chatter/records/shop.hpp"
#include "chatter/report.hpp"
#include "chatter/shop.hpp"
#include "chatter/solvers.hpp"
#include "cli_common.hpp"
#include "commands.hpp"

namespace chatter::cli {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

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
  print_flag_warnings(vm, false);

  // ---- options, all checked before anything is read or written ----
  DetectArgs a;
  a.recording = rec_path;
  a.rpm = rpm;
  a.teeth = teeth;
  if (vm.count("rpm-min")) a.rpm_min = rpm_min;
  if (vm.count("rpm-max")) a.rpm_max = rpm_max;
  a.channel = channel;
  a.peak_ratio = ratio;
  if (vm.count("depth-mm")) a.depth_mm = depth_mm;
  a.force = vm.count("force") > 0;
  std::optional<Config> cfg;
  Config placeholder;  // stands for --config in the argument checks until the file is read
  a.config = vm.count("config") ? &placeholder : nullptr;
  check_detect_args(a, ArgStyle::kFlag);
  check_outputs({{"--json", json_path == "-" ? "" : json_path}, {"--plot", plot_path, true}});  // before computing
  if (!config_path.empty()) {
    Common c;
    c.config_path = config_path;
    cfg = load_checked(c);
    a.config = &*cfg;
  }

  // ---- read, analyse and check against the model ----
  const DetectResult r = detect_recording(a, ArgStyle::kFlag);
  const json j = detect_record(r);

  // ---- write, then render ----
  if (!json_path.empty() && json_path != "-") write_text_file(json_path, j.dump(2) + "\n");
  std::ostream& os = json_path == "-" ? std::cerr : std::cout;
  os << detect_report(r);
  for (const auto& w : r.detection.warnings) os << "warning: " << w << "\n";
  if (json_path == "-") std::cout << j.dump(2) << "\n";
  if (!plot_path.empty()) {
    const PlotFiles pf = plot_detection(plot_path, "Spectrum: " + fs::path(rec_path).filename().string() + " at " +
                                                       fmt(rpm) + " rev/min, " + std::to_string(teeth) + " teeth",
                                        r.detection);
    os << "wrote plot: " << pf.image.string() << " (gnuplot script " << pf.script.string() << ", data "
       << pf.data.string() << ")\n";
  }
  return r.detection.chatter ? 3 : 0;
}

}  // namespace chatter::cli
