// The grinder motor's map from current to power and the useful power it
// leaves at the wheel (include/chatter/grinding.hpp: MotorMap; seed 000
// §4.4, eqs. 4.26 and 4.27).
#include <cmath>
#include <string>
#include <vector>

#include "chatter/error.hpp"
#include "chatter/grinding.hpp"
#include "chatter/kinematics.hpp"
#include "grinding_internal.hpp"
#include "grinding_text.hpp"

namespace chatter::grinding {

std::string MotorMap::validate() const {
  if (form != EmpiricalForm::kPoly11 && form != EmpiricalForm::kPoly22 && form != EmpiricalForm::kPoly33)
    return "the motor map is a poly11, poly22 or poly33 in current and motor speed";
  if (const std::string e = detail::validate_coefficients(form, coefficients); !e.empty()) return e;
  if (max_current_a && !(std::isfinite(*max_current_a) && *max_current_a > 0.0))
    return "the motor's max_current_a must be > 0";
  return "";
}

double MotorMap::power_w(double amps, double rpm, std::vector<std::string>* warnings) const {
  auto check = [&](const std::optional<Interval>& i, double v, const char* what, const char* unit) {
    if (warnings && i && !i->contains(v))
      warnings->push_back(std::string("grinding.motor: ") + what + " " + detail::num(v) + " " + unit +
                          " outside the measured " + detail::num(i->lo) + " to " + detail::num(i->hi) + " " + unit +
                          " (an extrapolation of the motor map)");
  };
  check(current_a, amps, "current", "A");
  check(motor_rpm, rpm, "motor speed", "rev/min");
  return detail::poly_value(form, coefficients, amps, rpm);
}

double useful_power_from_current(const Process& p, double current_a, std::vector<std::string>& warnings) {
  if (!p.motor)
    throw InputError("a motor current needs the motor's map from current to power: [grinding.motor]");
  if (!(std::isfinite(current_a) && current_a > 0.0))
    throw InputError("current_a = " + detail::num(current_a) + ": must be > 0 A");
  const double motor_rpm = rpm_from_revolutions_per_s(p.wheel.speed_rev_per_s) / p.transmission_ratio;
  const double motor_w = p.motor->power_w(current_a, motor_rpm, &warnings);
  if (!std::isfinite(motor_w) || !(motor_w > 0.0))
    throw InputError("the motor map gives " + detail::num(motor_w) + " W at " + detail::num(current_a) + " A and " +
                     detail::num(motor_rpm) + " rev/min (not > 0): outside where it holds");
  if (p.motor->max_current_a && current_a > *p.motor->max_current_a)
    warnings.push_back("current " + detail::num(current_a) + " A is above the motor's continuous limit " +
                       detail::num(*p.motor->max_current_a) + " A");
  if (!p.no_load_loss) {
    warnings.emplace_back("no [grinding.no_load_loss]: the useful power is taken as the motor's whole mechanical "
                          "power (the drag of the wheel in its medium is not subtracted)");
    return motor_w;
  }
  const double loss = p.no_load_loss->loss_w(p.wheel);
  if (!(motor_w > loss))
    throw InputError("at " + detail::num(current_a) + " A and " + detail::num(motor_rpm) + " rev/min the motor gives " +
                     detail::num(motor_w) + " W and the no-load loss takes " + detail::num(loss) +
                     " W: nothing is left to grind (raise the current or lower the speed)");
  return motor_w - loss;
}

Prediction predict_at_current(const Process& p, double current_a) {
  std::vector<std::string> notes;
  const double useful = useful_power_from_current(p, current_a, notes);
  Prediction r = predict_at_power(p, useful);
  r.mode = "current";
  r.motor_current_a = current_a;
  r.warnings.insert(r.warnings.begin(), notes.begin(), notes.end());
  if (!r.motor_power_w) r.motor_power_w = useful;  // no loss model: all of it
  return r;
}

}  // namespace chatter::grinding
