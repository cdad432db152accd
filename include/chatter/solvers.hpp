// One entry point to every lobe solver by name, for the CLI, the C API and
// the operation check. Each solver's own header documents its method.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "chatter/lobes.hpp"
#include "chatter/process.hpp"
#include "chatter/structural_model.hpp"

namespace chatter {

/// The method names this build provides: {"analytic", "coupled", "sdm", "time-domain"}.
std::vector<std::string> lobe_methods();

/// True when `method` names a solver this build provides.
bool has_lobe_method(const std::string& method);

/// Builds the solver named `method` with default options and the given
/// search depth (m, > 0).
/// @throws InputError on an unknown method or invalid depth.
std::unique_ptr<LobeSolver> make_lobe_solver(const std::string& method, const StructuralModel& model,
                                             const Process& process, double depth_max_m);

}  // namespace chatter
