// [grinding] of a grinding config (include/chatter/io/grinding_config.hpp;
// key reference docs/grinding.md and docs/config.md "[grinding]"): the wheel
// and its kinematics, seed 001's mechanistic model with its impacts table,
// the energy partition, the no-load loss and seed 000's empirical models.
#include "config_sections.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>
#include "chatter/kinematics.hpp"

namespace chatter::config_detail {
namespace {

using grinding::EmpiricalForm;
using grinding::EmpiricalModel;
using grinding::EmpiricalVariable;

constexpr std::string_view kGrindingKeys[] = {
    "wheel_diameter_mm", "wheel_width_mm",  "wheel_rpm",     "motor_rpm",          "transmission_ratio",
    "feed_mm_per_s",     "force_ratio",     "density_kg_per_m3", "wheel_min_diameter_mm",
    "edge_coefficient_n_per_mm", "cutting_coefficient_n_per_mm2", "impacts_per_turn", "impacts",
    "energy_partition",  "no_load_loss",    "models", "motor"};

// Hard bounds: beyond them a value is not a grinding wheel or process.
constexpr Plausible kDiameterBound{0.0, 5000.0, "must be <= 5000 mm"};
constexpr Plausible kWidthBound{0.0, 1000.0, "must be <= 1000 mm"};
constexpr Plausible kRpmBound{0.0, 2e5, "must be <= 200 000 rev/min"};
constexpr Plausible kFeedBound{0.0, 1e5, "must be <= 100 000 mm/s"};
constexpr Plausible kEdgeBound{0.0, 1e7, "must be <= 1e7 N/mm (a value in N/m? divide it by 1e3)"};
constexpr Plausible kCuttingBound{0.0, 1e9, "must be <= 1e9 N/mm^2 (a value in N/m^2? divide it by 1e6)"};
constexpr Plausible kImpactsBound{0.0, 1000.0, "must be <= 1000 impacts per turn"};

const Range kForceRatio{"in (0, 10]", 0.0, true, 10.0, false};
const Range kFraction{"in [0, 1]", 0.0, false, 1.0, false};
// A speed written in rev/s where rev/min was meant reads this much too low.
constexpr double kRevPerSToRpm = rpm_from_revolutions_per_s(1.0);

std::optional<double> bounded(const Table& t, std::string_view key, std::optional<double> v, const Plausible& b) {
  if (v && !t.plausible(key, *v, b)) return std::nullopt;
  return v;
}

// ---------------------------------------------------------------- impacts

std::optional<grinding::ImpactsPerTurn> read_impacts(const Table& g) {
  const Document& doc = g.doc();
  const bool number = g.has("impacts_per_turn"), table = g.has("impacts");
  if (number && table) {
    doc.error(g.path_of("impacts"), *g.find("impacts"),
              "not with impacts_per_turn (give one: a number, or the table [[grinding.impacts]])");
    return std::nullopt;
  }
  if (number) {
    const auto v = bounded(g, "impacts_per_turn", g.number("impacts_per_turn", kPositive), kImpactsBound);
    warn_usual(g, "impacts_per_turn", v, usual::kImpactsPerTurn);
    if (!v) return std::nullopt;
    return grinding::ImpactsPerTurn(*v);
  }
  if (!table) return std::nullopt;
  const Path path = g.path_of("impacts");
  const toml::array* rows = g.find("impacts")->as_array();
  if (!rows || rows->empty() || !rows->is_array_of_tables()) {
    doc.error(path, *g.find("impacts"), "must be an array of tables ([[grinding.impacts]] power_w = ..., impacts_per_turn = ...)");
    return std::nullopt;
  }
  std::vector<double> power, impacts;
  bool ok = true;
  for (std::size_t i = 0; i < rows->size(); ++i) {
    const Table row(doc, *rows->get(i)->as_table(), element(path, i));
    constexpr std::string_view kRowKeys[] = {"power_w", "impacts_per_turn"};
    row.reject_unknown(kRowKeys);
    const auto p = row.required_number("power_w", kPositive, "W");
    const auto n = bounded(row, "impacts_per_turn", row.required_number("impacts_per_turn", kPositive, ""), kImpactsBound);
    if (p && !power.empty() && ok && !(*p > power.back())) {
      doc.error(row.path_of("power_w"), *row.find("power_w"),
                "must increase from row to row (the previous row has " + number_text(power.back()) + " W)");
      ok = false;
    }
    if (!p || !n) {
      ok = false;
      continue;
    }
    power.push_back(*p);
    impacts.push_back(*n);
    warn_usual(row, "power_w", p, usual::kGrindingPowerW);
    warn_usual(row, "impacts_per_turn", n, usual::kImpactsPerTurn);
  }
  if (!ok) return std::nullopt;
  return model_checked(g, [&] { return grinding::ImpactsPerTurn(power, impacts); });
}

// --------------------------------------------------------- energy partition

// [[grinding.energy_partition.beta_table]]: one row per feed (increasing),
// its powers (increasing) and betas (seed 001 table 2.2).
std::optional<grinding::BetaTable> read_beta_table(const Table& t) {
  const Document& doc = t.doc();
  const Path path = t.path_of("beta_table");
  const toml::array* rows = t.find("beta_table")->as_array();
  if (!rows || rows->empty() || !rows->is_array_of_tables()) {
    doc.error(path, *t.find("beta_table"),
              "must be an array of tables ([[grinding.energy_partition.beta_table]] feed_mm_per_s = ..., "
              "power_w = [...], beta = [...])");
    return std::nullopt;
  }
  std::vector<grinding::BetaTable::Row> out;
  bool ok = true;
  for (std::size_t i = 0; i < rows->size(); ++i) {
    const Table row(doc, *rows->get(i)->as_table(), element(path, i));
    constexpr std::string_view kRowKeys[] = {"feed_mm_per_s", "power_w", "beta"};
    row.reject_unknown(kRowKeys);
    const auto f = bounded(row, "feed_mm_per_s", row.required_number("feed_mm_per_s", kPositive, "mm/s"), kFeedBound);
    const auto p = row.number_list("power_w", kPositive);
    const auto b = row.number_list("beta", kFraction);
    for (const char* k : {"power_w", "beta"})
      if (!row.has(k)) doc.error_key(row.path_of(k), "missing (required: a list, one per power)");
    if (f && !out.empty() && !(*f * 1e-3 > out.back().feed_m_per_s)) {
      doc.error(row.path_of("feed_mm_per_s"), *row.find("feed_mm_per_s"),
                "must increase from row to row (the previous row has " + number_text(out.back().feed_m_per_s * 1e3) +
                    " mm/s)");
      ok = false;
    }
    if (p && b && p->size() != b->size()) {
      doc.error(row.path_of("beta"), *row.find("beta"),
                "must hold one beta per power (" + std::to_string(p->size()) + " powers, " + std::to_string(b->size()) +
                    " betas)");
      ok = false;
    }
    if (p)
      for (std::size_t k = 1; k < p->size(); ++k)
        if (!((*p)[k] > (*p)[k - 1])) {
          const auto [ip, node] = row.list_item("power_w", k);
          doc.error(ip, *node, "the powers must increase along the row");
          ok = false;
          break;
        }
    if (!f || !p || !b) {
      ok = false;
      continue;
    }
    warn_usual(row, "feed_mm_per_s", f, usual::kGrindingFeedMmPerS);
    for (const double w : *p) warn_usual(row, "power_w", std::optional<double>(w), usual::kGrindingPowerW);
    out.push_back({*f * 1e-3, *p, *b});
  }
  if (!ok) return std::nullopt;
  return model_checked(t, [&] { return grinding::BetaTable(out); });
}

std::optional<grinding::EnergyPartitionModel> read_partition(const Table& g, bool mechanistic) {
  const auto t = g.table("energy_partition");
  if (!t) return std::nullopt;
  const Document& doc = g.doc();
  const std::size_t mark = doc.error_count();
  constexpr std::string_view kKeys[] = {"model", "u_ch_j_per_mm3", "alpha", "beta", "beta_table"};
  t->reject_unknown(kKeys);
  constexpr std::string_view kRule = R"(must be "malkin", "modified" or "power")";
  grinding::EnergyPartitionModel e;
  if (!t->has("model")) doc.error_key(t->path_of("model"), R"(missing (required, "malkin", "modified" or "power"))");
  if (const auto m = t->string("model", kRule)) {
    if (*m == "malkin") e.model = grinding::PartitionModel::kMalkin;
    else if (*m == "modified") e.model = grinding::PartitionModel::kModified;
    else if (*m == "power") e.model = grinding::PartitionModel::kPower;
    else doc.error(t->path_of("model"), *t->find("model"), kRule);
  }
  stop_if_errors_since(doc, mark);
  if (e.model == grinding::PartitionModel::kPower) {
    if (!mechanistic)
      doc.error_key(t->path_of("model"), "\"power\" splits the power into friction and chip: it needs the mechanistic "
                                         "model (edge_coefficient_n_per_mm, cutting_coefficient_n_per_mm2)");
    const auto a = t->required_number("alpha", kFraction, "");
    std::optional<double> b;
    if (t->has("beta") && t->has("beta_table"))
      doc.error(t->path_of("beta_table"), *t->find("beta_table"),
                "not with beta (give one: a number, or the table [[grinding.energy_partition.beta_table]])");
    else if (t->has("beta_table"))
      e.beta_table = read_beta_table(*t);
    else
      b = t->required_number("beta", kFraction, "");
    if (t->has("u_ch_j_per_mm3"))
      doc.error(t->path_of("u_ch_j_per_mm3"), *t->find("u_ch_j_per_mm3"), "only for model = \"malkin\" or \"modified\"");
    stop_if_errors_since(doc, mark);
    warn_usual(*t, "alpha", a, usual::kFrictionHeatFraction);
    e.alpha = *a;
    if (b) e.beta = *b;
  } else {
    const auto u = t->required_number("u_ch_j_per_mm3", kPositive, "J/mm^3");
    for (const char* k : {"alpha", "beta", "beta_table"})
      if (t->has(k)) doc.error(t->path_of(k), *t->find(k), "only for model = \"power\"");
    stop_if_errors_since(doc, mark);
    warn_usual(*t, "u_ch_j_per_mm3", u, {1.0, 100.0, "the 1 to 100 J/mm^3 of chip formation (steel 13.8)", 1e-9, "J/m^3"});
    e.chip_energy_j_per_m3 = *u * 1e9;
  }
  return e;
}

// ------------------------------------------------------------ no-load loss

std::optional<grinding::NoLoadLoss> read_no_load(const Table& g) {
  const auto t = g.table("no_load_loss");
  if (!t) return std::nullopt;
  const std::size_t mark = g.doc().error_count();
  constexpr std::string_view kKeys[] = {"c0", "speed_exponent", "diameter_exponent"};
  t->reject_unknown(kKeys);
  const auto c0 = t->required_number("c0", kNonNegative, "W / ((rad/s)^speed_exponent mm^diameter_exponent)");
  const auto k = t->required_number("speed_exponent", kAnyNumber, "");
  const auto x = t->number("diameter_exponent", kAnyNumber);
  stop_if_errors_since(g.doc(), mark);
  warn_usual(*t, "speed_exponent", k, {0.5, 4.0, "the 0.5 to 4 of drag losses (3 for pure drag, 1.3 with air injection)"});
  if (x && *x != 0.0)
    warn_usual(*t, "diameter_exponent", x, {0.05, 4.0, "the 0.05 to 4 of drag losses' diameter exponents (seed 000: 0.35)"});
  return grinding::NoLoadLoss{*c0, *k, x.value_or(0.0)};
}

// A [low, high] pair of `t`'s key (low < high), recorded as an error
// otherwise; nullopt when absent or bad. `where` ends the rule's text.
std::optional<grinding::Interval> read_interval(const Table& t, std::string_view key, const Range& range,
                                                std::string_view where = "") {
  const auto v = t.number_list(key, range);
  if (!v) return std::nullopt;
  if (v->size() != 2 || !((*v)[0] < (*v)[1])) {
    t.doc().error(t.path_of(key), *t.find(key), "must be [low, high] with low < high" + std::string(where));
    return std::nullopt;
  }
  return grinding::Interval{(*v)[0], (*v)[1]};
}

// The coefficients key holds the form's count, else an error naming both.
void check_coefficient_count(const Table& t, grinding::EmpiricalForm form, std::size_t given) {
  const std::size_t need = grinding::coefficient_count(form);
  if (given != need)
    t.doc().error(t.path_of("coefficients"), *t.find("coefficients"),
                  "must hold " + std::to_string(need) + " numbers for form = \"" + grinding::empirical_form_name(form) +
                      "\" (" + std::to_string(given) + " given)");
}

// ---------------------------------------------------------- empirical models

// [grinding.models.<name>.fit]: the fit's statistics (grind fit --out writes
// them): covariance p x p of its linear parameters, residual variance, dof.
std::optional<grinding::FitUncertainty> read_fit_statistics(const Table& f, std::size_t p) {
  const Document& doc = f.doc();
  const std::size_t mark = doc.error_count();
  constexpr std::string_view kKeys[] = {"covariance", "residual_variance", "degrees_of_freedom"};
  f.reject_unknown(kKeys);
  grinding::FitUncertainty u;
  const auto s2 = f.required_number("residual_variance", kNonNegative, "");
  if (!f.has("degrees_of_freedom")) doc.error_key(f.path_of("degrees_of_freedom"), "missing (required, an integer >= 1)");
  const auto dof = f.integer("degrees_of_freedom", 1);
  const toml::node* c = f.find("covariance");
  const std::string shape = "must be " + std::to_string(p) + " rows of " + std::to_string(p) +
                            " numbers (one per coefficient, as grind fit --out writes it)";
  if (!c) doc.error_key(f.path_of("covariance"), "missing (required: " + shape + ")");
  else if (const toml::array* rows = c->as_array(); !rows || rows->size() != p) {
    doc.error(f.path_of("covariance"), *c, shape);
  } else {
    for (std::size_t i = 0; i < p; ++i) {
      const toml::array* row = rows->get(i)->as_array();
      if (!row || row->size() != p) {
        doc.error(element(f.path_of("covariance"), i), *rows->get(i), shape);
        break;
      }
      for (std::size_t j = 0; j < p; ++j) {
        const toml::node& x = *row->get(j);
        std::optional<double> v;
        if (const auto* d = x.as_floating_point()) v = d->get();
        else if (const auto* n = x.as_integer()) v = static_cast<double>(n->get());
        if (!v || !std::isfinite(*v)) {
          doc.error(element(element(f.path_of("covariance"), i), j), x, "must be a finite number");
          continue;
        }
        u.covariance.push_back(*v);
      }
    }
  }
  stop_if_errors_since(doc, mark);
  u.residual_variance = *s2;
  u.degrees_of_freedom = *dof;
  return u;
}

std::optional<EmpiricalModel> read_model(const Table& models, std::string_view name) {
  const auto t = models.table(name);
  if (!t) return std::nullopt;
  const Document& doc = models.doc();
  const std::size_t mark = doc.error_count();
  constexpr std::string_view kKeys[] = {"form", "coefficients", "variables", "domain", "fit"};
  t->reject_unknown(kKeys);
  constexpr std::string_view kFormRule = R"(must be "poly11", "poly22", "poly33", "power_law" or "hahn_lindsay")";
  EmpiricalModel m;
  if (!t->has("form")) doc.error_key(t->path_of("form"), "missing (required: poly11, poly22, poly33, power_law or hahn_lindsay)");
  if (const auto f = t->string("form", kFormRule)) {
    bool known = false;
    for (EmpiricalForm e : {EmpiricalForm::kPoly11, EmpiricalForm::kPoly22, EmpiricalForm::kPoly33,
                            EmpiricalForm::kPowerLaw, EmpiricalForm::kHahnLindsay})
      if (*f == grinding::empirical_form_name(e)) {
        m.form = e;
        known = true;
      }
    if (!known) doc.error(t->path_of("form"), *t->find("form"), kFormRule);
  }
  if (!t->has("coefficients")) doc.error_key(t->path_of("coefficients"), "missing (required, the model's coefficients in docs/grinding.md's term order)");
  const auto c = t->number_list("coefficients", kAnyNumber);
  stop_if_errors_since(doc, mark);
  m.coefficients = *c;
  const std::size_t need = grinding::coefficient_count(m.form);
  check_coefficient_count(*t, m.form, m.coefficients.size());
  // The second variable: the useful power (default) or the normal force.
  m.variable = m.form == EmpiricalForm::kHahnLindsay ? EmpiricalVariable::kNormalForce : EmpiricalVariable::kUsefulPower;
  if (const toml::node* v = t->find("variables")) {
    const toml::array* a = v->as_array();
    std::vector<std::string> names;
    if (a)
      for (const toml::node& e : *a)
        if (const auto* s = e.as_string()) names.push_back(s->get());
    const bool power = std::find(names.begin(), names.end(), "useful_power_w") != names.end();
    const bool force = std::find(names.begin(), names.end(), "normal_force_n") != names.end();
    if (!a || names.size() != a->size() || power == force)
      doc.error(t->path_of("variables"), *v,
                "must be a list of names holding either \"useful_power_w\" or \"normal_force_n\" (with "
                "\"cutting_speed_m_per_s\"; power_law also \"wheel_rpm\", \"wheel_diameter_mm\")");
    else
      m.variable = power ? EmpiricalVariable::kUsefulPower : EmpiricalVariable::kNormalForce;
  }
  if (m.form == EmpiricalForm::kHahnLindsay && m.variable != EmpiricalVariable::kNormalForce)
    doc.error_key(t->path_of("variables"), "hahn_lindsay reads the normal force (variables = [\"normal_force_n\", "
                                           "\"cutting_speed_m_per_s\"])");
  if (name == "normal_force" && m.variable == EmpiricalVariable::kNormalForce)
    doc.error_key(t->path_of("variables"), "the normal-force model reads the useful power, not the normal force");
  if (m.form == EmpiricalForm::kPowerLaw && !m.coefficients.empty() && !(m.coefficients[0] > 0.0))
    doc.error(element(t->path_of("coefficients"), 0), *t->find("coefficients"), "the power law's constant C must be > 0");
  if (const auto d = t->table("domain")) {
    constexpr std::string_view kDomainKeys[] = {"cutting_speed_m_per_s", "useful_power_w", "normal_force_n",
                                                "wheel_diameter_mm", "wheel_rpm"};
    d->reject_unknown(kDomainKeys);
    auto interval = [&](std::string_view key) { return read_interval(*d, key, kAnyNumber); };
    m.domain.cutting_speed_m_per_s = interval("cutting_speed_m_per_s");
    m.domain.useful_power_w = interval("useful_power_w");
    m.domain.normal_force_n = interval("normal_force_n");
    m.domain.wheel_diameter_mm = interval("wheel_diameter_mm");
    m.domain.wheel_rpm = interval("wheel_rpm");
  }
  if (const auto f = t->table("fit")) m.uncertainty = read_fit_statistics(*f, need);
  stop_if_errors_since(doc, mark);
  if (m.uncertainty)
    if (const std::string e = m.validate(); !e.empty()) doc.error_key(t->path_of("fit"), e);
  stop_if_errors_since(doc, mark);
  return m;
}

// [grinding.motor]: the motor's power from current and motor speed (seed 000
// eq. 4.26, a cubic fitted on a dynamometer), its measured range and limit.
std::optional<grinding::MotorMap> read_motor(const Table& g) {
  const auto t = g.table("motor");
  if (!t) return std::nullopt;
  const Document& doc = g.doc();
  const std::size_t mark = doc.error_count();
  constexpr std::string_view kKeys[] = {"form", "coefficients", "current_a", "motor_rpm", "max_current_a"};
  t->reject_unknown(kKeys);
  constexpr std::string_view kFormRule = R"(must be "poly11", "poly22" or "poly33" (x = current A, y = motor rev/min))";
  grinding::MotorMap m;
  if (!t->has("form")) doc.error_key(t->path_of("form"), "missing (required: poly11, poly22 or poly33)");
  if (const auto f = t->string("form", kFormRule)) {
    if (*f == "poly11") m.form = EmpiricalForm::kPoly11;
    else if (*f == "poly22") m.form = EmpiricalForm::kPoly22;
    else if (*f == "poly33") m.form = EmpiricalForm::kPoly33;
    else doc.error(t->path_of("form"), *t->find("form"), kFormRule);
  }
  if (!t->has("coefficients"))
    doc.error_key(t->path_of("coefficients"), "missing (required: the map's coefficients, MATLAB's term order, W)");
  const auto c = t->number_list("coefficients", kAnyNumber);
  m.current_a = read_interval(*t, "current_a", kNonNegative, " (where the map was measured)");
  m.motor_rpm = read_interval(*t, "motor_rpm", kNonNegative, " (where the map was measured)");
  m.max_current_a = t->number("max_current_a", kPositive);
  stop_if_errors_since(doc, mark);
  m.coefficients = *c;
  check_coefficient_count(*t, m.form, m.coefficients.size());
  warn_usual(*t, "max_current_a", m.max_current_a, usual::kMotorCurrentA);
  stop_if_errors_since(doc, mark);
  return m;
}

grinding::EmpiricalModels read_models(const Table& g) {
  grinding::EmpiricalModels out;
  const auto t = g.table("models");
  if (!t) return out;
  constexpr std::string_view kKeys[] = {"removal", "wear", "normal_force"};
  t->reject_unknown(kKeys);
  if (auto m = attempt([&] { return read_model(*t, "removal"); })) out.removal = *m;
  if (auto m = attempt([&] { return read_model(*t, "wear"); })) out.wear = *m;
  if (auto m = attempt([&] { return read_model(*t, "normal_force"); })) out.normal_force = *m;
  return out;
}

}  // namespace

grinding::Process read_grinding(const Table& root) {
  const auto g = root.table("grinding");
  const Document& doc = root.doc();
  if (!g) doc.fail_key("grinding", "missing (required table)");
  g->reject_unknown(kGrindingKeys);
  const std::size_t mark = doc.error_count();
  grinding::Process p;

  const auto d = bounded(*g, "wheel_diameter_mm", g->required_number("wheel_diameter_mm", kPositive, "mm"), kDiameterBound);
  const auto e = bounded(*g, "wheel_width_mm", g->required_number("wheel_width_mm", kPositive, "mm"), kWidthBound);
  // The wheel speed: wheel_rpm, or motor_rpm x transmission_ratio (seed 000:
  // 2000 rev/min x 1.125 = 2250 rev/min at the wheel).
  std::optional<double> rpm;
  const bool by_wheel = g->has("wheel_rpm"), by_motor = g->has("motor_rpm") || g->has("transmission_ratio");
  if (by_wheel && by_motor) {
    doc.error_key(g->path_of(g->has("motor_rpm") ? "motor_rpm" : "transmission_ratio"),
                  "not with wheel_rpm (give wheel_rpm, or motor_rpm and transmission_ratio)");
  } else if (by_motor) {
    const auto motor = bounded(*g, "motor_rpm", g->required_number("motor_rpm", kPositive, "rev/min"), kRpmBound);
    const auto ratio = g->required_number("transmission_ratio", kPositive, "wheel rev / motor rev");
    warn_usual(*g, "motor_rpm", motor, {500.0, 30000.0, "the 500 to 30 000 rev/min of grinder motors", kRevPerSToRpm, "rev/s"});
    warn_usual(*g, "transmission_ratio", ratio, {0.1, 10.0, "the 0.1 to 10 of grinder transmissions"});
    if (motor && ratio) rpm = *motor * *ratio;
    if (ratio) p.transmission_ratio = *ratio;
  } else if (!g->meant("wheel_rpm") && !by_wheel) {
    doc.error_key(g->path_of("wheel_rpm"), "missing (required, rev/min; or motor_rpm and transmission_ratio)");
  } else {
    rpm = bounded(*g, "wheel_rpm", g->number("wheel_rpm", kPositive), kRpmBound);
    warn_usual(*g, "wheel_rpm", rpm, usual::kWheelRpm);
  }
  const auto feed = bounded(*g, "feed_mm_per_s", g->required_number("feed_mm_per_s", kPositive, "mm/s"), kFeedBound);
  const auto mu = g->required_number("force_ratio", kForceRatio, "F_T/F_N");
  const auto rho = g->number("density_kg_per_m3", kPositive);
  const auto dmin = g->number("wheel_min_diameter_mm", kPositive);
  if (d && dmin && !(*dmin < *d))
    doc.error(g->path_of("wheel_min_diameter_mm"), *g->find("wheel_min_diameter_mm"),
              "must be below wheel_diameter_mm (" + number_text(*d) + " mm)");
  warn_usual(*g, "wheel_diameter_mm", d, usual::kWheelDiameterMm);
  warn_usual(*g, "wheel_min_diameter_mm", dmin, usual::kWheelDiameterMm);
  warn_usual(*g, "wheel_width_mm", e, usual::kWheelWidthMm);
  warn_usual(*g, "feed_mm_per_s", feed, usual::kGrindingFeedMmPerS);
  warn_usual(*g, "force_ratio", mu, usual::kGrindingForceRatio);
  warn_usual(*g, "density_kg_per_m3", rho, {500.0, 25000.0, "the 500 to 25 000 kg/m^3 of solids (steel 7850)", 1e3, "g/cm^3"});

  // Seed 001's mechanistic model: both coefficients and the impacts, or none.
  const bool has_ke = g->has("edge_coefficient_n_per_mm"), has_kc = g->has("cutting_coefficient_n_per_mm2");
  const bool has_nc = g->has("impacts_per_turn") || g->has("impacts");
  const bool mechanistic = has_ke || has_kc || has_nc;
  if (mechanistic) {
    if (!has_ke) doc.error_key(g->path_of("edge_coefficient_n_per_mm"), "missing (the mechanistic model needs it, N/mm, >= 0)");
    if (!has_kc) doc.error_key(g->path_of("cutting_coefficient_n_per_mm2"), "missing (the mechanistic model needs it, N/mm^2, > 0)");
    if (!has_nc)
      doc.error_key(g->path_of("impacts_per_turn"),
                    "missing (the mechanistic model needs impacts_per_turn = n, or the table [[grinding.impacts]])");
  }
  const auto ke = bounded(*g, "edge_coefficient_n_per_mm", g->number("edge_coefficient_n_per_mm", kNonNegative), kEdgeBound);
  const auto kc = bounded(*g, "cutting_coefficient_n_per_mm2", g->number("cutting_coefficient_n_per_mm2", kPositive), kCuttingBound);
  const auto read_nc = attempt([&] { return read_impacts(*g); });
  const std::optional<grinding::ImpactsPerTurn> nc = read_nc ? *read_nc : std::nullopt;
  warn_usual(*g, "edge_coefficient_n_per_mm", ke, {1.0, 2000.0, "the 1 to 2000 N/mm of grinding edge coefficients (seed 001: 75, 177)", 1e-3, "N/m"});
  warn_usual(*g, "cutting_coefficient_n_per_mm2", kc, {500.0, 1e5, "the 500 to 100 000 N/mm^2 of grinding (seed 001: 6787, 10 020)", 1e-6, "N/m^2"});
  const auto partition = attempt([&] { return read_partition(*g, mechanistic); });
  const auto no_load = attempt([&] { return read_no_load(*g); });
  const auto models = attempt([&] { return read_models(*g); });
  const auto motor = attempt([&] { return read_motor(*g); });
  if (!mechanistic && (!models || !models->removal))
    doc.error_key("grinding", "no removal model: give the mechanistic model (edge_coefficient_n_per_mm, "
                              "cutting_coefficient_n_per_mm2, impacts_per_turn) or [grinding.models.removal]");
  stop_if_errors_since(doc, mark);
  if (!d || !e || !rpm || !feed || !mu || (mechanistic && (!ke || !kc || !nc))) throw Skip{};

  p.wheel.diameter_m = *d * 1e-3;
  p.wheel.width_m = *e * 1e-3;
  p.wheel.speed_rev_per_s = revolutions_per_s(*rpm);
  p.feed_m_per_s = *feed * 1e-3;
  p.force_ratio = *mu;
  if (rho) p.density_kg_per_m3 = *rho;
  if (dmin) p.min_wheel_diameter_m = *dmin * 1e-3;
  if (mechanistic) p.mechanistic = grinding::MechanisticModel{*ke * 1e3, *kc * 1e6, *nc};
  if (partition) p.partition = *partition;
  if (no_load) p.no_load_loss = *no_load;
  if (p.no_load_loss) {
    // c0 carries no unit a band can hold; the loss it gives on this wheel can.
    const double loss = p.no_load_loss->loss_w(p.wheel);
    const auto t = g->table("no_load_loss");
    if (p.no_load_loss->c0 > 0.0 && !(loss >= 1.0 && loss <= 2e4))
      t->doc().warn(t->path_of("c0"), *t->find("c0"),
                    "gives a no-load loss of " + number_text(loss) + " W at " + number_text(*rpm) + " rev/min and " +
                        number_text(*d) + " mm, outside the 1 W to 20 kW of grinder drag; check c0's units "
                        "(W / ((rad/s)^speed_exponent mm^diameter_exponent))");
  }
  if (models) p.empirical = *models;
  if (motor) p.motor = *motor;
  if (const std::string why = p.validate(); !why.empty()) doc.fail_key("grinding", why);  // a rule above is missing
  return p;
}

}  // namespace chatter::config_detail
