// `chatter coefficients` on turning tests: Kienzle's law per direction, its
// record, report and [process] keys (include/chatter/records/shop.hpp;
// docs/shop_data.md "Kienzle's law"). The fit is fit_kienzle (src/shop/kienzle_fit.cpp).
#include <cmath>
#include <cstdio>
#include <numbers>
#include <sstream>

#include <nlohmann/json.hpp>

#include "chatter/error.hpp"
#include "chatter/number_text.hpp"
#include "chatter/io/table_writer.hpp"
#include "chatter/records/shop.hpp"

namespace chatter {
namespace {

using nlohmann::json;

// The directions the tests measured, in the law's order.
std::vector<std::pair<const char*, const KienzleDirectionFit*>> measured(const KienzleFit& f) {
  std::vector<std::pair<const char*, const KienzleDirectionFit*>> out{{"tangential", &f.tangential}, {"feed", &f.feed}};
  if (f.radial.term.specific_force_n_per_m2 > 0.0) out.emplace_back("radial", &f.radial);
  return out;
}

}  // namespace

KienzleResult fit_kienzle_tests(const std::filesystem::path& tests, double lead_angle_deg, ArgStyle style) {
  if (!(std::isfinite(lead_angle_deg) && lead_angle_deg > 0.0 && lead_angle_deg <= 90.0))
    throw InputError(arg_name(style, "lead_angle_deg") + " = " + number_text(lead_angle_deg, 4) +
                     ": must be in (0, 90] deg (90 = the edge perpendicular to the feed)");
  KienzleResult r;
  r.tests_path = tests;
  r.tests = read_turning_tests(tests);
  try {
    r.fit = fit_kienzle(r.tests.tests, lead_angle_deg * std::numbers::pi / 180.0);
  } catch (const InputError& e) {
    throw InputError(tests.string() + ": " + e.what());
  }
  return r;
}

json kienzle_record(const KienzleResult& r) {
  const KienzleFit& f = r.fit;
  json j;
  j["tests"] = r.tests_path.string();
  j["force_law"] = "kienzle";
  j["lead_angle_deg"] = f.lead_angle_rad * 180.0 / std::numbers::pi;
  j["degrees_of_freedom"] = f.degrees_of_freedom;
  for (const auto& [name, d] : measured(f)) {
    j["specific_force_n_per_mm2"][name] = d->term.specific_force_n_per_m2 * 1e-6;
    j["exponent"][name] = d->term.exponent;
    j["standard_error"][name] = {{"specific_force_n_per_mm2", finite_or_null(d->k_standard_error_n_per_m2 * 1e-6)},
                                 {"exponent", finite_or_null(d->m_standard_error)}};
    j["confidence_95"][name] = {{"specific_force_n_per_mm2", finite_or_null(d->k_confidence_95_n_per_m2 * 1e-6)},
                                {"exponent", finite_or_null(d->m_confidence_95)}};
    j["r_squared"][name] = finite_or_null(d->r_squared);
  }
  j["rows"] = json::array();
  for (std::size_t i = 0; i < r.tests.tests.size(); ++i) {
    const TurningForceTest& t = r.tests.tests[i];
    json row = {{"line", r.tests.line[i]},
                {"feed_mm_per_rev", t.feed_per_rev_m * 1e3},
                {"depth_mm", t.depth_m * 1e3},
                {"specific_cutting_force_n_per_mm2", t.tangential_n / (t.feed_per_rev_m * t.depth_m * 1e6)}};
    for (const auto& [name, d] : measured(f)) row[std::string("residual_") + name + "_n"] = d->residual_n[i];
    j["rows"].push_back(row);
  }
  j["warnings"] = f.warnings;
  return j;
}

std::string kienzle_report(const KienzleResult& r) {
  const KienzleFit& f = r.fit;
  std::ostringstream os;
  os << "Kienzle's law F = k_1.1 b h^(1-m) from " << r.tests.tests.size() << " turning tests ("
     << r.tests_path.filename().string() << ", lead angle " << number_text(f.lead_angle_rad * 180.0 / std::numbers::pi, 4)
     << " deg; h = f sin(lead), b = a / sin(lead)):\n";
  const bool errors = f.degrees_of_freedom > 0;
  os << "  direction    k_1.1 (N/mm^2)      m           R^2" << (errors ? "     (+- standard error; 95 %: x "
                                                                              "Student t)"
                                                                            : "") << "\n";
  for (const auto& [name, d] : measured(f)) {
    os << "  " << name << std::string(12 - std::string(name).size(), ' ') << number_text(d->term.specific_force_n_per_m2 * 1e-6, 5);
    if (errors) os << " +- " << number_text(d->k_standard_error_n_per_m2 * 1e-6, 3);
    os << "   " << number_text(d->term.exponent, 4);
    if (errors) os << " +- " << number_text(d->m_standard_error, 2);
    os << "   " << (std::isfinite(d->r_squared) ? number_text(d->r_squared, 4) : std::string("-")) << "\n";
  }
  os << "  line  feed mm/rev  depth mm  k_c N/mm^2  residual F_c N  residual F_f N\n";
  for (std::size_t i = 0; i < r.tests.tests.size(); ++i) {
    const TurningForceTest& t = r.tests.tests[i];
    char b[160];
    std::snprintf(b, sizeof b, "  %4d  %11.4g  %8.4g  %10.5g  %14.3g  %14.3g\n", r.tests.line[i], t.feed_per_rev_m * 1e3,
                  t.depth_m * 1e3, t.tangential_n / (t.feed_per_rev_m * t.depth_m * 1e6), f.tangential.residual_n[i],
                  f.feed.residual_n[i]);
    os << b;
  }
  return os.str();
}

std::string kienzle_fragment(const KienzleResult& r, ArgStyle style) {
  const KienzleFit& f = r.fit;
  for (const auto& [name, d] : measured(f))
    if (!(d->term.exponent >= 0.0 && d->term.exponent < 1.0))
      throw InputError(arg_name(style, "out") + ": the fitted " + name + " exponent m = " + number_text(d->term.exponent, 4) +
                       " is not a valid law (0 <= m < 1): check the tests");
  auto inline_table = [&](auto value) {
    std::string s = "{ ";
    bool first = true;
    for (const auto& [name, d] : measured(f)) {
      s += std::string(first ? "" : ", ") + name + " = " + table_number(value(*d));
      first = false;
    }
    return s + " }";
  };
  std::ostringstream t;
  t << "# Kienzle's law fitted by `chatter coefficients` from " << r.tests_path.string() << ": "
    << r.tests.tests.size() << " tests";
  if (f.degrees_of_freedom > 0) {
    t << "; standard errors:";
    for (const auto& [name, d] : measured(f))
      t << " " << name << " k_1.1 +- " << number_text(d->k_standard_error_n_per_m2 * 1e-6, 3) << ", m +- "
        << number_text(d->m_standard_error, 2) << ";";
  }
  t << "\n# Add feed_per_rev_mm (the chip the regenerative side is linearised at) and the modes.\n"
    << "[process]\noperation = \"turning\"\nforce_law = \"kienzle\"\n"
    << "specific_force_n_per_mm2 = "
    << inline_table([](const KienzleDirectionFit& d) { return d.term.specific_force_n_per_m2 * 1e-6; }) << "\n"
    << "exponent = " << inline_table([](const KienzleDirectionFit& d) { return d.term.exponent; }) << "\n";
  const double lead = f.lead_angle_rad * 180.0 / std::numbers::pi;
  if (std::abs(lead - 90.0) > 1e-9) t << "lead_angle_deg = " << table_number(lead) << "\n";
  return t.str();
}

}  // namespace chatter
