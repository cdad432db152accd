// The usual band of each length, speed and coefficient a user types, in the
// unit the user types it in, and the unit slips that most likely explain a
// value outside it (docs/config.md, "Plausibility warnings"). One
// definition, read by the config reader (a key) and the command line (a
// flag): a value outside is warned, never refused (refusals are the hard
// bounds beside each reader).
#pragma once

#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "chatter/kinematics.hpp"

namespace chatter {

struct Usual {
  double lo, hi;
  const char* what;         ///< "the 25 to 600 mm of grinding wheels"
  double mixup_factor = 0;  ///< written x factor is the value in the key's unit if the mix-up happened
  const char* mixup_unit = "";
  double other_factor = 0;  ///< a second mix-up (m below the band, um above it)
  const char* other_unit = "";
  bool contains(double v) const { return v >= lo && v <= hi; }
};

/// "" inside the band; else "outside <what>; is it in <unit> (<name> = meant)?"
/// (the hint only when the mixed-up value falls inside the band). `name` is
/// the key or the flag as the user wrote it.
std::string unusual(std::string_view name, double v, const Usual& u);

/// Bands shared by a config key and a command-line flag.
namespace usual {
inline constexpr Usual kSpindleSpeedRpm{10.0, 200000.0, "the 10 to 200 000 rev/min of machine spindles",
                                        rpm_from_revolutions_per_s(1.0), "rev/s"};
inline constexpr Usual kDepthOfCutMm{0.01, 100.0, "the 0.01 to 100 mm of a depth of cut", 1e-3, "um", 1e3, "m"};
inline constexpr Usual kSearchedDepthMm{0.05, 1000.0, "the 0.05 to 1 000 mm a searched depth of cut can reach", 1e-3,
                                        "um", 1e3, "m"};
inline constexpr Usual kSweepPoints{2.0, 20000.0, "the 2 to 20 000 speeds a lobe sweep needs (each one a solve)"};
inline constexpr Usual kToolDiameterMm{0.1, 500.0, "the 0.1 to 500 mm of milling cutters", 1e3, "m", 1e-3, "um"};
inline constexpr Usual kWorkpieceDiameterMm{0.5, 5000.0, "the 0.5 to 5 000 mm of turned parts", 1e3, "m", 1e-3, "um"};
inline constexpr Usual kFluteLengthMm{0.1, 500.0, "the 0.1 to 500 mm of cutting flutes", 1e3, "m", 1e-3, "um"};
inline constexpr Usual kRadialImmersion{2e-3, 1.0, "the 0.002 to 1 of milling (a_e/D, a ratio)", 1e-2, "percent"};
inline constexpr Usual kFeedMm{0.001, 1.0, "the 0.001 to 1 mm of a chip's feed", 1e3, "m", 1e-3, "um"};
inline constexpr Usual kCuttingCoefficientNPerM2{1e8, 1e10, "the 1e8 to 1e10 N/m^2 of metal cutting", 1e6, "N/mm^2"};
inline constexpr Usual kProcessDampingNPerM{1e3, 1e7, "the 1e3 to 1e7 N/m of process-damping coefficients", 1e3,
                                            "N/mm"};
inline constexpr Usual kCuttingSpeedMPerMin{5.0, 3000.0, "the 5 to 3 000 m/min of cutting speeds", 60.0, "m/s"};
inline constexpr Usual kPowerKw{0.05, 1000.0, "the 0.05 to 1 000 kW of machine spindles", 1e-3, "W"};
inline constexpr Usual kTorqueNm{0.1, 10000.0, "the 0.1 to 10 000 N m of machine spindles", 1e-3, "N mm"};
inline constexpr Usual kPartErrorUm{0.5, 1000.0, "the 0.5 to 1 000 um of part tolerances", 1e3, "mm"};
inline constexpr Usual kSafetyFactor{1.0, 10.0, "the 1 to 10 of safety factors on the limit"};
inline constexpr Usual kSpeedTolerancePercent{0.1, 50.0, "the 0.1 to 50 % a spindle speed may be moved", 100.0,
                                              "fractions, not percent"};
inline constexpr Usual kPositionMm{0.0, 20000.0, "the 0 to 20 m of a machine's travel", 1e-3, "um"};
inline constexpr Usual kFrequencyHz{20.0, 100000.0, "the 20 Hz to 100 kHz of a measured FRF's upper end", 1e3, "kHz"};
inline constexpr Usual kGrindingPowerW{10.0, 50000.0, "the 10 W to 50 kW of grinder motors", 1e3, "kW"};
inline constexpr Usual kSpeedVariationAmplitude{0.005, 0.5, "the 0.005 to 0.5 of speed variation amplitudes (R_VA)",
                                                0.01, "percent"};
inline constexpr Usual kSpeedVariationFrequency{0.001, 2.0, "the 0.001 to 2 of modulation frequency ratios (R_VF)"};
inline constexpr Usual kAdaptStepPercent{0.5, 100.0, "the 0.5 to 100 % of one adaptation step", 100.0,
                                         "fractions, not percent"};
inline constexpr Usual kGrooveDepthMm{0.001, 5.0, "the 0.001 to 5 mm of a ground groove", 1e-3, "um", 1e3, "m"};
inline constexpr Usual kGrindingRemovalMm3PerS{0.1, 5000.0, "the 0.1 to 5 000 mm^3/s of grinding removal rates", 1e3,
                                               "cm^3/s"};
inline constexpr Usual kWheelDiameterMm{25.0, 600.0, "the 25 to 600 mm of grinding wheels", 1e3, "m"};
inline constexpr Usual kWheelWidthMm{1.0, 100.0, "the 1 to 100 mm of grinding wheel widths", 1e3, "m"};
inline constexpr Usual kWheelRpm{500.0, 30000.0, "the 500 to 30 000 rev/min of grinding wheels",
                                 rpm_from_revolutions_per_s(1.0), "rev/s"};
inline constexpr Usual kGrindingFeedMmPerS{1.0, 500.0, "the 1 to 500 mm/s of robotic grinding feeds", 1e3, "m/s"};
inline constexpr Usual kKienzleSpecificForceNPerMm2{200.0, 6000.0,
                                                   "the 200 to 6 000 N/mm^2 of k_1.1 (aluminium about 700, steels "
                                                   "1 500 to 2 500, nickel alloys about 3 000)",
                                                   1e-6, "N/m^2"};
inline constexpr Usual kLeadAngleDeg{15.0, 90.0, "the 15 to 90 deg of turning inserts' lead angles",
                                    57.29577951308232, "rad"};
inline constexpr Usual kKienzleExponent{0.05, 0.6, "the 0.05 to 0.6 of Kienzle exponents m (steels about 0.25)"};
inline constexpr Usual kGrindingForceRatio{0.1, 1.5, "the 0.1 to 1.5 of grinding force ratios F_T/F_N (seed 001: 0.26)"};
inline constexpr Usual kImpactsPerTurn{0.05, 20.0, "the 0.05 to 20 impacts per wheel turn of robotic grinding"};
inline constexpr Usual kMotorCurrentA{0.5, 500.0, "the 0.5 to 500 A of grinder motors (seed 000: 16, 19 A)", 1e-3, "mA"};
inline constexpr Usual kFrictionHeatFraction{0.05, 1.0,
                                             "the 0.05 to 1 of friction energy entering the part (seed 001: 0.76, 0.85)"};
}  // namespace usual

/// A command-line flag (without its dashes) whose number has a usual band,
/// with a typical value (tests check that it lies inside and that 1000
/// times it and a thousandth of it lie outside).
struct FlagBand {
  const char* flag;
  const Usual* band;
  double typical;
};
inline constexpr FlagBand kFlagBands[] = {
    {"rpm", &usual::kSpindleSpeedRpm, 3000.0},
    {"rpm-min", &usual::kSpindleSpeedRpm, 1000.0},
    {"rpm-max", &usual::kSpindleSpeedRpm, 8000.0},
    {"rpm-points", &usual::kSweepPoints, 400.0},
    {"depth-mm", &usual::kDepthOfCutMm, 2.0},
    {"depth-max-mm", &usual::kSearchedDepthMm, 10.0},
    {"plot-depth-max-mm", &usual::kSearchedDepthMm, 10.0},
    {"feed-per-tooth-mm", &usual::kFeedMm, 0.05},
    {"feed-mm-per-rev", &usual::kFeedMm, 0.2},
    {"radial-immersion", &usual::kRadialImmersion, 0.5},
    {"immersion-min", &usual::kRadialImmersion, 0.05},
    {"immersion-max", &usual::kRadialImmersion, 1.0},
    {"tool-diameter-mm", &usual::kToolDiameterMm, 16.0},
    {"diameter-mm", &usual::kToolDiameterMm, 16.0},
    {"workpiece-diameter-mm", &usual::kWorkpieceDiameterMm, 60.0},
    {"tangential-coefficient-n-per-m2", &usual::kCuttingCoefficientNPerM2, 7e8},
    {"cutting-speed-m-per-min", &usual::kCuttingSpeedMPerMin, 250.0},
    {"max-power-kw", &usual::kPowerKw, 15.0},
    {"max-torque-nm", &usual::kTorqueNm, 50.0},
    {"max-sle-um", &usual::kPartErrorUm, 20.0},
    {"safety", &usual::kSafetyFactor, 1.25},
    {"speed-tolerance-pct", &usual::kSpeedTolerancePercent, 5.0},
    {"fmax", &usual::kFrequencyHz, 5000.0},
    {"ssv-amplitude", &usual::kSpeedVariationAmplitude, 0.2},
    {"ssv-amplitude-max", &usual::kSpeedVariationAmplitude, 0.3},
    {"ssv-frequency", &usual::kSpeedVariationFrequency, 0.02},
    {"ssv-frequency-min", &usual::kSpeedVariationFrequency, 0.01},
    {"ssv-frequency-max", &usual::kSpeedVariationFrequency, 0.1},
    {"max-step-pct", &usual::kAdaptStepPercent, 10.0},
    {"power-w", &usual::kGrindingPowerW, 1000.0},
    {"power-w-min", &usual::kGrindingPowerW, 500.0},
    {"power-w-max", &usual::kGrindingPowerW, 2000.0},
    {"target-depth-mm", &usual::kGrooveDepthMm, 0.05},
    {"target-removal-mm3-per-s", &usual::kGrindingRemovalMm3PerS, 50.0},
    {"wheel-diameter-mm", &usual::kWheelDiameterMm, 230.0},
    {"wheel-width-mm", &usual::kWheelWidthMm, 6.8},
    {"wheel-rpm", &usual::kWheelRpm, 6000.0},
    {"feed-mm-per-s", &usual::kGrindingFeedMmPerS, 80.0},
    {"force-ratio", &usual::kGrindingForceRatio, 0.26},
    {"impacts-per-turn", &usual::kImpactsPerTurn, 1.3},
    {"current-a", &usual::kMotorCurrentA, 19.0},
    {"wheel-rpm-min", &usual::kWheelRpm, 2000.0},
    {"wheel-rpm-max", &usual::kWheelRpm, 3000.0},
    {"lead-angle-deg", &usual::kLeadAngleDeg, 75.0},
};

/// Numeric flags with no usual band, and why (a test requires every numeric
/// flag of every command in kFlagBands or here).
struct UnbandedFlag {
  const char* flag;
  const char* why;
};
inline constexpr UnbandedFlag kUnbandedFlags[] = {
    {"position-mm", "checked against the config's positions: outside the part it is refused, inside any value is real"},
    {"position-min-mm", "as --position-mm"},
    {"position-max-mm", "as --position-mm"},
    {"fmin", "0 Hz is a real lower end; a slip is caught on --fmax"},
    {"steps", "a numerical setting (steps per period) with its own bounds"},
    {"collocation", "a numerical setting with its own bounds"},
    {"periods", "a numerical setting with its own bounds"},
    {"axial-slices", "a numerical setting with its own bounds"},
    {"threads", "a count of threads"},
    {"samples", "a Monte Carlo sample count with its own bounds"},
    {"seed", "a random seed: any integer"},
    {"depth-points", "a grid count with its own bounds"},
    {"immersion-points", "a grid count with its own bounds"},
    {"position-points", "a grid count with its own bounds"},
    {"ssv-amplitude-points", "a grid count with its own bounds"},
    {"ssv-frequency-points", "a grid count with its own bounds"},
    {"scan-points", "a grid count with its own bounds"},
    {"points", "a grid count with its own bounds"},
    {"revolutions", "a simulated length with its own bounds"},
    {"rtol", "the integrator's relative tolerance, with its own bounds"},
    {"out-every", "a sampling interval of the written series"},
    {"warn-size-mb", "a file size threshold"},
    {"iterations", "a count of adaptation steps"},
    {"index", "an index into a list"},
    {"teeth", "a count: refused outside 1 to 64"},
    {"modes", "a count of modes, checked against the peaks found"},
    {"record", "an index into a file"},
    {"term", "an index into a file"},
    {"channel", "an index into a recording"},
    {"gamma", "a ratio in (0, 1], refused outside"},
    {"min-pitch-ratio", "a ratio in (0, 1], refused outside"},
    {"peak-ratio", "a ratio in (0, 1], refused outside"},
    {"scale", "the unit conversion itself"},
    {"turns", "a simulated length"},
    {"points-per-turn", "a numerical setting"},
    {"power-loop-turns", "a controller time constant in wheel turns"},
    {"series-turns", "a count of turns kept"},
    {"volume-mm3", "any volume a part asks"},
    {"area-mm2", "any area a part asks"},
    {"g-ratio", "an empirical wear ratio, from 1 to thousands"},
    {"threshold-n", "a force threshold on the record's own scale"},
    {"threshold-rpm", "a speed drop on the record's own scale"},
    {"wheel-change-min", "a time, 0 (the default) for none"},
    {"speed-points", "a grid count with its own bounds"},
};

/// "<name> = v: outside <band>; is it in <unit> (<name> = meant)?" for each
/// argument whose number lies outside its usual band: the one check of the
/// command line's flags and of Python's keyword arguments. `name` as the
/// user wrote it ("--depth-mm" or "depth_mm"; looked up in kFlagBands with
/// the dashes stripped and underscores read as dashes); names without a band
/// and the value 0 ("none": no feed, the exact speed) are skipped.
std::vector<std::string> unusual_arguments(const std::vector<std::pair<std::string, double>>& arguments);

}  // namespace chatter
