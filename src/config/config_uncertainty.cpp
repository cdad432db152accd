// [uncertainty] of the TOML config (docs/config.md, "Uncertainty";
// docs/uncertainty.md): 1-sigma spreads of the modes and cutting coefficients.
#include "config_sections.hpp"

#include <cstddef>
#include <sstream>
#include <string>
#include <vector>

namespace chatter::config_detail {

/// `[uncertainty]`: 1σ spreads in percent (docs/config.md, docs/uncertainty.md).
/// Mode keys: one number for every mode, or an array with one value per mode
/// (tool modes, then workpiece modes). Every rule of
/// UncertaintySpreads::validate is checked here with the key and the value
/// as written.
std::optional<UncertaintySpreads> read_uncertainty(const Table& root, const StructuralModel& model,
                                                   const Process& process) {
  const auto t = root.table("uncertainty");
  if (!t) return std::nullopt;
  const Document& doc = root.doc();
  constexpr std::string_view kUncertaintyKeys[] = {"frequency_percent",
                                                   "damping_percent",
                                                   "stiffness_percent",
                                                   "tangential_coefficient_percent",
                                                   "radial_coefficient_percent",
                                                   "feed_force_coefficient_percent"};
  t->reject_unknown(kUncertaintyKeys);
  const std::size_t mark = doc.error_count();
  // 3 s < 1: a 3-sigma draw p (1 - 3 s) stays > 0.
  const Range kSpreadPercent{"in [0, 33.33) % (a 3-sigma draw p (1 - 3 s / 100) must stay > 0)", 0.0, false,
                             100.0 / kUncertaintyTruncationSigma, true};
  const std::size_t n_modes = model.tool.modes.size() + model.workpiece.modes.size();
  UncertaintySpreads s;
  // A spread below 0.1 % is a fraction typed as percent (0.05 for 5 %).
  const Usual kSpreadUsual{0.1, 100.0 / kUncertaintyTruncationSigma, "the 0.1 to 33 % of measured spreads", 100.0,
                           "fractions, not percent"};
  auto warn_spread = [&](std::string_view key, std::optional<double> p) {
    if (p && *p > 0.0) warn_usual(*t, key, p, kSpreadUsual);
  };
  auto mode_list = [&](std::string_view key, std::vector<double>* out) {
    const auto v = t->number_list(key, kSpreadPercent);
    if (!v) return;
    // (Not the frequency: a modal fit gives it to 0.01 %, a real spread.)
    for (const double p : *v)
      if (key != "frequency_percent" && p > 0.0 && p < kSpreadUsual.lo) {
        warn_spread(key, p);
        break;
      }
    const toml::node& n = *t->find(key);
    if (n.as_array() && v->size() != n_modes) {
      doc.error(t->path_of(key), n,
                "must have one value per mode: " + std::to_string(n_modes) +
                    " (tool modes, then workpiece modes), or be one number for every mode");
      return;
    }
    for (const double p : *v) out->push_back(p / 100.0);
  };
  mode_list("frequency_percent", &s.frequency);
  mode_list("damping_percent", &s.damping);
  mode_list("stiffness_percent", &s.stiffness);
  std::vector<const Mode*> modes;
  for (const Mode& md : model.tool.modes) modes.push_back(&md);
  for (const Mode& md : model.workpiece.modes) modes.push_back(&md);
  for (std::size_t m = 0; m < modes.size() && !s.damping.empty(); ++m) {
    const double sd = s.damping_of(m), zeta = modes[m]->damping_ratio;
    if (zeta * (1.0 + kUncertaintyTruncationSigma * sd) < 1.0) continue;
    const bool one = s.damping.size() == 1;
    const Path where = one ? t->path_of("damping_percent") : element(t->path_of("damping_percent"), m);
    const toml::node& n = one ? *t->find("damping_percent") : *t->find("damping_percent")->as_array()->get(m);
    std::ostringstream rule;
    rule << "with damping ratio " << zeta << " (" << (m < model.tool.modes.size() ? "tool" : "workpiece")
         << " mode " << (m < model.tool.modes.size() ? m : m - model.tool.modes.size())
         << ") a 3-sigma draw reaches " << zeta * (1.0 + kUncertaintyTruncationSigma * sd)
         << ": must be < " << 100.0 * (1.0 / zeta - 1.0) / kUncertaintyTruncationSigma
         << " (a damping ratio stays < 1)";
    doc.error(where, n, rule.str());
    break;
  }
  const bool milling = process.rotating_edges();
  const auto kt = t->number("tangential_coefficient_percent", kSpreadPercent);
  const auto kr = t->number("radial_coefficient_percent", kSpreadPercent);
  const auto kf = t->number("feed_force_coefficient_percent", kSpreadPercent);
  warn_spread("tangential_coefficient_percent", kt);
  warn_spread("radial_coefficient_percent", kr);
  warn_spread("feed_force_coefficient_percent", kf);
  for (const std::string_view key : {"tangential_coefficient_percent", "radial_coefficient_percent"})
    if (!milling && t->has(key))
      doc.error(t->path_of(key), *t->find(key), "only for milling (turning: feed_force_coefficient_percent)");
  if (milling && t->has("feed_force_coefficient_percent"))
    doc.error(t->path_of("feed_force_coefficient_percent"), *t->find("feed_force_coefficient_percent"),
              "only for turning (milling: tangential_coefficient_percent, radial_coefficient_percent)");
  if (milling) {
    s.tangential = kt.value_or(0.0) / 100.0;
    s.radial = kr.value_or(0.0) / 100.0;
  } else {
    s.tangential = kf.value_or(0.0) / 100.0;
  }
  stop_if_errors_since(doc, mark);
  if (const std::string why = s.validate(model, process); !why.empty())
    doc.fail_key("uncertainty", why);  // a rule above is missing: still name the table
  return s;
}

}  // namespace chatter::config_detail
