// Internal: the pieces the `chatter grind` subcommands share (cmd_grind.cpp,
// cmd_grind_data.cpp, cmd_grind_plan.cpp).
#pragma once

#include <string>
#include <vector>

#include "chatter/io/grinding_config.hpp"
#include "chatter/io/plot.hpp"
#include "cli_common.hpp"

namespace chatter::cli {

/// Parses a grind subcommand's arguments, `name` the positional argument
/// (CONFIG, TESTS.csv, ...); adds --strict when `config`. False when --help
/// was printed. @throws po::error on a usage error.
bool parse_grind(const std::vector<std::string>& args, const char* usage, po::options_description& d, const char* name,
                 po::variables_map& vm, std::string& positional, bool config = true);

/// load_grinding_config with the plausibility warnings on stderr, or refused
/// with --strict (as load_checked does for lobe configs).
GrindingConfig load_grinding_checked(const std::string& path, bool strict);

/// @throws InputError "--<flag> = v: must be > 0 <unit>" when the flag is given and not > 0.
void require_positive(const po::variables_map& vm, const char* flag, const char* unit);

/// "wrote plot: ... (gnuplot script ..., data ...)".
void print_plot(std::ostream& os, const PlotFiles& pf);

int cmd_grind_fit(const std::vector<std::string>& args);      // cmd_grind_data.cpp
int cmd_grind_impacts(const std::vector<std::string>& args);  // cmd_grind_data.cpp
int cmd_grind_plan(const std::vector<std::string>& args);     // cmd_grind_plan.cpp

/// Shop-style number text of the grind reports (4 significant digits).
std::string grind_number(double x);

}  // namespace chatter::cli
