// Internal to src/grinding: what one file of the grinding model computes for
// another (include/chatter/grinding.hpp has the public side).
#pragma once

#include <string>
#include <vector>

#include "chatter/grinding.hpp"

namespace chatter::grinding::detail {

/// The energy partition of prediction `r` (its power, specific energy and,
/// with the mechanistic model, friction and chip power already set) under
/// p.partition; a clamped fraction or a beta held at a table's end adds a
/// sentence to `warnings`. @pre p.partition. (partition.cpp)
EnergyPartition energy_partition(const Process& p, const Prediction& r, std::vector<std::string>& warnings);

/// Empty when `coefficients` holds coefficient_count(form) finite numbers,
/// else the rule (the empirical models' and the motor map's). (empirical.cpp)
std::string validate_coefficients(EmpiricalForm form, const std::vector<double>& coefficients);

/// A poly11, poly22 or poly33 in MATLAB's term order at (x, y).
/// @pre c holds coefficient_count(form) numbers. (empirical.cpp)
double poly_value(EmpiricalForm form, const std::vector<double>& c, double x, double y);

/// "" for a G-ratio in the 0.2 to 20 of rough grinding with resin-bonded
/// discs, else the sentence that says why the ratio is not to be trusted.
/// (empirical.cpp)
std::string unusual_g_ratio(double g);

/// The 0.975 quantile of Student's t with `dof` degrees of freedom (0 for
/// dof <= 0). (intervals.cpp)
double student_t975(int dof);

/// Empty when `u` fits a model of p parameters, else the violated rule.
/// (intervals.cpp)
std::string validate_uncertainty(const FitUncertainty& u, std::size_t p);

}  // namespace chatter::grinding::detail
