// The records of the forced response (include/chatter/records/forced.hpp).
#include "chatter/records/forced.hpp"

#include <cmath>
#include <limits>
#include <sstream>

#include <nlohmann/json.hpp>

#include "chatter/io/table_writer.hpp"

namespace chatter {
namespace {

using nlohmann::json;

json number_or_null(double x) { return std::isfinite(x) ? json(x) : json(nullptr); }
json um(double m) { return number_or_null(m * 1e6); }
json xy_um(double x_m, double y_m) { return {{"x", um(x_m)}, {"y", um(y_m)}}; }

// A table cell: the number, or empty when not finite.
std::string cell(double x) { return std::isfinite(x) ? table_number(x) : std::string(); }

}  // namespace

json forced_record(const ForcedResponse& r, const ForcedRecordContext& c) {
  json j;
  j["config"] = c.config;
  j["warnings"] = c.warnings;
  if (c.position_mm) j["position_mm"] = *c.position_mm;
  j["operation"] = r.milling ? "milling" : "turning";
  j["spindle_rpm"] = r.spindle_rpm;
  j["depth_mm"] = r.depth_m * 1e3;
  j[r.milling ? "feed_per_tooth_mm" : "feed_mm_per_rev"] = r.feed_m * 1e3;
  if (c.radial_immersion) j["radial_immersion"] = *c.radial_immersion;
  j["stable"] = r.stable;
  j["spectral_radius"] = number_or_null(r.spectral_radius);
  if (c.limit) j["depth_limit_mm"] = c.limit->bounded() ? json(c.limit->depth_limit_m * 1e3) : json(nullptr);
  j["method"] = r.method;
  const bool have = r.stable;
  auto value = [&](double x) { return have ? number_or_null(x) : json(nullptr); };
  auto micro = [&](double x) { return have ? um(x) : json(nullptr); };
  j["period_s"] = value(r.period_s);
  j["harmonics"] = r.harmonics;
  j["surface_location_error_um"] = micro(r.surface_location_error_m);
  j["surface_location_error_range_um"] = {{"min", micro(r.sle_min_m)}, {"max", micro(r.sle_max_m)}};
  j["peak_to_peak_um"] = have ? xy_um(r.peak_to_peak_x_m, r.peak_to_peak_y_m) : json(nullptr);
  j["static_deflection_um"] = have ? xy_um(r.static_x_m, r.static_y_m) : json(nullptr);
  j["mean_force_n"] = have ? json{{"x", r.mean_force_x_n}, {"y", r.mean_force_y_n}} : json(nullptr);
  j["min_chip_thickness_um"] = micro(r.min_chip_m);
  j["negative_chip_arc_deg"] = value(r.negative_chip_arc_deg);
  j["negative_chip_fraction"] = value(r.negative_chip_fraction);
  j["teeth_leave_cut"] = have ? json(r.teeth_leave_cut) : json(nullptr);
  j["linear_limit_holds"] = r.linear_limit_holds;
  if (!r.milling) j["diametral_error_um"] = micro(r.diametral_error_m);
  if (r.milling) {
    json z = json::array(), sle = json::array();
    for (std::size_t i = 0; i < r.wall_z_m.size() && have; ++i) {
      z.push_back(r.wall_z_m[i] * 1e3);
      sle.push_back(r.wall_sle_m[i] * 1e6);
    }
    j["wall_profile"] = {{"z_mm", z}, {"sle_um", sle}};
  }
  return j;
}

json forced_check_record(const ForcedResponse& r, std::optional<double> max_error_m,
                         std::optional<bool> within_tolerance) {
  const bool s = r.stable;
  json j;
  j["stable"] = s;
  j[r.milling ? "surface_location_error_um" : "diametral_error_um"] =
      s ? um(r.milling ? r.surface_location_error_m : r.diametral_error_m) : json(nullptr);
  j["peak_to_peak_um"] = s ? xy_um(r.peak_to_peak_x_m, r.peak_to_peak_y_m) : json(nullptr);
  j["min_chip_thickness_um"] = s ? um(r.min_chip_m) : json(nullptr);
  j["teeth_leave_cut"] = s ? json(r.teeth_leave_cut) : json(nullptr);
  j["linear_limit_holds"] = r.linear_limit_holds;
  j["max_error_um"] = max_error_m ? json(*max_error_m * 1e6) : json(nullptr);
  j["within_tolerance"] = within_tolerance ? json(*within_tolerance) : json(nullptr);
  return j;
}

ColumnRecord forced_columns(const ForcedResponse& r, const ForcedRecordContext& context, bool with_path) {
  ColumnRecord out;
  out.fields = forced_record(r, context);
  if (!(with_path && r.stable && r.milling)) return out;
  out.groups.push_back({"/path",
                        {{"time_s", r.t_s},
                         {"rel_x_um", scaled(r.rel_x_m, 1e6)},
                         {"rel_y_um", scaled(r.rel_y_m, 1e6)},
                         {"wall_normal_um", scaled(r.wall_normal_m, 1e6)}}});
  return out;
}

ColumnRecord sle_columns(const std::vector<ForcedResponse>& rows, const SleContext& context) {
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  ColumnRecord out;
  out.fields = {{"config", context.config}, {"depth_mm", context.depth_mm}, {context.feed_key, context.feed_mm}};
  if (context.position_mm) out.fields["position_mm"] = *context.position_mm;
  std::vector<double> rpm, sle, ppx, ppy, chip;
  std::vector<bool> stable, leave;
  for (const ForcedResponse& r : rows) {
    rpm.push_back(r.spindle_rpm);
    sle.push_back(r.stable ? r.surface_location_error_m * 1e6 : kNaN);
    ppx.push_back(r.stable ? r.peak_to_peak_x_m * 1e6 : kNaN);
    ppy.push_back(r.stable ? r.peak_to_peak_y_m * 1e6 : kNaN);
    chip.push_back(r.stable ? r.min_chip_m * 1e6 : kNaN);
    stable.push_back(r.stable);
    leave.push_back(r.stable && r.teeth_leave_cut);
  }
  out.columns = {{"spindle_rpm", std::move(rpm)},       {"surface_location_error_um", std::move(sle)},
                 {"peak_to_peak_x_um", std::move(ppx)}, {"peak_to_peak_y_um", std::move(ppy)},
                 {"min_chip_thickness_um", std::move(chip)}, {"stable", std::move(stable)},
                 {"teeth_leave_cut", std::move(leave)}};
  return out;
}

std::string forced_path_csv(const ForcedResponse& r) {
  std::ostringstream os;
  os << "time_s,rel_x_um,rel_y_um,wall_normal_um\n";
  for (std::size_t i = 0; i < r.t_s.size(); ++i)
    os << table_number(r.t_s[i]) << ',' << table_number(r.rel_x_m[i] * 1e6) << ','
       << table_number(r.rel_y_m[i] * 1e6) << ',' << table_number(r.wall_normal_m[i] * 1e6) << '\n';
  return os.str();
}

std::string sle_table_csv(const std::vector<ForcedResponse>& rows) {
  std::ostringstream os;
  os << "spindle_rpm,surface_location_error_um,peak_to_peak_x_um,peak_to_peak_y_um,min_chip_thickness_um,stable\n";
  for (const ForcedResponse& r : rows) {
    os << table_number(r.spindle_rpm) << ',';
    if (r.stable)
      os << cell(r.surface_location_error_m * 1e6) << ',' << cell(r.peak_to_peak_x_m * 1e6) << ','
         << cell(r.peak_to_peak_y_m * 1e6) << ',' << cell(r.min_chip_m * 1e6) << ",1\n";
    else
      os << ",,,,0\n";
  }
  return os.str();
}

std::string shaft_table_csv(const std::vector<double>& positions_mm, const std::vector<ShaftDeflection>& rows) {
  std::ostringstream os;
  os << "position_mm,force_n,deflection_x_um,deflection_y_um,diametral_error_um\n";
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const ShaftDeflection& r = rows[i];
    os << table_number(i < positions_mm.size() ? positions_mm[i] : r.position_m * 1e3) << ',' << table_number(r.deflection.force_n) << ','
       << table_number(r.deflection.deflection_x_m * 1e6) << ',' << table_number(r.deflection.deflection_y_m * 1e6)
       << ',' << table_number(r.deflection.diametral_error_m * 1e6) << '\n';
  }
  return os.str();
}

}  // namespace chatter
