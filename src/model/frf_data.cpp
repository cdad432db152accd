#include "chatter/frf_data.hpp"
#include "chatter/number_text.hpp"

#include <cmath>

#include "chatter/error.hpp"

namespace chatter {
namespace {

}  // namespace

void validate(const FrfTable& t, const std::string& whole, const std::function<std::string(std::size_t)>& where) {
  if (t.frequency_hz.size() != t.value.size())
    throw InputError(whole + ": " + std::to_string(t.frequency_hz.size()) + " frequencies but " +
                     std::to_string(t.value.size()) + " values");
  if (t.frequency_hz.size() < 2)
    throw InputError(whole + ": " + std::to_string(t.frequency_hz.size()) +
                     " frequency line(s), an FRF needs at least 2");
  for (std::size_t i = 0; i < t.frequency_hz.size(); ++i) {
    const double f = t.frequency_hz[i];
    if (!std::isfinite(f)) throw InputError(where(i) + ": frequency " + number_text(f, 10) + " Hz is not finite");
    if (f < 0.0) throw InputError(where(i) + ": negative frequency " + number_text(f, 10) + " Hz (must be >= 0)");
    if (!std::isfinite(t.value[i].real()) || !std::isfinite(t.value[i].imag()))
      throw InputError(where(i) + ": value (" + number_text(t.value[i].real(), 10) + ", " +
                       number_text(t.value[i].imag(), 10) + ") at " + number_text(f, 10) + " Hz is not finite");
    if (i > 0 && f <= t.frequency_hz[i - 1]) {
      const std::string what = f < t.frequency_hz[i - 1] ? "decreasing frequency " : "repeated frequency ";
      throw InputError(where(i) + ": " + what + number_text(f, 10) + " Hz after " + number_text(t.frequency_hz[i - 1], 10) +
                       " Hz (frequencies must increase strictly)");
    }
  }
}

void validate(const FrfTable& t) {
  validate(t, t.source, [&](std::size_t i) { return t.source + ": frequency line " + std::to_string(i + 1); });
}

}  // namespace chatter
