// Grinding models from test data: least-squares fits of the mechanistic
// coefficients (k_e, k_c) and of the empirical forms, and the impacts per
// wheel turn counted in a normal-force (or wheel-speed) record.
// User guide: docs/grinding.md ("grind fit", "grind impacts"); the models:
// include/chatter/grinding.hpp. Readers of the files: io/grinding_io.hpp.
//
// Statistics of every fit (ordinary least squares, m tests, p unknowns):
// residual variance s^2 = RSS / (m - p); standard errors sqrt(diag(s^2 (X'X)^-1));
// 95 % intervals +- t(0.975, m - p) x standard error (Student t);
// R^2 = 1 - RSS/TSS about the mean of the measured values; RMSE = sqrt(RSS/m);
// MAE = mean |residual|; MAPE = 100 mean |residual / measured| (tests with a
// measured value of 0 are left out of MAPE). Residual = measured - fitted.
// power_law is fitted on logarithms (ln y linear in ln n, ln y2, ln D); its
// standard errors are those of ln C and the exponents (C's own interval is
// exp of ln C's), its R^2, RMSE, MAE and MAPE are of y itself.
// hahn_lindsay is fitted as y = a (F_N V_c) + b V_c (linear), K_p = a,
// F_th = -b/a, F_th's standard error by the delta method.
#pragma once

#include <string>
#include <vector>

#include "chatter/grinding.hpp"

namespace chatter::grinding {

/// Coefficients with their statistics (see the file comment).
struct FitStatistics {
  std::vector<std::string> names;      ///< coefficient names, in order
  std::vector<double> coefficients;    ///< in the model's units (mechanistic: SI)
  std::vector<double> standard_error;  ///< same units; 0 with no degree of freedom left
  std::vector<double> confidence_95;   ///< half-widths (power_law C: see lower/upper)
  std::vector<double> lower_95, upper_95;  ///< the 95 % interval of each coefficient
  int tests = 0;
  int degrees_of_freedom = 0;          ///< m - p
  double r_squared = 0.0, rmse = 0.0, mae = 0.0, mape_percent = 0.0;
  /// The covariance of the fit's linear parameters, s^2 and m - p (the
  /// parameters: FitUncertainty's; mechanistic: k_e, k_c in SI), for the
  /// intervals of predictions (`grind fit --out` writes it into the model).
  FitUncertainty uncertainty;
  std::vector<double> fitted;          ///< per test, the model's value
  std::vector<double> residuals;       ///< per test, measured - fitted
  /// A negative coefficient that must be positive, R^2 below 0.9, no degree
  /// of freedom left, ... each naming the coefficient or the measure.
  std::vector<std::string> warnings;
};

/// One logged test of the mechanistic model: power, removal and impacts, on
/// its own wheel and feed.
struct MechanisticTest {
  double power_w = 0.0;               ///< useful grinding power, > 0
  double removal_m3_per_s = 0.0;      ///< measured removal (volume / time), > 0
  double impacts_per_turn = 1.0;      ///< n_c > 0
  Wheel wheel;
  double feed_m_per_s = 0.0;
};

/// (k_e, k_c) by least squares of P = k_e [n_c N (3/4) E w] + k_c Z_w over
/// the tests (seed 001 eq. 4.7: linear in the coefficients once Z_w and n_c
/// are measured). Coefficients in SI: k_e N/m, k_c N/m^2; residuals in W.
/// @throws InputError with fewer than 3 tests, or when the two regressors are
/// proportional over the tests (the split friction/chip cannot be told: vary
/// the power or the feed). Cost O(m).
FitStatistics fit_mechanistic(const std::vector<MechanisticTest>& tests);

/// One test for an empirical model: what it reads and the measured value
/// (mm^3/s for removal and wear, N for the normal force).
struct EmpiricalSample {
  EmpiricalInputs inputs;
  double value = 0.0;
};

/// The coefficients of `form` on `variable` (docs: EmpiricalForm) by least
/// squares. @throws InputError with fewer tests than coefficients + 1, a
/// power_law sample with a value, speed, variable or diameter <= 0, a
/// hahn_lindsay fit on the power, or a singular design (name the repeated
/// variable). Cost O(m p^2).
FitStatistics fit_empirical(EmpiricalForm form, EmpiricalVariable variable,
                            const std::vector<EmpiricalSample>& samples);

// ---------------------------------------------------------------- impacts

/// What the record holds.
enum class ImpactSignal {
  kNormalForce,  ///< N: an impact is a peak
  kWheelSpeed,   ///< rev/min: an impact is a dip (the wheel is braked)
};

struct ImpactCountOptions {
  double wheel_rpm = 0.0;  ///< the wheel's nominal speed, > 0: one turn = 60 / rpm s
  /// An impact starts when the signal (force, or the speed's drop below its
  /// median) rises above this; 0: automatic, the median plus 0.25 x (the
  /// highest value - median) (a quarter of the way from the no-contact
  /// baseline to the largest peak, when contact takes less than half of the
  /// time).
  double threshold = 0.0;
  /// ... and ends when it falls below the median plus this fraction of
  /// (threshold - median): the hysteresis that keeps noise on a peak from
  /// counting twice.
  double release_fraction = 0.5;
};

/// Impacts per wheel turn from a record (seed 001 §4.7: peaks of the normal
/// force per revolution, their histogram and weighted mean).
struct ImpactCount {
  double threshold = 0.0;          ///< the threshold used (signal units)
  int turns = 0;                   ///< whole turns in the record
  std::vector<int> per_turn;       ///< impacts in each turn (an impact counts in the turn of its maximum)
  std::vector<double> peak_value;  ///< per impact: force peak (N) or speed drop (rev/min)
  std::vector<double> peak_time_s; ///< per impact, time of its maximum
  /// histogram[k] = turns with k impacts, k = 0 .. max.
  std::vector<int> histogram;
  double mean_per_turn = 0.0;      ///< weighted mean = sum k histogram[k] / turns (the seed's n_c)
  double turns_without_contact = 0.0;  ///< fraction of turns with no impact
};

/// @pre time strictly increasing, same length as signal.
/// @throws InputError when the record spans less than two turns, the options
///         are bad, or the signal never crosses the threshold band (flat).
/// Cost O(samples log samples) (the percentiles).
ImpactCount count_impacts(const std::vector<double>& time_s, const std::vector<double>& signal, ImpactSignal kind,
                          const ImpactCountOptions& options);

}  // namespace chatter::grinding
