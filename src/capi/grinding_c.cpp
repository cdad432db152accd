// The grinding part of the C API (include/chatter/chatter.h, "grinding";
// docs/c_api.md): predict and fit over the library, the records from the io
// layer (the same JSON as the CLI). Nothing propagates into C.
#include <algorithm>
#include <cstring>
#include <string>

#include "capi_internal.hpp"
#include "chatter/chatter.h"
#include "chatter/error.hpp"
#include "chatter/grinding.hpp"
#include "chatter/io/grinding_config.hpp"
#include "chatter/io/grinding_io.hpp"
#include "chatter/records/grinding.hpp"

namespace {

using chatter::capi::fail;
using chatter::capi::guarded;

chatter::grinding::Prediction predict(const chatter::GrindingConfig& c, chatter_grinding_target target, double value) {
  switch (target) {
    case CHATTER_GRINDING_POWER_W: return chatter::grinding::predict_at_power(c.process, value);
    case CHATTER_GRINDING_DEPTH_MM: return chatter::grinding::predict_for_depth(c.process, value * 1e-3);
    case CHATTER_GRINDING_REMOVAL_MM3_PER_S: return chatter::grinding::predict_for_removal(c.process, value * 1e-9);
    case CHATTER_GRINDING_TARGET_FORCE_INT: break;  // the enum's size marker, no target
  }
  throw chatter::InputError("target = " + std::to_string(static_cast<int>(target)) +
                            ": must be CHATTER_GRINDING_POWER_W, _DEPTH_MM or _REMOVAL_MM3_PER_S");
}

// Copies `text` into buffer (NUL-terminated, truncated to size - 1 bytes).
void copy_out(const std::string& text, char* buffer, std::size_t size, std::size_t* length) {
  if (length) *length = text.size();
  if (buffer && size > 0) {
    const std::size_t n = std::min(size - 1, text.size());
    std::memcpy(buffer, text.data(), n);
    buffer[n] = '\0';
  }
}

chatter::GrindingFitReport fit(const char* tests_csv, const char* model, const char* variable) {
  return chatter::fit_grinding_tests(chatter::read_grinding_tests(tests_csv, {}), model, variable ? variable : "",
                                     tests_csv);
}

}  // namespace

extern "C" {

chatter_status chatter_grinding_predict(const char* config_path, chatter_grinding_target target, double value,
                                        chatter_grinding_prediction* out) {
  if (!config_path || !out)
    return fail(CHATTER_NULL_ARGUMENT, "chatter_grinding_predict: config_path and out must not be NULL");
  return guarded([&] {
    const chatter::GrindingConfig c = chatter::load_grinding_config(config_path);
    const chatter::grinding::Prediction p = predict(c, target, value);
    chatter_grinding_prediction r{};
    r.power_w = p.power_w;
    r.removal_rate_mm3_per_s = p.removal_rate_m3_per_s * 1e9;
    r.max_depth_mm = p.max_depth_m * 1e3;
    r.groove_width_mm = p.groove_width_m * 1e3;
    r.depth_per_pass_mm = p.depth_per_pass_m * 1e3;
    r.tangential_force_n = p.tangential_force_n;
    r.normal_force_n = p.normal_force_n;
    r.specific_energy_j_per_mm3 = p.specific_energy_j_per_m3 * 1e-9;
    r.contact_duration_s = p.contact_duration_s;
    r.cutting_speed_m_per_s = p.cutting_speed_m_per_s;
    if (p.friction_power_w && p.chip_power_w && p.impacts_per_turn) {
      r.has_mechanistic = 1;
      r.friction_power_w = *p.friction_power_w;
      r.chip_power_w = *p.chip_power_w;
      r.impacts_per_turn = *p.impacts_per_turn;
    }
    if (p.energy_partition) {
      r.has_energy_partition = 1;
      r.energy_partition = p.energy_partition->fraction;
      r.heat_into_part_w = p.energy_partition->heat_into_part_w;
    }
    if (p.empirical) {
      if (p.empirical->removal_rate_m3_per_s) {
        r.has_empirical_removal = 1;
        r.empirical_removal_rate_mm3_per_s = *p.empirical->removal_rate_m3_per_s * 1e9;
      }
      if (p.empirical->normal_force_n) {
        r.has_empirical_normal_force = 1;
        r.empirical_normal_force_n = *p.empirical->normal_force_n;
      }
      if (p.empirical->wear_rate_m3_per_s) {
        r.has_empirical_wear = 1;
        r.empirical_wear_rate_mm3_per_s = *p.empirical->wear_rate_m3_per_s * 1e9;
      }
    }
    r.warning_count = c.warnings.size() + p.warnings.size();
    *out = r;
  });
}

chatter_status chatter_grinding_predict_json(const char* config_path, chatter_grinding_target target, double value,
                                             char* buffer, size_t size, size_t* length) {
  if (!config_path) return fail(CHATTER_NULL_ARGUMENT, "chatter_grinding_predict_json: config_path must not be NULL");
  if (!buffer && size > 0)
    return fail(CHATTER_NULL_ARGUMENT, "chatter_grinding_predict_json: buffer is NULL but size is not 0");
  return guarded([&] {
    const chatter::GrindingConfig c = chatter::load_grinding_config(config_path);
    copy_out(chatter::grinding_prediction_record(predict(c, target, value), c).dump(2) + "\n", buffer, size, length);
  });
}

chatter_status chatter_grinding_fit(const char* tests_csv, const char* model, const char* variable, const char* target,
                                    chatter_grinding_fit_result* out) {
  if (!tests_csv || !model || !out)
    return fail(CHATTER_NULL_ARGUMENT, "chatter_grinding_fit: tests_csv, model and out must not be NULL");
  return guarded([&] {
    const chatter::GrindingFitReport r = fit(tests_csv, model, variable);
    const chatter::GrindingFitReport::Target* t = nullptr;
    std::string names;
    for (const auto& x : r.targets) {
      names += (names.empty() ? "" : ", ") + x.name;
      if (!target || x.name == target) {
        t = &x;
        break;
      }
    }
    if (!t)
      throw chatter::InputError(std::string(tests_csv) + ": target \"" + target + "\": not fitted (fitted: " + names + ")");
    const bool mech = r.model == "mechanistic";
    chatter_grinding_fit_result f{};
    f.count = t->fit.coefficients.size();
    for (std::size_t i = 0; i < f.count && i < CHATTER_GRINDING_MAX_COEFFICIENTS; ++i) {
      const double s = mech ? (i == 0 ? 1e-3 : 1e-6) : 1.0;  // N/m -> N/mm, N/m^2 -> N/mm^2
      f.coefficients[i] = t->fit.coefficients[i] * s;
      f.standard_error[i] = t->fit.standard_error[i] * (mech ? s : 1.0);
      f.lower_95[i] = t->fit.lower_95[i] * s;
      f.upper_95[i] = t->fit.upper_95[i] * s;
    }
    f.tests = t->fit.tests;
    f.degrees_of_freedom = t->fit.degrees_of_freedom;
    f.r_squared = t->fit.r_squared;
    f.rmse = t->fit.rmse;
    f.mae = t->fit.mae;
    f.mape_percent = t->fit.mape_percent;
    *out = f;
  });
}

chatter_status chatter_grinding_fit_json(const char* tests_csv, const char* model, const char* variable, char* buffer,
                                         size_t size, size_t* length) {
  if (!tests_csv || !model)
    return fail(CHATTER_NULL_ARGUMENT, "chatter_grinding_fit_json: tests_csv and model must not be NULL");
  if (!buffer && size > 0)
    return fail(CHATTER_NULL_ARGUMENT, "chatter_grinding_fit_json: buffer is NULL but size is not 0");
  return guarded([&] { copy_out(chatter::grinding_fit_record(fit(tests_csv, model, variable), std::nullopt).dump(2) + "\n", buffer, size, length); });
}

}  // extern "C"
