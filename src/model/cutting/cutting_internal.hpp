// Internal to the cutting law (src/model/cutting): the implementations'
// constructors and the check every one applies to a CutPoint.
#pragma once

#include <memory>

#include "chatter/cutting_law.hpp"

namespace chatter::cutting_detail {

/// @throws InputError naming the rule broken (CuttingLaw::mean's preconditions).
void check_point(const CutPoint& p);

/// Turning with tangential coefficient K_c (N/m², 0 = not given). @pre turning.
std::unique_ptr<const CuttingLaw> turning_law(const Process& process, double kc);
/// Milling with edge coefficients (zero with a profile). @pre milling.
std::unique_ptr<const CuttingLaw> milling_law(const Process& process, const EdgeCoefficients& edge);

}  // namespace chatter::cutting_detail
