// chatter simulate: one time-domain run (include/chatter/time_domain.hpp),
// its verdict as JSON on stdout, the series / once-per-period samples /
// spectrum as CSV files, and a plot.
#include <algorithm>
#include <cmath>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "cli_common.hpp"
#include "commands.hpp"
#include "live_plot.hpp"
#include "chatter/error.hpp"
#include "chatter/io/plot.hpp"
#include "chatter/io/table_writer.hpp"
#include "chatter/records.hpp"
#include "chatter/report.hpp"
#include "chatter/time_domain.hpp"

namespace chatter::cli {

namespace {

// Size (MB) of a series file above which simulate warns (a 50 MB CSV is
// about 400 000 samples: more than a spreadsheet or a plot wants).
constexpr double kSeriesWarnMb = 50.0;

// Every `every`-th sample (the first included).
void write_series_csv(std::ostream& os, const std::vector<SeriesSample>& rows, int every = 1) {
  os << "time_s,tool_x_um,tool_y_um,workpiece_x_um,workpiece_y_um,rel_x_um,rel_y_um,force_x_n,force_y_n,chip_um,in_cut\n";
  for (std::size_t i = 0; i < rows.size(); i += static_cast<std::size_t>(every)) {
    const SeriesSample& r = rows[i];
    os << table_number(r.t_s) << ',' << table_number(r.tool_x_m * 1e6) << ',' << table_number(r.tool_y_m * 1e6) << ','
       << table_number(r.workpiece_x_m * 1e6) << ',' << table_number(r.workpiece_y_m * 1e6) << ','
       << table_number(r.rel_x_m * 1e6) << ',' << table_number(r.rel_y_m * 1e6) << ',' << table_number(r.force_x_n)
       << ',' << table_number(r.force_y_n) << ',' << table_number(r.chip_m * 1e6) << ',' << (r.in_cut ? 1 : 0) << '\n';
  }
}

// The files simulate writes: --out (every out_every-th sample, warned above
// warn_mb), --periodic, --spectrum.
struct SimulationTables {
  std::string out_path, periodic_path, spectrum_path;
  int out_every = 1;
  double warn_mb = kSeriesWarnMb;
};
std::vector<std::pair<std::filesystem::path, std::string>> simulation_tables(const SimulationResult& r,
                                                                             const SimulationTables& t) {
  const std::string& out_path = t.out_path;
  const std::string& periodic_path = t.periodic_path;
  const std::string& spectrum_path = t.spectrum_path;
  const int out_every = t.out_every;
  const double warn_mb = t.warn_mb;
  std::vector<std::pair<std::filesystem::path, std::string>> files;
  if (!out_path.empty()) {
    std::ostringstream os;
    write_series_csv(os, r.series, out_every);
    files.emplace_back(out_path, os.str());
    const double mb = static_cast<double>(files.back().second.size()) / 1e6;
    if (mb > warn_mb) {
      const double suggest = std::ceil(mb / warn_mb) * out_every;
      std::cerr << "warning: --out " << out_path << ": the time series is " << fmt(mb, 3) << " MB ("
                << (r.series.size() + static_cast<std::size_t>(out_every) - 1) / static_cast<std::size_t>(out_every)
                << " samples), above " << fmt(warn_mb, 3) << " MB; --out-every " << fmt(suggest, 6)
                << " writes it under that (or use --periodic for one sample per period)\n";
    }
  }
  if (!periodic_path.empty()) {
    std::ostringstream os;
    write_series_csv(os, r.once_per_period);
    files.emplace_back(periodic_path, os.str());
  }
  if (!spectrum_path.empty()) {
    std::ostringstream os;
    os << "frequency_hz,amplitude_um,harmonic\n";
    const std::vector<int> harmonic = spectrum_harmonics(r);
    for (std::size_t k = 0; k < r.spectrum_hz.size(); ++k)
      os << table_number(r.spectrum_hz[k]) << ',' << table_number(r.spectrum_amplitude_m[k] * 1e6) << ','
         << (harmonic[k] > 0 ? std::to_string(harmonic[k]) : std::string("")) << '\n';
    files.emplace_back(spectrum_path, os.str());
  }
  return files;
}

// Delay periods to simulate: --periods, --revolutions converted, or the
// default (200 delay periods).
int simulation_periods(const po::variables_map& vm, const Process& process, double rpm, bool linear, int revolutions,
                       int periods) {
  if (vm.count("revolutions") && vm.count("periods")) throw InputError("--revolutions and --periods: give one of them");
  if (vm.count("revolutions")) {
    if (revolutions < 1 || revolutions > 1000000)
      throw InputError("--revolutions = " + std::to_string(revolutions) + ": must be in [1, 1000000]");
    periods = simulation_periods_in_revolutions(process, rpm, linear, revolutions);
  } else if (!vm.count("periods")) {
    periods = default_simulation_periods(process, rpm, linear);
  }
  if (periods < 4 || periods > 10000000)
    throw InputError("--periods = " + std::to_string(periods) + ": must be in [4, 10000000]");
  return periods;
}

// simulate's options, into the caller's variables.
void describe_simulate(po::options_description& d, double& rpm, double& depth_mm, double& feed_mm, double& rtol,
                       int& revolutions, int& periods, SimulationTables& tables, std::string& plot_path) {
  std::string& out_path = tables.out_path;
  int& out_every = tables.out_every;
  double& warn_mb = tables.warn_mb;
  d.add_options()
      ("rpm", po::value<double>(&rpm)->required(), "spindle speed, rev/min (required)")
      ("depth-mm", po::value<double>(&depth_mm)->required(), "depth of cut, mm (required; axial depth in milling)")
      ("revolutions", po::value<int>(&revolutions), "spindle revolutions to simulate (default: enough for 200 delay "
                                                    "periods: 200 in turning, 200 / teeth in milling; with speed "
                                                    "variation the whole principal periods that hold them, >= 20)")
      ("periods", po::value<int>(&periods), "delay periods (tooth periods in milling; principal periods with speed "
                                            "variation) to simulate, instead of --revolutions")
      ("feed-per-tooth-mm", po::value<double>(&feed_mm), "feed per tooth (milling) or per revolution (turning), mm "
                                                         "(default: [process] feed_per_tooth_mm / feed_per_rev_mm, "
                                                         "else 0.1)")
      ("linear", "linear delay equation: no static chip, the tool never leaves the cut, start from a 1 um "
                 "displacement; reports the growth factor per period (compare with sdm's spectral radius)")
      ("linear-forced", "linear delay equation with the static chip (the feed; the tool never leaves the cut): the "
                        "run converges to the forced response of chatter forced, which it cross-checks")
      ("multiple-regeneration", "cut the chip from the surface left by all earlier passes, not only the last one")
      ("fail-on-chatter", "exit with status 3 when the verdict is chatter (for scripts: 0 stable, 3 chatter, 2 bad "
                          "input)")
      ("rtol", po::value<double>(&rtol)->default_value(1e-7, "1e-7"), "integrator relative tolerance (1e-12 .. 1e-2)")
      ("out", po::value<std::string>(&out_path), "write the time series (CSV: time, tool/workpiece/relative "
                                                 "displacement in um, force in N, chip in um, in-cut flag)")
      ("out-every", po::value<int>(&out_every)->default_value(1), "with --out: write every N-th sample of the "
                                                                  "series (N >= 1; the first sample always)")
      ("warn-size-mb", po::value<double>(&warn_mb)->default_value(kSeriesWarnMb, "50"),
       "warn on standard error when the --out file is larger than this, MB (> 0)")
      ("periodic", po::value<std::string>(&tables.periodic_path), "write the once-per-period samples (CSV, same columns)")
      ("spectrum", po::value<std::string>(&tables.spectrum_path), "write the spectrum of the relative displacement (CSV: "
                                                           "frequency_hz, amplitude_um, harmonic)")
      ("plot", po::value<std::string>(&plot_path), "draw displacement, force and spectrum (.png, .svg or .pdf)");
  add_show_option(d);
  add_speed_variation_options(d);
}

// simulate's usage text.
const char* const kSimulateUsage =
    "Usage: chatter simulate CONFIG --rpm R --depth-mm D [options]\n\n"
    "Simulates the cut in time (modal equations with the real chip: the tool may leave\n"
    "the cut) and says whether it chatters. Prints one JSON object: verdict (stable or\n"
    "chatter) and the measure it rests on, growth_per_period (|mu|, < 1 decays),\n"
    "chatter_frequency_hz, max_amplitude_mm, out_of_cut_fraction, the tooth-passing\n"
    "harmonics and the integrator's cost. The last half of the run is analysed.\n"
    "--show draws the run while it integrates (the window is redrawn after every tenth\n"
    "of the periods), then its spectrum and verdict.\n\n"
    "Example:\n"
    "  chatter simulate configs/milling_benchmark_ae005_down.toml --rpm 17000 --depth-mm 4 \\\n"
    "      --out series.csv --plot sim.png\n";

}  // namespace

int cmd_simulate(const std::vector<std::string>& args) {
  Common common;
  common.method = "time-domain";
  double rpm = 0.0, depth_mm = 0.0, feed_mm = 0.1, rtol = 1e-7;
  int revolutions = 0, periods = 0;
  SimulationTables tables;
  std::string& out_path = tables.out_path;
  std::string plot_path;
  int& out_every = tables.out_every;
  double& warn_mb = tables.warn_mb;
  po::options_description d("Options");
  describe_simulate(d, rpm, depth_mm, feed_mm, rtol, revolutions, periods, tables, plot_path);
  po::variables_map vm;
  if (!parse(args, kSimulateUsage, d, common, vm)) return 0;
  check_outputs({{"--out", out_path}, {"--periodic", tables.periodic_path}, {"--spectrum", tables.spectrum_path},
                 {"--plot", plot_path, true}});  // before computing
  const ShowRequest show = show_request(vm);  // a display or GNUPLOT_TERM, before computing
  if (out_every < 1) throw InputError("--out-every = " + std::to_string(out_every) + ": must be >= 1");
  if (!vm["out-every"].defaulted() && out_path.empty())
    throw InputError("--out-every: only with --out (it thins the time series written there)");
  if (!(std::isfinite(warn_mb) && warn_mb > 0.0)) throw InputError("--warn-size-mb = " + fmt(warn_mb) + ": must be > 0");
  Config cfg = load_checked(common);
  apply_speed_variation_options(vm, common, cfg);
  if (!vm.count("feed-per-tooth-mm")) feed_mm = cfg.feed_mm.value_or(0.1);
  check_spindle_rpm(rpm, "--rpm");
  check_depth_mm(depth_mm, "--depth-mm", /*allow_zero=*/true);
  if (!(std::isfinite(feed_mm) && feed_mm >= 0.0 && feed_mm <= 100.0))
    throw InputError("--feed-per-tooth-mm = " + fmt(feed_mm) + ": must be in [0, 100] mm");
  if (vm.count("linear") && vm.count("linear-forced"))
    throw InputError("--linear and --linear-forced: give one of them (--linear-forced is linear with the feed)");
  periods = simulation_periods(vm, cfg.process, rpm, vm.count("linear") > 0, revolutions, periods);
  TimeDomainOptions o;
  if (!(rtol >= 1e-12 && rtol <= 1e-2)) throw InputError("--rtol = " + fmt(rtol) + ": must be in [1e-12, 1e-2]");
  o.relative_tolerance = rtol;
  TimeDomainSimulator sim(cfg.model, cfg.process, o);
  SimulationSettings st;
  st.spindle_rpm = rpm;
  st.depth_m = depth_mm * 1e-3;
  st.periods = periods;
  st.feed_m = feed_mm * 1e-3;
  st.linear = vm.count("linear") > 0 || vm.count("linear-forced") > 0;
  st.linear_static_chip = vm.count("linear-forced") > 0;
  st.multiple_regeneration = vm.count("multiple-regeneration") > 0;
  st.record_series = !out_path.empty() || !plot_path.empty() || show.requested;
  double f_max = 0.0;  // the spectrum of the plots reaches 2.5 x the highest natural frequency
  for (const Body* b : {&cfg.model.tool, &cfg.model.workpiece})
    for (const Mode& m : b->modes) f_max = std::max(f_max, m.natural_frequency_hz);
  std::ostringstream title_text;
  title_text << cfg.name << ", " << fmt(rpm) << " rev/min, " << fmt(depth_mm) << " mm" << (st.linear ? " (linear)" : "");
  const std::string title = title_text.str();
  std::optional<LiveWindow> window;
  if (show.requested) {
    // The run as it integrates: redrawn after every tenth of the periods.
    window.emplace(show);
    const int every = std::max(1, (periods + 9) / 10);
    st.on_period = [&, every](const SimulationResult& so_far) {
      const std::size_t done = so_far.once_per_period.size() - 1;
      if (done % static_cast<std::size_t>(every) == 0 && done < static_cast<std::size_t>(periods) &&
          so_far.series.size() >= 2)
        plot_simulation(*window, title, so_far, f_max, /*running=*/true);
    };
  }
  sim.require_chip(st);  // a cut with no chip is refused, not judged (docs/results.md)
  const SimulationResult r = sim.simulate(st);

  nlohmann::json j = simulation_record(r, simulation_request(st, cfg.process, rtol, depth_mm, feed_mm),
                                       record_source(cfg, common.position_mm));
  if (!r.linear_limit_warning.empty()) std::cerr << "warning: " << r.linear_limit_warning << "\n";

  const auto files = simulation_tables(r, tables);
  if (!files.empty()) write_text_files(files);
  if (window) {
    plot_simulation(*window, title, r, f_max, /*running=*/false);
    window.reset();  // gnuplot has drawn
  }
  if (!plot_path.empty()) {
    try {
      const PlotFiles pf = plot_simulation(plot_path, title, r, f_max);
      j["plot"] = pf.image.string();
    } catch (const GnuplotNotFound& e) {
      // The numbers are still printed and the tables written.
      std::cout << j.dump(2) << "\n";
      throw;
    }
  }
  std::cout << j.dump(2) << "\n";
  report_shown(std::cerr, show);
  return (vm.count("fail-on-chatter") && r.verdict != SimulationVerdict::kStable) ? kExitChatter : 0;
}

}  // namespace chatter::cli
