// The C API of the cutting load (chatter.h: chatter_cutting_load), over the
// cutting law (chatter/cutting_law.hpp) with the options `check` uses
// (chatter::cutting_law_options).
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "capi_internal.hpp"
#include "chatter/cutting_law.hpp"
#include "chatter/operations.hpp"

namespace {

using chatter::capi::fail;
using chatter::capi::guarded;

void require_positive(double x, const char* name) {
  if (!(std::isfinite(x) && x > 0.0))
    throw chatter::InputError(std::string("chatter_cutting_load: ") + name + " = " + std::to_string(x) +
                              ": must be > 0");
}

}  // namespace

extern "C" {

chatter_status chatter_cutting_load(const chatter_model* model, double spindle_rpm, double depth_mm, double feed_mm,
                                    double diameter_mm, double kc, chatter_cutting_load_result* out) {
  if (!model || !out) return fail(CHATTER_NULL_ARGUMENT, "chatter_cutting_load: model and out must not be NULL");
  return guarded([&] {
    require_positive(spindle_rpm, "spindle_rpm");
    require_positive(depth_mm, "depth_mm");
    require_positive(feed_mm, "feed_mm");
    if (!std::isnan(diameter_mm)) require_positive(diameter_mm, "diameter_mm");
    if (!std::isnan(kc)) require_positive(kc, "tangential_coefficient_n_per_m2");
    const chatter::Process& process = model->config.process;
    const bool milling = process.rotating_edges();
    chatter::capi::warn_unusual({{"rpm", spindle_rpm},
                                 {"depth_mm", depth_mm},
                                 {milling ? "feed_per_tooth_mm" : "feed_mm_per_rev", feed_mm},
                                 {milling ? "tool_diameter_mm" : "workpiece_diameter_mm", std::isnan(diameter_mm) ? 0.0 : diameter_mm},
                                 {"tangential_coefficient_n_per_m2", std::isnan(kc) ? 0.0 : kc}});
    if (milling && !std::isnan(kc))
      throw chatter::InputError("chatter_cutting_load: tangential_coefficient_n_per_m2: only for turning (milling's "
                                "K_t is the config's)");
    const double config_diameter = milling ? process.milling_parameters().tool_diameter_m
                                           : process.turning_parameters().workpiece_diameter_m;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double d = !std::isnan(diameter_mm) ? diameter_mm * 1e-3 : config_diameter > 0.0 ? config_diameter : nan;
    std::vector<std::string>& warnings = chatter::capi::last_warnings();  // the law's (K_f as pressure) too
    const auto law = chatter::CuttingLaw::of(
        process, chatter::cutting_law_options(process, std::isnan(kc) ? std::nullopt : std::optional<double>(kc),
                                              warnings));
    const chatter::CutPoint p{spindle_rpm, depth_mm * 1e-3, feed_mm * 1e-3, d};
    const chatter::MeanCut m = law->mean(p);
    chatter_cutting_load_result c{};
    c.mean_force_n = m.tangential_force_n;
    c.torque_nm = m.torque_n_m;
    c.power_kw = m.power_w * 1e-3;
    c.removal_rate_mm3_per_s = m.removal_rate_m3_per_s * 1e9;
    c.mean_force_x_n = m.force_n.x();
    c.mean_force_y_n = m.force_n.y();
    c.peak_force_n = law->peak_force_n(p);
    *out = c;
  });
}

}  // extern "C"
