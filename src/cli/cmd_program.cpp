// `chatter program PART.ngc --config JOB.toml`: a whole NC program checked
// block by block (docs/program.md): read by LinuxCNC's interpreter
// (chatter/io/nc_program.hpp), the stock simulated, every feed move's
// stability, load and part error (chatter/records/program.hpp), printed as a
// table and written as the record, CSV, plot and annotated program.
#include <boost/program_options.hpp>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "chatter/error.hpp"
#include "chatter/io/job.hpp"
#include "chatter/io/plot_program.hpp"
#include "chatter/io/table_writer.hpp"
#include "chatter/records/program.hpp"
#include "cli_common.hpp"
#include "live_plot.hpp"
#include "commands.hpp"

namespace po = boost::program_options;

namespace chatter::cli {
namespace {

constexpr const char* kUsage =
    "Usage: chatter program PART.ngc --config JOB.toml [options]\n\n"
    "Checks a whole NC program block by block. LinuxCNC's G-code interpreter reads PART.ngc;\n"
    "the stock of JOB.toml ([stock]: a bar to turn or a box to mill) is cut along the toolpath,\n"
    "and every feed move gets its engagement (depth of cut and position along the bar, or the\n"
    "axial depth and engaged arc), its depth limit (what `chatter point` gives for that cut),\n"
    "margin, chatter frequency, power, torque and part error (SLE or diametral error).\n"
    "Exit status: 0 every cutting block stable and within the machine, 3 otherwise, 2 bad input.\n"
    "Fix a program: --out FIXED.ngc --fix-speed (a robust stable S for each unstable block)\n"
    "--fix-feed (F scaled to the machine's power and torque). Guide: docs/program.md\n";

std::string f(double x, const char* fmt) {
  if (std::isnan(x)) return "-";
  if (std::isinf(x)) return "inf";
  char b[48];
  std::snprintf(b, sizeof b, fmt, x);
  return b;
}

std::string read_file_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream os;
  os << in.rdbuf();
  return os.str();
}

void print_table(const ProgramReport& r, std::ostream& os) {
  os << (r.turning ? "  line tool      rpm  depth_mm  pos_mm  limit_mm  margin  verdict   kW     diam_err_um\n"
                   : "  line tool      rpm  a_p_mm  a_e_mm  arc_deg    limit_mm  margin  verdict   kW     sle_um\n");
  for (const ProgramRow& w : r.rows) {
    if (w.air) continue;
    char b[256];
    const std::string verdict = w.stable ? (w.overloaded ? "OVER" : "stable") : (w.overloaded ? "CHAT+OVER" : "CHATTER");
    if (r.turning)
      std::snprintf(b, sizeof b, "%6d %4d %8.0f %9s %7s %9s %7s  %-9s %6s %9s\n", w.line, w.tool, w.spindle_rpm,
                    f(w.depth_mm, "%.3f").c_str(), f(w.position_mm, "%.1f").c_str(), f(w.depth_limit_mm, "%.3f").c_str(),
                    f(w.margin, "%.2f").c_str(), verdict.c_str(), f(w.power_kw, "%.2f").c_str(),
                    f(w.part_error_um, "%.1f").c_str());
    else
      std::snprintf(b, sizeof b, "%6d %4d %8.0f %7s %7s %5s-%-5s %9s %7s  %-9s %6s %9s\n", w.line, w.tool, w.spindle_rpm,
                    f(w.axial_depth_mm, "%.2f").c_str(), f(w.radial_depth_mm, "%.2f").c_str(),
                    f(w.entry_angle_deg, "%.1f").c_str(), f(w.exit_angle_deg, "%.1f").c_str(),
                    f(w.depth_limit_mm, "%.3f").c_str(), f(w.margin, "%.2f").c_str(), verdict.c_str(),
                    f(w.power_kw, "%.2f").c_str(), f(w.part_error_um, "%.1f").c_str());
    os << b;
  }
  const ProgramSummary& s = r.summary;
  os << s.blocks << " feed moves: " << s.cutting_blocks << " cutting, " << s.air_blocks << " in the air; "
     << s.unstable_blocks << " unstable, " << s.overloaded_blocks << " overloaded; worst margin "
     << f(s.worst_margin, "%.3g") << " (line " << s.worst_line << "); removed " << f(s.removed_volume_mm3, "%.0f")
     << " mm3 in " << f(s.cutting_time_s, "%.1f") << " s of cutting; " << s.solves << " solves, " << s.cache_hits
     << " cache hits\n";
}

}  // namespace

int cmd_program(const std::vector<std::string>& args) {
  std::string program_path, job_path, json_path, table_path, plot_path, out_path;
  po::options_description d("Options");
  d.add_options()
      ("help,h", "print this help")
      ("config", po::value<std::string>(&job_path)->required(), "the job: JOB.toml with [stock], [[tools]], [machine] (required; docs/program.md)")
      ("json", po::value<std::string>(&json_path), "write the record as JSON to this file ('-': standard output, the table then goes to standard error)")
      ("table", po::value<std::string>(&table_path), "write one CSV row per feed move to this file")
      ("plot", po::value<std::string>(&plot_path), "plot margin, power and limit against cutting time (and the toolpath or the bar) to this image (.png, .svg, .pdf)")
      ("out", po::value<std::string>(&out_path), "write the program with a comment on every unstable or overloaded block (and the fixes) to this file")
      ("fix-speed", "with --out: set each unstable block's S to a robust stable speed (as check suggests; the old S restored after it)")
      ("fix-feed", "with --out: scale each overloaded block's F to the machine's power and torque (the old F restored after it)")
      ("fail-on-chatter", "exit with status 3 when a block chatters or overloads (always so here, as check: kept for scripts)")
      ("no-cache", "solve every sample of every block (the cache never changes an answer; for checking that)")
      ("threads", po::value<int>()->default_value(0), "threads for the solves (0 = every core); the result does not depend on it")
      ("quiet,q", "no progress bar")
      ("progress", "show the progress (fraction done, time left) even when standard error is not a terminal");
  add_show_option(d);
  po::variables_map vm;
  po::options_description all;
  all.add(d).add_options()("program", po::value<std::string>(&program_path), "");
  po::positional_options_description pos;
  pos.add("program", 1);
  store_command_line(args, all, pos, vm);
  if (vm.count("help")) {
    std::cout << kUsage << "\n" << d << "\n";
    return 0;
  }
  po::notify(vm);
  if (program_path.empty()) throw InputError("program: give the NC program (PART.ngc) as the first argument");
  if ((vm.count("fix-speed") || vm.count("fix-feed")) && out_path.empty())
    throw InputError("--fix-speed/--fix-feed: give --out FIXED.ngc (the program is never changed in place)");
  check_outputs({{"--json", json_path == "-" ? "" : json_path},
                 {"--table", table_path},
                 {"--plot", plot_path, true},
                 {"--out", out_path}});
  const ShowRequest show = show_request(vm);
  const Job job = load_job(job_path);
  for (const std::string& w : job.warnings) std::cerr << "warning: " << w << "\n";
  ProgramOptions opt;
  opt.threads = thread_count(vm);
  opt.fix_speed = vm.count("fix-speed") > 0;
  opt.fix_feed = vm.count("fix-feed") > 0;
  if (vm.count("no-cache")) opt.cache = false;
  ProgramReport report;
  {
    Progress bar(vm, 1000, "program", 1.0);
    opt.progress = [&](double x) { bar.tick(static_cast<std::size_t>(x * 1000)); };
    report = run_program(program_path, job, opt);
  }
  for (const std::string& w : report.warnings) std::cerr << "warning: " << w << "\n";
  const nlohmann::json record = program_record(report);
  std::vector<std::pair<std::filesystem::path, std::string>> files;
  if (!json_path.empty() && json_path != "-") files.emplace_back(json_path, record.dump(2) + "\n");
  if (!table_path.empty()) files.emplace_back(table_path, program_csv(report));
  if (!out_path.empty()) files.emplace_back(out_path, annotate_program(read_file_text(program_path), report));
  write_text_files(files);
  const ProgramPlotData plot = program_plot_data(report, job.machine.max_power_kw.value_or(0.0));
  if (!plot_path.empty()) plot_program(plot, plot_path);
  if (show.requested) {
    LiveWindow window(show);
    plot_program(plot, window);
  }
  print_table(report, json_path == "-" ? std::cerr : std::cout);
  if (show.requested) report_shown(std::cerr, show);
  if (json_path == "-") std::cout << record.dump(2) << "\n";
  for (const auto& [p, text] : files) std::cerr << "wrote " << p.string() << "\n";
  if (!plot_path.empty()) std::cerr << "wrote " << plot_path << "\n";
  return report.ok() ? 0 : kExitChatter;
}

}  // namespace chatter::cli
