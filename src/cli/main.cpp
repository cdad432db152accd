// The `chatter` command line: the command list (one table: the dispatch,
// `chatter --help` and README's command list come from it; a test keeps
// README in step), and the mapping of exceptions to exit statuses. Each
// command lives in its own cmd_*.cpp; Boost.Program_options only in src/cli.
// Exit status: 0 success, 2 bad input or usage, 1 internal failure.
#include <boost/program_options.hpp>

#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "chatter/error.hpp"
#include "chatter/io/table_writer.hpp"  // version()
#include "cli_common.hpp"
#include "commands.hpp"

namespace po = boost::program_options;
using chatter::InputError;

namespace {

struct Command {
  const char* name;
  const char* purpose;  ///< one line (README's command list repeats it)
  const char* doc;      ///< the page that documents it
  int (*run)(const std::vector<std::string>&);
};

// Every command, in the order `chatter --help` lists them.
const Command kCommands[] = {
    {"lobes", "stability-lobe table and diagram: the deepest stable cut at each spindle speed", "docs/results.md",
     chatter::cli::cmd_lobes},
    {"point", "is one operating point (speed, depth) stable? the limit there and the margin", "docs/results.md",
     chatter::cli::cmd_point},
    {"check", "check every operation of a part program (stability, part error, spindle power); suggest a robust stable speed for each",
     "docs/operations.md", chatter::cli::cmd_check},
    {"program", "check a whole NC program (G-code) block by block: engagement from the simulated stock, stability, power, part error; fix speeds and feeds",
     "docs/program.md", chatter::cli::cmd_program},
    {"recommend", "the speed and depth that remove the most material, stable and within power and torque",
     "docs/operations.md", chatter::cli::cmd_recommend},
    {"map", "Floquet spectral radius over speed x depth (sdm), Hopf and flip boundaries", "docs/sdm.md",
     chatter::cli::cmd_map},
    {"compare", "every method at the same speeds, and how far they differ", "docs/method.md",
     chatter::cli::cmd_compare},
    {"simulate", "the cut in time with the real chip: stable or chatter, amplitude, spectrum",
     "docs/time_domain.md", chatter::cli::cmd_simulate},
    {"surface", "lobes along the part: the limit over tool position x speed", "docs/position.md",
     chatter::cli::cmd_surface},
    {"forced", "the forced vibration of a stable cut: surface location error, diametral error, teeth out of the cut",
     "docs/forced.md", chatter::cli::cmd_forced},
    {"sle", "surface location error and peak-to-peak vibration against spindle speed, under the lobes",
     "docs/forced.md", chatter::cli::cmd_sle},
    {"performance", "every performance index, loss term and constraint of one cut (speed, feed, depth)",
     "docs/optimization.md", chatter::cli::cmd_performance},
    {"optimize", "the speed and feed that minimise the loss (or cost, ...) under every constraint, stability included",
     "docs/optimization.md", chatter::cli::cmd_optimize},
    {"adapt", "the adaptive loop: correct the models from measurements and move toward the optimum",
     "docs/optimization.md", chatter::cli::cmd_adapt},
    {"design-pitch", "variable-pitch angles that raise the worst stability limit over a speed band, vs equal pitch",
     "docs/design_pitch.md", chatter::cli::cmd_design_pitch},
    {"fit", "modes (frequency, damping, stiffness) fitted to a measured FRF (tap test)", "docs/frf.md",
     chatter::cli::cmd_fit},
    {"frf", "receptance of the tool, the workpiece and the relative motion", "docs/frf.md", chatter::cli::cmd_frf},
    {"coefficients", "cutting coefficients from test cuts (milling: forces or spindle power; turning: Kienzle's k_1.1 and m from forces at several feeds)", "docs/shop_data.md",
     chatter::cli::cmd_coefficients},
    {"detect", "chatter in a recording of the cut, and the spindle speeds to try", "docs/shop_data.md",
     chatter::cli::cmd_detect},
    {"grind", "robotic grinding at controlled power: predict, sweep, fit, impacts, simulate, plan",
     "docs/grinding.md", chatter::cli::cmd_grind},
};

std::string main_help() {
  std::ostringstream os;
  os << R"(chatter - predict regenerative chatter and draw stability lobes

Usage: chatter <command> CONFIG [options]

Commands:
)";
  for (const Command& c : kCommands) {
    std::string name = c.name;
    name.resize(std::max<std::size_t>(name.size(), 13), ' ');
    os << "  " << name << c.purpose << " (" << c.doc << ")\n";
  }
  os << R"(
On the shop floor:
  1. Describe the tool and workpiece modes (from a tap test) and the cut in a
     TOML config; start from one in configs/ (keys: docs/config.md). Cutters:
     helix, variable pitch and runout (docs/physics.md sec. 9), ball-end and
     bull-nose end mills (docs/cutter_geometry.md), turning inserts with lead
     angle and nose radius (docs/turning_inserts.md); spindle speed
     variation (docs/ssv.md).
  2. chatter lobes CONFIG --plot lobes.png: pick a spindle speed at a peak
     between two lobes; cut below the curve there, with margin.
  3. chatter check CONFIG --operations ops.csv before running a program (with
     --max-power-kw and the tool diameter it checks the spindle's power too).
  4. To see what a cut does in time: chatter simulate CONFIG --rpm R --depth-mm D.
  Every command picks its method with --method auto (turning: analytic;
  milling: sdm, which sees the flip lobes of low radial immersion) and names
  the method it used; every reported number is defined in docs/results.md.

Examples:
  chatter lobes configs/seed_turning_1dof.toml --table lobes.csv --plot lobes.png
  chatter point configs/seed_turning_1dof.toml --rpm 1200 --depth-mm 1.5
  chatter lobes configs/milling_benchmark_ae005_down.toml --plot sdm.png
  chatter lobes configs/milling_benchmark_ae005_down.toml --show     (a live gnuplot window)
  chatter check configs/seed_turning_1dof.toml --operations examples/operations/case_a_ops.csv
  chatter frf configs/coupled_tool1_workpiece1.toml --out frf.csv --plot frf.png
  chatter simulate configs/milling_benchmark_ae005_down.toml --rpm 17000 --depth-mm 4 --plot sim.png

Run 'chatter <command> --help' for the options of a command.
Options: --help, --version. Every command that reads a config prints its
plausibility warnings ("warning: FILE: KEY = VALUE: ...; did you mean ...?")
and takes --strict to refuse a config that raises one.
Exit status: 0 success, 2 bad input or usage, 1 internal failure
(check: 3 when some operations are unstable, out of tolerance or over the spindle; lobes --depth-mm D, point and
simulate with --fail-on-chatter: 3 on chatter; detect: 3 on chatter;
forced: 3 when the cut is unstable; performance: 3 when a constraint fails;
optimize: 3 when no set-point meets every constraint).
)";
  return os.str();
}

std::string command_names() {
  std::string out;
  for (const Command& c : kCommands) out += (out.empty() ? "" : ", ") + std::string(c.name);
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  std::string command;  // the subcommand, once recognised
  try {
    if (args.empty()) {
      std::cerr << main_help();
      return 2;
    }
    const std::string cmd = args.front();
    if (cmd == "--help" || cmd == "-h" || cmd == "help") {
      std::cout << main_help();
      return 0;
    }
    if (cmd == "--version") {
      std::cout << "chatter " << chatter::version() << "\n";
      return 0;
    }
    args.erase(args.begin());
    for (const Command& c : kCommands)
      if (cmd == c.name) {
        command = cmd;
        return c.run(args);
      }
    std::cerr << "chatter: unknown command '" << cmd << "' (commands: " << command_names() << "; see chatter --help)\n";
    return 2;
  } catch (const po::error& e) {
    // A malformed value (e.g. --revolutions 0.5): say what it must look like.
    const char* hint = dynamic_cast<const po::invalid_option_value*>(&e)
                           ? ": expected a number (a whole number for counts such as --revolutions, --periods, "
                             "--rpm-points)"
                           : "";
    std::cerr << "chatter: " << e.what() << hint << " (see chatter " << command << (command.empty() ? "" : " ")
              << "--help)\n";
    return 2;
  } catch (const InputError& e) {
    // One line per error (a config reports all of its errors at once).
    std::istringstream lines(e.what());
    for (std::string line; std::getline(lines, line);) std::cerr << "chatter: " << line << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "chatter: internal error: " << e.what() << "\n";
    return 1;
  }
}
