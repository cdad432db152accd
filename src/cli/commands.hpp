// The subcommands (main.cpp lists them in its command table). Each takes the arguments after
// the subcommand name and returns the exit status (0, or throws).
#pragma once

#include <string>
#include <vector>

namespace chatter::cli {

int cmd_program(const std::vector<std::string>& args);    // src/cli/cmd_program.cpp
int cmd_check(const std::vector<std::string>& args);      // src/cli/cmd_operations.cpp
int cmd_recommend(const std::vector<std::string>& args);  // src/cli/cmd_operations.cpp
int cmd_fit(const std::vector<std::string>& args);        // src/cli/cmd_fit.cpp
int cmd_compare(const std::vector<std::string>& args);    // src/cli/cmd_compare.cpp
int cmd_simulate(const std::vector<std::string>& args);   // src/cli/cmd_simulate.cpp
int cmd_coefficients(const std::vector<std::string>& args);  // src/cli/cmd_coefficients.cpp
int cmd_detect(const std::vector<std::string>& args);        // src/cli/cmd_detect.cpp
int cmd_surface(const std::vector<std::string>& args);       // src/cli/cmd_surface.cpp
int cmd_lobes(const std::vector<std::string>& args);         // src/cli/cmd_lobes.cpp
int cmd_point(const std::vector<std::string>& args);         // src/cli/cmd_point.cpp
int cmd_frf(const std::vector<std::string>& args);           // src/cli/cmd_frf.cpp
int cmd_map(const std::vector<std::string>& args);           // src/cli/cmd_map.cpp
int cmd_grind(const std::vector<std::string>& args);         // src/cli/cmd_grind.cpp (docs/grinding.md)
int cmd_forced(const std::vector<std::string>& args);        // src/cli/cmd_forced.cpp
int cmd_sle(const std::vector<std::string>& args);           // src/cli/cmd_forced.cpp
int cmd_performance(const std::vector<std::string>& args);   // src/cli/cmd_optimize.cpp
int cmd_optimize(const std::vector<std::string>& args);      // src/cli/cmd_optimize.cpp
int cmd_adapt(const std::vector<std::string>& args);         // src/cli/cmd_optimize.cpp
int cmd_design_pitch(const std::vector<std::string>& args);  // src/cli/cmd_design_pitch.cpp

}  // namespace chatter::cli
