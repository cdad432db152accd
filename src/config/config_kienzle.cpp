// [process] force_law = "kienzle" of a turning config (docs/config.md,
// "Process"; docs/cutting_law.md, "Kienzle's law"): the size effect
//   force_law = "kienzle"
//   specific_force_n_per_mm2 = { tangential = 883, feed = 748 }   # k_1.1 at h = 1 mm
//   exponent = { tangential = 0.44, feed = 0.232 }                # m
// with the radial direction optional in both (the same directions in both).
#include "config_sections.hpp"

#include <string>

#include "chatter/usual_bands.hpp"

namespace chatter::config_detail {
namespace {

constexpr std::string_view kDirections[] = {"tangential", "feed", "radial"};
const Range kExponent{"in [0, 1) (0 = the linear law; at 1 the force would not grow with the chip)", 0.0, false, 1.0,
                      true};

// One direction's k_1.1 (N/mm² as written) and m; nullopt when absent or bad.
std::optional<KienzleTerm> read_term(const Table& k, const Table& m, std::string_view direction, bool required) {
  const Document& doc = k.doc();
  const bool given_k = k.has(direction), given_m = m.has(direction);
  if (required || given_k || given_m) {
    if (!given_k && !k.meant(direction))
      doc.error_key(k.path_of(direction), "missing: the " + std::string(direction) +
                                              " direction's k_1.1 (N/mm^2 at a 1 mm chip)" +
                                              (required ? "" : ", given with its exponent"));
    if (!given_m && !m.meant(direction))
      doc.error_key(m.path_of(direction), "missing: the " + std::string(direction) + " direction's exponent m" +
                                              (required ? "" : ", given with its k_1.1"));
  }
  const auto kv = k.number(direction, kPositive);
  const auto mv = m.number(direction, kExponent);
  warn_usual(k, direction, kv, usual::kKienzleSpecificForceNPerMm2);
  if (mv && *mv > 0.0) warn_usual(m, direction, mv, usual::kKienzleExponent);  // 0: the linear law, on purpose
  if (!kv || !mv) return std::nullopt;
  return KienzleTerm{*kv * 1e6, *mv};
}

}  // namespace

std::optional<KienzleLaw> read_kienzle(const Table& process, std::optional<double> feed_mm) {
  const Document& doc = process.doc();
  const std::optional<std::string> law = process.string("force_law", "must be \"linear\" or \"kienzle\"");
  if (law && *law != "linear" && *law != "kienzle")
    doc.error(process.path_of("force_law"), *process.find("force_law"),
              "must be \"linear\" (forces proportional to the chip) or \"kienzle\" (the size effect: "
              "specific_force_n_per_mm2 and exponent per direction)");
  if (law.value_or("linear") != "kienzle") {
    for (const std::string_view key : {"specific_force_n_per_mm2", "exponent"})
      if (const toml::node* n = process.find(key))
        doc.error(process.path_of(key), *n, "only with force_law = \"kienzle\"");
    return std::nullopt;
  }
  for (const std::string_view key : {"feed_force_coefficient_n_per_m2", "feed_force_coefficient_n_per_mm2",
                                     "radial_force_coefficient_n_per_m2", "radial_force_coefficient_n_per_mm2"})
    if (const toml::node* n = process.find(key))
      doc.error(process.path_of(key), *n,
                "not with force_law = \"kienzle\": its feed and radial terms give K_f and K_r at each feed");
  const std::size_t mark = doc.error_count();
  for (const std::string_view key : {"specific_force_n_per_mm2", "exponent"})
    if (!process.has(key))
      doc.error_key(process.path_of(key), "missing: force_law = \"kienzle\" needs specific_force_n_per_mm2 (k_1.1, "
                                          "N/mm^2) and exponent (m), each { tangential = ..., feed = ... } "
                                          "(radial optional)");
  if (!feed_mm && !process.meant("feed_per_rev_mm"))
    doc.error_key(process.path_of("feed_per_rev_mm"),
                  "missing: force_law = \"kienzle\" needs the feed per revolution (mm): the regenerative side is "
                  "linearised at its mean chip (a check row's or a set-point's own feed replaces it there)");
  const auto k = process.table("specific_force_n_per_mm2");
  const auto m = process.table("exponent");
  if (!k || !m) {
    stop_if_errors_since(doc, mark);
    throw Skip{};
  }
  k->reject_unknown(kDirections);
  m->reject_unknown(kDirections);
  KienzleLaw out;
  const auto tangential = read_term(*k, *m, "tangential", true);
  const auto feed = read_term(*k, *m, "feed", true);
  const auto radial = read_term(*k, *m, "radial", false);
  stop_if_errors_since(doc, mark);
  if (!tangential || !feed || !feed_mm) throw Skip{};
  out.tangential = *tangential;
  out.feed = *feed;
  if (radial) out.radial = *radial;
  out.feed_m = *feed_mm * 1e-3;
  return out;
}

}  // namespace chatter::config_detail
