// [process] speed_variation of the TOML config (docs/config.md, "Process";
// docs/ssv.md): spindle speed variation, an inline table
//   speed_variation = { amplitude_ratio = 0.1, frequency_ratio = 0.05 }
// with both keys required together.
#include "config_sections.hpp"

#include <string>

namespace chatter::config_detail {
namespace {

constexpr std::string_view kKeys[] = {"amplitude_ratio", "frequency_ratio"};
const Range kAmplitude{"in [0, 1) (the speed swings between (1 - R_VA) and (1 + R_VA) times the mean)", 0.0, false,
                       1.0, true};
const Range kFrequency{"> 0 (modulation frequency / spindle frequency)", 0.0, true, kInf, true};

}  // namespace

std::optional<SpeedVariation> read_speed_variation(const Table& process) {
  const auto t = process.table("speed_variation");
  if (!t) return std::nullopt;
  const Document& doc = process.doc();
  const std::size_t mark = doc.error_count();
  t->reject_unknown(kKeys);
  for (const std::string_view key : kKeys)
    if (!t->has(key) && !t->meant(key))
      doc.error_key(t->path_of(key),
                    "missing: speed_variation needs both amplitude_ratio (R_VA in [0, 1)) and frequency_ratio "
                    "(R_VF > 0)");
  const auto rva = t->number("amplitude_ratio", kAmplitude);
  const auto rvf = t->number("frequency_ratio", kFrequency);
  stop_if_errors_since(doc, mark);
  if (!rva || !rvf) throw Skip{};
  if (*rva > kLargeSpeedVariation)
    doc.warn(t->path_of("amplitude_ratio"), *t->find("amplitude_ratio"),
             "a swing of more than +-" + number_text(100.0 * kLargeSpeedVariation) +
                 " % of the mean speed is beyond what spindle drives follow (usual R_VA: 0.05 to 0.3)");
  if (*rvf > 1.0)
    doc.warn(t->path_of("frequency_ratio"), *t->find("frequency_ratio"),
             "a modulation faster than the spindle turns (R_VF > 1) is beyond what spindle drives follow (usual "
             "R_VF: 0.005 to 0.5)");
  return SpeedVariation{*rva, *rvf};
}

}  // namespace chatter::config_detail
