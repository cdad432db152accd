// Reading an NC program (RS274/NGC G-code) with LinuxCNC's interpreter
// (docs/program.md "Reading the program"). The engine has no G-code parser
// of its own: modal groups, units, planes, G7/G8, G94/G95, G96/G97, arcs,
// canned cycles, cutter compensation, subroutines and expressions are the
// interpreter's. `/usr/bin/rs274 -g` (Debian `linuxcnc-uspace`) is run as a
// process with an argument vector, on a copy of the program whose every
// block carries its line number as an N word (the interpreter reports
// canonical calls, each with the N word of the block it came from), and a
// tool table written from the job's tools (diameters for G41/G42).
#pragma once

#include <filesystem>
#include <map>
#include <string>

#include "chatter/toolpath.hpp"

namespace chatter {

struct NcReadOptions {
  /// The interpreter; empty = $CHATTER_RS274 if set, else /usr/bin/rs274.
  std::filesystem::path interpreter{};
  /// Tool number -> cutter-compensation diameter, mm (milling: the tool's
  /// diameter; turning: twice the nose radius), written as the tool table.
  /// A T word for a number not here is the interpreter's error.
  std::map<int, double> tool_diameters_mm{};
  /// Longest the interpreter may run, s (a program that loops forever).
  double timeout_s = 120.0;
};

/// The interpreter the options name (for messages and --version).
std::filesystem::path nc_interpreter(const NcReadOptions& options);

/// The feed moves of `file` in program order (chatter/toolpath.hpp), in mm.
/// @throws InputError "<file>: cannot read ...", "<file>:<line>: <the
///         interpreter's message>" (an interpreter error, with the offending
///         block), "<interpreter>: not found (install linuxcnc-uspace ...)",
///         or a timeout.
Toolpath read_nc_program(const std::filesystem::path& file, const NcReadOptions& options);

/// The same from the interpreter's canonical-call log (`rs274 -g` stdout),
/// for tests and for a log made elsewhere. @throws InputError on a call
/// whose arguments do not parse (naming the log line).
Toolpath parse_canon_log(const std::string& log, const std::string& source);

/// The program with every block's N word set to its 1-based line number
/// (an existing N word replaced; `%` lines, blank lines and the block-delete
/// slash kept in place).
std::string number_program_lines(const std::string& program);

}  // namespace chatter
