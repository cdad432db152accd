// The one definition of every number the engine reports about stability
// (docs/results.md): each quantity is computed here, or by the one member
// of Process named here, and every command, method, output format, the C
// API and Python take it from here.
//
//   quantity            definition                                   where
//   tooth_passing_hz    N·N_t/60 (turning N/60), any pitch            Process::tooth_passing_hz
//   tooth_period_s      1 / tooth_passing_hz                          Process::delay_s
//   floquet_period_s    shortest repeat of the cutter (pitch, helix,  Process::floquet_period_s
//                       runout when the method sees it): the period
//                       multipliers and growth factors refer to
//   lobe                ⌊f_c / f_tp⌋ of the limit's chatter frequency  lobe_number
//   depth_limit, chatter_frequency, lobe, multiplier_type: of the limit (the lobe-table row);
//   spectral_radius, dominant_*: of the asked depth (PointReport::at_depth).
//
// Units: SI (m, s, Hz) inside the structs; the records (chatter/records.hpp)
// write mm and rev/min.
#pragma once

#include <complex>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "chatter/lobes.hpp"
#include "chatter/process.hpp"
#include "chatter/results.hpp"

namespace chatter {

/// Lobe number of a chatter frequency f_c at tooth-passing frequency f_tp
/// (Hz): k = ⌊f_c / f_tp⌋, the number of whole chatter waves per tooth
/// period — the k of ωτ = ε + 2πk (ε in (0, 2π)) of the transfer-function
/// lobes, and for every other method the same count. A flip (f_c = (k + ½)
/// f_tp) is lobe k; a fold or a frequency on a harmonic (f_c = k f_tp) is lobe
/// k: a ratio within 1e-9 (relative) of a whole number counts as that number,
/// so round-off never flips the number between neighbouring rows.
/// −1 when f_c is not a finite number >= 0 or f_tp is not > 0.
int lobe_number(double chatter_frequency_hz, double tooth_passing_hz);

}  // namespace chatter
