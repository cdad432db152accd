// `chatter grind plan`: wheels, grinding time and wheel changes for a repair
// (seed 000 §6.6; docs/grinding.md "grind plan"), at a fixed wheel speed or,
// with --objective, at the speed of the largest removal or G-ratio at every
// diameter, the two strategies compared. The plans are library functions
// (chatter/grinding.hpp: plan_repair, compare_plan_objectives).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "chatter/error.hpp"
#include "chatter/grinding.hpp"
#include "chatter/io/grinding_io.hpp"
#include "chatter/io/table_writer.hpp"
#include "chatter/records/grinding.hpp"
#include "cmd_grind.hpp"

namespace chatter::cli {

namespace {

const char* const kPlanUsage = R"(Usage: chatter grind plan CONFIG (--volume-mm3 V | --area-mm2 A --depth-mm D) (--power-w P | --current-a I) [options]

Wheels, grinding time and wheel changes for a repair (seed 000 §6.6): each
wheel is used from the config's wheel_diameter_mm down to
wheel_min_diameter_mm; the removal and wear rates follow its diameter (the
wear from [grinding.models.wear], or --g-ratio). --current-a instead of
--power-w: the operator's motor current, the useful power then following the
speed and diameter through [grinding.motor] and the no-load loss.

At a fixed wheel speed (the config's) the cutting speed falls as the wheel
wears. --objective removal|g-ratio chooses the wheel speed anew at every
diameter, among --speed-points speeds from --wheel-rpm-min to --wheel-rpm-max
inside the models' tested cutting speed and power: the largest removal rate,
or the largest G-ratio (the wheel lasts longest). Both strategies are then
planned and compared, as seed 000 does (its example: three wheels fewer and
four hours gained by the G-ratio, with 3 h per wheel change under water);
--table writes the chosen objective's wheel life.

Example:
  chatter grind plan configs/grinding_underwater_seed000.toml --area-mm2 1.5e6 --depth-mm 2 \
      --current-a 19 --wheel-change-min 180 --objective g-ratio --wheel-rpm-min 2025 --wheel-rpm-max 3375
)";

void print_plan(std::ostream& os, const grinding::Plan& plan, const grinding::PlanOptions& o, const char* indent) {
  const auto f = grind_number;
  os << indent << "one wheel           removes " << f(plan.removal_per_wheel_m3 * 1e9) << " mm^3 in "
     << f(plan.wheel_life_s / 60) << " min (mean G-ratio " << f(plan.mean_g_ratio) << ", usable volume "
     << f(plan.usable_wheel_volume_m3 * 1e9) << " mm^3)\n"
     << indent << "wheels              " << f(plan.wheels) << " -> " << plan.wheels_needed << " wheels, "
     << plan.wheel_changes << " changes\n"
     << indent << "time                grinding " << f(plan.grinding_time_s / 3600) << " h + changes "
     << f(plan.wheel_changes * o.wheel_change_s / 3600) << " h = " << f(plan.total_time_s / 3600) << " h\n";
  if (plan.objective == grinding::PlanObjective::kFixedSpeed || plan.life.empty()) return;
  const grinding::PlanStep &a = plan.life.front(), &b = plan.life.back();
  os << indent << "wheel speed         " << f(a.wheel_rpm) << " rev/min at " << f(a.diameter_m * 1e3) << " mm ("
     << f(a.cutting_speed_m_per_s) << " m/s, " << f(a.power_w) << " W) to " << f(b.wheel_rpm) << " rev/min at "
     << f(b.diameter_m * 1e3) << " mm (" << f(b.cutting_speed_m_per_s) << " m/s, " << f(b.power_w) << " W)\n";
}

}  // namespace

int cmd_grind_plan(const std::vector<std::string>& args) {
  std::string config, json_path, table_path, objective;
  grinding::PlanOptions o;
  double change_min = 0.0;
  po::options_description d("Options");
  d.add_options()("volume-mm3", po::value<double>(), "material to remove, mm^3")
      ("area-mm2", po::value<double>(), "area to grind, mm^2 (with --depth-mm)")
      ("depth-mm", po::value<double>(), "depth to remove over the area, mm")
      ("power-w", po::value<double>(), "useful grinding power, W")
      ("current-a", po::value<double>(), "the motor current instead of the power, A ([grinding.motor])")
      ("g-ratio", po::value<double>(&o.g_ratio), "removal / wear, constant (default: the wear model)")
      ("wheel-change-min", po::value<double>(&change_min)->default_value(0.0), "time to change a wheel, min")
      ("objective", po::value<std::string>(&objective),
       "removal or g-ratio: the wheel speed of the largest removal rate or G-ratio at every diameter (both "
       "strategies are planned and compared)")
      ("wheel-rpm-min", po::value<double>(&o.wheel_rpm_min), "lowest wheel speed searched, rev/min (--objective)")
      ("wheel-rpm-max", po::value<double>(&o.wheel_rpm_max), "highest wheel speed searched, rev/min (--objective)")
      ("speed-points", po::value<int>(&o.speed_points)->default_value(200), "wheel speeds searched per diameter")
      ("json", po::value<std::string>(&json_path), "write the JSON record here ('-': standard output)")
      ("table", po::value<std::string>(&table_path), "write one wheel's life as CSV (diameter, speed, rates, removed, time)");
  po::variables_map vm;
  if (!parse_grind(args, kPlanUsage, d, "config", vm, config)) return 0;
  const bool by_volume = vm.count("volume-mm3") > 0, by_area = vm.count("area-mm2") || vm.count("depth-mm");
  if (by_volume == by_area)
    throw InputError("give --volume-mm3, or --area-mm2 with --depth-mm (one way, not both)");
  if (vm.count("power-w") + vm.count("current-a") != 1)
    throw InputError("give --power-w or --current-a (one of them)");
  for (const auto& [flag, unit] : std::vector<std::pair<const char*, const char*>>{
           {"volume-mm3", "mm^3"}, {"area-mm2", "mm^2"}, {"depth-mm", "mm"}, {"g-ratio", ""}, {"power-w", "W"},
           {"current-a", "A"}, {"wheel-rpm-min", "rev/min"}, {"wheel-rpm-max", "rev/min"}})
    require_positive(vm, flag, unit);
  if (by_area && !(vm.count("area-mm2") && vm.count("depth-mm")))
    throw InputError("--area-mm2 and --depth-mm go together (the volume is their product)");
  const bool searched = vm.count("objective") > 0;
  if (searched) {
    o.objective = grinding::plan_objective_from_name(objective, "--objective");
    if (!vm.count("wheel-rpm-min") || !vm.count("wheel-rpm-max"))
      throw InputError("--objective searches the wheel speed: give --wheel-rpm-min and --wheel-rpm-max");
  } else if (vm.count("wheel-rpm-min") || vm.count("wheel-rpm-max")) {
    throw InputError("--wheel-rpm-min/--wheel-rpm-max go with --objective (without it the config's wheel speed is used)");
  }
  o.volume_m3 = by_volume ? vm["volume-mm3"].as<double>() * 1e-9
                          : vm["area-mm2"].as<double>() * vm["depth-mm"].as<double>() * 1e-9;
  if (vm.count("power-w")) o.power_w = vm["power-w"].as<double>();
  else o.current_a = vm["current-a"].as<double>();
  o.wheel_change_s = change_min * 60.0;
  check_outputs({{"--json", json_path == "-" ? "" : json_path}, {"--table", table_path}});
  const GrindingConfig c = load_grinding_checked(config, vm.count("strict") > 0);

  const GrindingPlanRun run = with_flag("plan", [&] { return run_grinding_plan(c, o); });
  const grinding::Plan& plan = run.plan;
  const std::optional<grinding::PlanComparison>& both = run.both;
  const std::string json = run.record.dump(2) + "\n";
  std::vector<std::pair<std::filesystem::path, std::string>> files;
  if (!json_path.empty() && json_path != "-") files.emplace_back(json_path, json);
  if (!table_path.empty()) files.emplace_back(table_path, run.csv);
  write_text_files(files);

  std::ostream& os = json_path == "-" ? std::cerr : std::cout;
  const auto f = grind_number;
  os << config << ": " << f(o.volume_m3 * 1e9) << " mm^3 at "
     << (o.current_a ? f(*o.current_a) + " A of motor current" : f(o.power_w) + " W") << "\n";
  if (!both) {
    print_plan(os, plan, o, "  ");
  } else {
    os << "  the largest removal at every diameter:\n";
    print_plan(os, both->removal, o, "    ");
    os << "  the largest G-ratio at every diameter:\n";
    print_plan(os, both->g_ratio, o, "    ");
    os << "  the G-ratio strategy uses " << both->wheels_saved << " wheel" << (both->wheels_saved == 1 ? "" : "s")
       << " fewer and " << (both->time_saved_s >= 0 ? "saves " : "takes ") << f(std::abs(both->time_saved_s) / 3600)
       << " h" << (both->time_saved_s >= 0 ? "" : " more") << " (seed 000 §6.6: 3 wheels fewer, 4 h gained on its "
       << "models)\n";
  }
  std::vector<std::string> warnings = plan.warnings;
  if (both)
    for (const std::string& w : (o.objective == grinding::PlanObjective::kRemoval ? both->g_ratio : both->removal).warnings)
      if (std::find(warnings.begin(), warnings.end(), w) == warnings.end()) warnings.push_back(w);
  for (const std::string& w : warnings) std::cerr << "warning: " << w << "\n";
  if (json_path == "-") std::cout << json;
  if (!table_path.empty()) os << "wrote table: " << table_path << "\n";
  return 0;
}

}  // namespace chatter::cli
