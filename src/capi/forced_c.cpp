// The C API of the forced response (chatter.h: chatter_forced_response),
// over the same library calls as `chatter forced` (src/cli/cmd_forced.cpp).
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "capi_internal.hpp"
#include "chatter/forced.hpp"

namespace {

using chatter::capi::fail;
using chatter::capi::guarded;

// As the CLI: the deepest cut of the depth-limit search, mm.
constexpr double kDefaultDepthMaxMm = 50.0;

double um_or_nan(double m) { return std::isfinite(m) ? m * 1e6 : std::numeric_limits<double>::quiet_NaN(); }

}  // namespace

extern "C" {

chatter_status chatter_forced_response(const chatter_model* model, double spindle_rpm, double depth_mm, double feed_mm,
                                       chatter_forced_result* out) {
  if (!model || !out) return fail(CHATTER_NULL_ARGUMENT, "chatter_forced_response: model and out must not be NULL");
  return guarded([&] {
    const std::string where = "chatter_forced_response: ";
    if (!(std::isfinite(spindle_rpm) && spindle_rpm > 0.0))
      throw chatter::InputError(where + "spindle_rpm = " + std::to_string(spindle_rpm) + ": must be > 0");
    if (!(std::isfinite(depth_mm) && depth_mm > 0.0))
      throw chatter::InputError(where + "depth_mm = " + std::to_string(depth_mm) + ": must be > 0");
    if (!(std::isfinite(feed_mm) && feed_mm > 0.0))
      throw chatter::InputError(where + "feed_mm = " + std::to_string(feed_mm) + ": must be > 0");
    const chatter::Config& cfg = model->config;
    chatter::capi::warn_unusual({{"rpm", spindle_rpm},
                                 {"depth_mm", depth_mm},
                                 {cfg.process.rotating_edges() ? "feed_per_tooth_mm" : "feed_mm_per_rev", feed_mm}});
    chatter::ForcedOptions o;
    o.sdm.depth_max_m = std::max(cfg.sweep.depth_max_mm.value_or(kDefaultDepthMaxMm), 2.0 * depth_mm) * 1e-3;
    const chatter::ForcedResponseSolver solver(cfg.model, cfg.process, o);
    chatter::ForcedSettings st;
    st.spindle_rpm = spindle_rpm;
    st.depth_m = depth_mm * 1e-3;
    st.feed_m = feed_mm * 1e-3;
    st.record_path = false;
    const chatter::ForcedResponse r = solver.response(st);
    const chatter::StabilityLimit limit = solver.stability().limit_at(chatter::SpindleSpeed(spindle_rpm));
    const double nan = std::numeric_limits<double>::quiet_NaN();
    chatter_forced_result c{};
    c.stable = r.stable ? 1 : 0;
    c.spectral_radius = r.spectral_radius;
    c.depth_limit_mm = limit.bounded() ? limit.depth_limit_m * 1e3 : HUGE_VAL;
    c.surface_location_error_um = r.stable ? um_or_nan(r.surface_location_error_m) : nan;
    c.sle_min_um = r.stable ? um_or_nan(r.sle_min_m) : nan;
    c.sle_max_um = r.stable ? um_or_nan(r.sle_max_m) : nan;
    c.peak_to_peak_x_um = r.stable ? r.peak_to_peak_x_m * 1e6 : nan;
    c.peak_to_peak_y_um = r.stable ? r.peak_to_peak_y_m * 1e6 : nan;
    c.static_deflection_x_um = r.stable ? r.static_x_m * 1e6 : nan;
    c.static_deflection_y_um = r.stable ? r.static_y_m * 1e6 : nan;
    c.min_chip_thickness_um = r.stable ? um_or_nan(r.min_chip_m) : nan;
    c.negative_chip_arc_deg = r.stable ? r.negative_chip_arc_deg : nan;
    c.teeth_leave_cut = r.stable && r.teeth_leave_cut ? 1 : 0;
    c.linear_limit_holds = r.linear_limit_holds ? 1 : 0;
    c.diametral_error_um = r.stable ? um_or_nan(r.diametral_error_m) : nan;
    *out = c;
  });
}

}  // extern "C"
