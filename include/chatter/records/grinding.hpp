// The JSON records of the grinding commands (docs/grinding.md lists the
// keys): the one place they are built, for `chatter grind` (dumped), Python
// (converted by the one converter) and the C API (dumped into the caller's
// buffer). Shop units at this edge: mm, mm^3/s, N, W, J/mm^3, s, m/s,
// rev/min; null where a quantity is not known, never NaN.
#pragma once

#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "chatter/grinding.hpp"
#include "chatter/grinding_data.hpp"
#include "chatter/grinding_dynamics.hpp"
#include "chatter/io/grinding_config.hpp"
#include "chatter/io/grinding_io.hpp"
#include "chatter/records/columns.hpp"

namespace chatter {

/// `grind predict`: the prediction (mechanistic or empirical, at a power or
/// inverted from a target), the config's wheel and name, and its warnings
/// with the prediction's (format "chatter-grinding-prediction").
nlohmann::json grinding_prediction_record(const grinding::Prediction& p, const GrindingConfig& config);
/// `grind fit`: model, coefficients (names and values in the config's
/// units), standard errors, 95 % intervals, R^2, RMSE, MAE, MAPE, per-test
/// residuals and derived columns, warnings ("chatter-grinding-fit"), and
/// `fragment`: the [grinding] table the fit makes (grinding_fit_fragment),
/// null when it makes none or was not asked.
nlohmann::json grinding_fit_record(const GrindingFitReport& r, const std::optional<std::string>& fragment);
/// `grind impacts`: impacts per turn, histogram, peaks ("chatter-grinding-impacts").
nlohmann::json grinding_impacts_record(const grinding::ImpactCount& c, const ImpactRecord& record,
                                       const std::string& file, double wheel_rpm);
/// `grind simulate`: the dynamics run and its quasi-static prediction ("chatter-grinding-simulation").
nlohmann::json grinding_simulation_record(const grinding::DynamicsResult& r, const GrindingConfig& config);
/// `grind plan`: wheels, times and the mean G-ratio of a repair ("chatter-grinding-plan").
nlohmann::json grinding_plan_record(const grinding::Plan& p, const grinding::PlanOptions& o,
                                    const GrindingConfig& config);
/// `grind plan --objective`'s record: both strategies (seed 000 §6.6), each
/// with the keys of a plan record, and what the G-ratio one saves.
nlohmann::json grinding_plan_comparison_record(const grinding::PlanComparison& c, const grinding::PlanOptions& o,
                                               const GrindingConfig& config);

/// One `grind plan` as every front end runs it: at a fixed speed, or with an
/// objective both strategies compared (the chosen one is `plan`); its record
/// and the chosen plan's wheel life as CSV (grinding_plan_csv).
struct GrindingPlanRun {
  grinding::Plan plan;
  std::optional<grinding::PlanComparison> both;
  nlohmann::json record;
  std::string csv;
};
/// @throws InputError as plan_repair / compare_plan_objectives.
GrindingPlanRun run_grinding_plan(const GrindingConfig& config, const grinding::PlanOptions& o);

/// The grinding results with their tables as columns (Python: chatter.grind_sweep,
/// grind_plan, grind_impacts, grind_simulate), each table the CSV the CLI
/// writes (grinding_io.hpp): the sweep table alone; the plan's record with
/// "wheel_life"; the impacts record with "turns_table"; the simulation's
/// record with "series".
ColumnRecord grinding_sweep_columns(const std::vector<grinding::SweepCurve>& curves);
ColumnRecord grinding_plan_columns(const GrindingPlanRun& run);
ColumnRecord grinding_impacts_columns(const grinding::ImpactCount& c, const ImpactRecord& record,
                                      const std::string& file, double wheel_rpm);
ColumnRecord grinding_simulation_columns(const grinding::DynamicsResult& r, const GrindingConfig& config);

}  // namespace chatter
