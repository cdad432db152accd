// `chatter map CONFIG --ssv-map`: the spectral radius over the spindle speed
// variation (R_VA × R_VF) at one speed and depth (docs/ssv.md). The options
// are offered by `chatter map` (add_ssv_map_options); cmd_map hands over
// when --ssv-map is given.
#pragma once

#include <boost/program_options.hpp>

#include <string>

#include "cli_common.hpp"

namespace chatter::cli {

/// Adds --ssv-map, --depth-mm and the grid options (--rpm is map's own,
/// shared with --axes radial-axial).
void add_ssv_map_options(po::options_description& d);
/// Refuses the --ssv-map options without --ssv-map. @throws InputError.
void check_no_ssv_map_options(const po::variables_map& vm);
/// Runs the map (--out / --plot as `map`). @throws InputError.
int run_ssv_map(const po::variables_map& vm, const Common& common, const std::string& method,
                const std::string& out_path, const std::string& plot_path);

}  // namespace chatter::cli
