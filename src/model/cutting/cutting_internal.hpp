// Internal to the cutting law (src/model/cutting): the implementations'
// constructors (static and regenerative side) and the check every one
// applies to a CutPoint.
#pragma once

#include <memory>

#include "chatter/cutting_law.hpp"
#include "chatter/regenerative_cut.hpp"

namespace chatter::cutting_detail {

/// @throws InputError naming the rule broken (CuttingLaw::mean's preconditions).
void check_point(const CutPoint& p);

/// Turning with tangential coefficient K_c (N/m², 0 = not given). @pre turning.
std::unique_ptr<const CuttingLaw> turning_law(const Process& process, double kc);
/// Milling with edge coefficients (zero with a profile). @pre milling.
std::unique_ptr<const CuttingLaw> milling_law(const Process& process, const EdgeCoefficients& edge);
/// The regenerative cuts (RegenerativeCut::of checked the arguments).
/// @pre turning, resp. milling.
std::unique_ptr<const RegenerativeCut> turning_cut(const Process& process, double rpm, double depth_m);
std::unique_ptr<const RegenerativeCut> milling_cut(const Process& process, double rpm, double depth_m,
                                                   int helix_slices);

}  // namespace chatter::cutting_detail
