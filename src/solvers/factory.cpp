// The solver registry (see solvers.hpp): one descriptor per method, and the
// diagnostics hooks of the solvers that report more than the limit.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

#include "chatter/error.hpp"
#include "chatter/semi_discretization.hpp"
#include "chatter/solvers.hpp"
#include "chatter/time_domain.hpp"
#include "chatter/transfer_function.hpp"

namespace chatter {

namespace {

using Kind = SolverOption::Kind;

// A number in a message, as the CLI prints it (6 significant digits).
std::string message_number(double x) {
  std::ostringstream os;
  os.precision(6);
  os << x;
  return os.str();
}

template <class T>
T option_or(const SolverValues& o, const std::string& name, T fallback) {
  const auto it = o.find(name);
  return it == o.end() ? fallback : std::get<T>(it->second);
}

// ------------------------------------------------- transfer-function methods

const SolverOption kMaxPhaseStep{"max_phase_step_rad", Kind::kReal,
                                 "largest phase step of the frequency search (library only)", 0.0,
                                 std::numeric_limits<double>::infinity(), "rad", false};

TransferFunctionOptions tf_options(double depth_max_m, const SolverValues& o) {
  TransferFunctionOptions t;
  t.depth_max_m = depth_max_m;
  t.max_phase_step_rad = option_or(o, kMaxPhaseStep.name, t.max_phase_step_rad);
  return t;
}

SolverValues tf_effective_options(const LobeSolver& solver) {
  const auto& s = static_cast<const TransferFunctionSolver&>(solver);
  const SearchBand band = s.band();
  return {{"depth_max_m", s.options().depth_max_m},
          {"max_phase_step_rad", s.options().max_phase_step_rad},
          {"search_band_hz",
           std::vector<double>{band.omega_min_rad_s / (2 * std::numbers::pi),
                               band.omega_max_rad_s / (2 * std::numbers::pi)}},
          {"frequency_grid_points", static_cast<int>(band.grid_points)},
          {"frequency_resolution_hz", s.model().frequency_resolution_hz()}};
}

SolverDescriptor analytic_descriptor() {
  SolverDescriptor d;
  d.name = "analytic";
  d.summary = "transfer function, eigenvalues of H0*G";
  d.kind = SolverKind::kAveraged;
  // Real cutters: the helix is accepted and ignored (note from
  // ignored_feature_notes); variable pitch, variable helix and process
  // damping go to the general per-speed search.
  d.accepts = {SolverFeature::kModalModel, SolverFeature::kMeasuredFrf, SolverFeature::kMilling,
               SolverFeature::kTurning, SolverFeature::kHelix, SolverFeature::kVariablePitch,
               SolverFeature::kVariableHelix, SolverFeature::kProcessDamping, SolverFeature::kCutterProfile};
  d.in_default_compare = true;
  d.options = {kMaxPhaseStep};
  d.make = [](const StructuralModel& m, const Process& p, double depth_max_m, const SolverValues& o) {
    return std::unique_ptr<LobeSolver>(std::make_unique<AnalyticSolver>(m, p, tf_options(depth_max_m, o)));
  };
  d.effective_options = tf_effective_options;
  d.plot = {"#8fbce6", 7.0, "", 0};
  return d;
}

SolverDescriptor coupled_descriptor() {
  SolverDescriptor d;
  d.name = "coupled";
  d.summary = "tool-workpiece characteristic determinant; must agree with analytic";
  d.kind = SolverKind::kAveraged;
  // The helix leaves the averaged equation unchanged (note from
  // ignored_feature_notes); variable pitch and process damping are analytic's.
  d.accepts = {SolverFeature::kModalModel, SolverFeature::kMilling, SolverFeature::kTurning,
               SolverFeature::kHelix, SolverFeature::kCutterProfile};
  d.in_default_compare = true;
  d.options = {kMaxPhaseStep};
  d.make = [](const StructuralModel& m, const Process& p, double depth_max_m, const SolverValues& o) {
    return std::unique_ptr<LobeSolver>(std::make_unique<CoupledSolver>(m, p, tf_options(depth_max_m, o)));
  };
  d.effective_options = tf_effective_options;
  d.plot = {"#0b3a6e", 1.6, " dt (6,4)", 0};
  return d;
}

// --------------------------------------------------------------------- sdm

SolverDescriptor sdm_descriptor() {
  SolverDescriptor d;
  d.name = "sdm";
  d.summary = "semi-discretisation / Floquet: sees the flip lobes of low-immersion milling; slower";
  d.kind = SolverKind::kFloquet;
  // Speed variation: the time-varying delay over the principal period
  // (docs/ssv.md); not with process damping (refused by the solver).
  d.accepts = {SolverFeature::kModalModel,    SolverFeature::kMilling,       SolverFeature::kTurning,
               SolverFeature::kHelix,         SolverFeature::kProcessDamping, SolverFeature::kVariablePitch,
               SolverFeature::kVariableHelix, SolverFeature::kSpeedVariation, SolverFeature::kCutterProfile};
  d.in_default_compare = true;
  d.options = {{"steps", Kind::kInt,
                "steps per delay period (default 64 first order, 8 with --collocation, 4 with the "
                "automatic collocation of real cutters and turning; the step is also at most that fraction "
                "of the shortest natural period); more steps: more accurate, slower",
                1.0, std::numeric_limits<double>::infinity(), "", true},
               {"collocation", Kind::kInt,
                "Gauss collocation nodes per step, 0-3 (default: 3 for a helix, variable pitch or a profile, "
                "and for turning with a sharp edge; else 0: first order). 3 with its default 8 steps: limits "
                "within ~0.02 % where first order is within ~1 %, and faster; not for turning with process "
                "damping or a nose radius",
                0.0, static_cast<double>(kMaxCollocationNodes), "", true}};
  d.make = [](const StructuralModel& m, const Process& p, double depth_max_m, const SolverValues& o) {
    SemiDiscretizationOptions s;
    s.depth_max_m = depth_max_m;
    if (o.count("collocation")) {
      s.collocation_nodes = std::get<int>(o.at("collocation"));
      if (s.collocation_nodes > 0) s.steps_per_period = s.steps_per_vibration_cycle = kCollocationSteps;
    }
    if (o.count("steps")) {
      s.steps_per_period = std::get<int>(o.at("steps"));
      s.steps_per_vibration_cycle = s.steps_per_period;
    }
    return std::unique_ptr<LobeSolver>(std::make_unique<SemiDiscretizationSolver>(m, p, s));
  };
  d.effective_options = [](const LobeSolver& solver) {
    const auto& o = static_cast<const SemiDiscretizationSolver&>(solver).options();
    return SolverValues{{"depth_max_m", o.depth_max_m},
                        {"steps_per_period", o.steps_per_period},
                        {"steps_per_vibration_cycle", o.steps_per_vibration_cycle},
                        {"collocation_nodes", o.collocation_nodes},
                        {"depth_tolerance", o.depth_tolerance}};
  };
  d.plot = {"#d95f02", 3.0, "", 0};
  d.columns = {{"multiplier_type", false}, {"spectral_radius_check", true}};
  d.compare_columns = {"multiplier_type"};
  return d;
}

// ------------------------------------------------------------- time-domain

SolverDescriptor time_domain_descriptor() {
  SolverDescriptor d;
  d.name = "time-domain";
  d.summary = "simulation with the real chip; the depth where the simulated cut starts to chatter; about 0.3 s "
              "per speed (straight cutter), ~1 s on a helical variable-pitch one";
  d.kind = SolverKind::kSimulation;
  d.accepts = {SolverFeature::kModalModel,    SolverFeature::kMilling,       SolverFeature::kTurning,
               SolverFeature::kHelix,         SolverFeature::kVariablePitch, SolverFeature::kVariableHelix,
               SolverFeature::kRunout,        SolverFeature::kProcessDamping, SolverFeature::kCutterProfile,
               SolverFeature::kSpeedVariation};
  d.in_default_compare = false;  // slow: opt-in
  d.options = {
      {"periods", Kind::kInt,
       "delay periods simulated per verdict (default 200; the last half is analysed); more: sharper verdict near "
       "the limit, slower",
       kMinVerdictPeriods, kMaxVerdictPeriods, "", true},
      {"feed_per_tooth_mm", Kind::kReal,
       "feed per tooth (milling) or per revolution (turning), mm (default: [process] feed_per_tooth_mm / "
       "feed_per_rev_mm, else 0.1); sets where the tool leaves the cut",
       0.0, kMaxFeedMm, "mm", true},
      {"multiple_regeneration", Kind::kFlag, "the chip is cut from the surface left by all earlier passes", 0.0,
       0.0, "", true},
      {"linear", Kind::kFlag,
       "linear delay equation (no static chip, the tool never leaves the cut); the verdict is the growth factor "
       "per period",
       0.0, 0.0, "", true},
      {"axial_slices", Kind::kInt,
       "axial slices of each tooth for a helical or variable cutter (default 0 = automatic: with one helix "
       "angle the exact integral along the edge, 20 slices for other helical cutters, 1 otherwise); more: closer "
       "to the continuous flute, slower",
       0.0, 1000.0, "", true}};
  d.make = [](const StructuralModel& m, const Process& p, double depth_max_m, const SolverValues& o) {
    TimeDomainOptions t;
    t.depth_max_m = depth_max_m;
    t.periods = option_or(o, "periods", t.periods);
    if (o.count("feed_per_tooth_mm")) t.feed_m = std::get<double>(o.at("feed_per_tooth_mm")) * 1e-3;
    t.multiple_regeneration = option_or(o, "multiple_regeneration", false);
    t.linear = option_or(o, "linear", false);
    t.axial_slices = option_or(o, "axial_slices", t.axial_slices);
    return std::unique_ptr<LobeSolver>(std::make_unique<TimeDomainSolver>(m, p, t));
  };
  d.effective_options = [](const LobeSolver& solver) {
    const auto& o = static_cast<const TimeDomainSolver&>(solver).simulator().options();
    return SolverValues{{"depth_max_m", o.depth_max_m},
                        {"periods", o.periods},
                        {"feed_m", o.feed_m},
                        {"linear", o.linear},
                        {"multiple_regeneration", o.multiple_regeneration},
                        {"axial_slices", o.axial_slices},
                        {"relative_tolerance", o.relative_tolerance},
                        {"depth_tolerance", o.depth_tolerance}};
  };
  d.plot = {"#0f6b50", 1.6, "", 6};
  return d;
}

std::string known_methods() {
  std::string known;
  for (const auto& d : solver_registry()) known += (known.empty() ? "" : ", ") + d.name;
  return known;
}

// Empty when `v` is a valid value of `o`, else the rule it breaks.
std::string violation(const SolverOption& o, const SolverValue& v) {
  const auto range = [&](double x, bool integer) -> std::string {
    const auto bound = [&](double b) { return integer ? std::to_string(static_cast<long long>(b)) : message_number(b); };
    const std::string unit = o.unit.empty() ? "" : " " + o.unit;
    const bool has_max = std::isfinite(o.max);
    if (std::isfinite(x) && x >= o.min && x <= o.max) return "";
    if (has_max) return "must be in [" + bound(o.min) + ", " + bound(o.max) + "]" + unit;
    return "must be >= " + bound(o.min) + unit;
  };
  switch (o.kind) {
    case Kind::kInt:
      if (!std::holds_alternative<int>(v)) return "must be an integer";
      return range(std::get<int>(v), true);
    case Kind::kReal:
      if (!std::holds_alternative<double>(v)) return "must be a number";
      return range(std::get<double>(v), false);
    case Kind::kFlag:
      return std::holds_alternative<bool>(v) ? "" : "must be true or false";
  }
  return "";
}

std::string value_text(const SolverValue& v) {
  if (const int* i = std::get_if<int>(&v)) return std::to_string(*i);
  if (const double* x = std::get_if<double>(&v)) return message_number(*x);
  if (const bool* b = std::get_if<bool>(&v)) return *b ? "true" : "false";
  return "?";
}

}  // namespace

std::string to_string(SolverFeature f) {
  switch (f) {
    case SolverFeature::kModalModel: return "modal structural models";
    case SolverFeature::kMeasuredFrf: return "measured FRFs";
    case SolverFeature::kMilling: return "milling";
    case SolverFeature::kTurning: return "turning";
    case SolverFeature::kHelix: return "a helix (process.helix_angle_deg)";
    case SolverFeature::kVariablePitch: return "variable pitch (process.pitch_angles_deg)";
    case SolverFeature::kVariableHelix: return "a variable helix (one process.helix_angle_deg per tooth)";
    case SolverFeature::kRunout: return "runout (process.runout_um)";
    case SolverFeature::kProcessDamping: return "process damping (process.process_damping_coefficient_n_per_m)";
    case SolverFeature::kSpeedVariation: return "spindle speed variation (process.speed_variation)";
    case SolverFeature::kCutterProfile: return "a ball-end, bull-nose or general cutter (process.cutter_geometry)";
  }
  return "feature " + std::to_string(static_cast<std::uint32_t>(f));
}

std::vector<SolverFeature> FeatureSet::missing(const FeatureSet& needed) const {
  std::vector<SolverFeature> out;
  for (std::uint32_t b = 0; b < 32; ++b) {
    const auto f = static_cast<SolverFeature>(b);
    if (needed.contains(f) && !contains(f)) out.push_back(f);
  }
  return out;
}

FeatureSet needed_features(const StructuralModel& model, const Process& process) {
  FeatureSet s;
  if (model.mode_count() > 0) s.insert(SolverFeature::kModalModel);
  if (model.has_measured()) s.insert(SolverFeature::kMeasuredFrf);
  s.insert(process.rotating_edges() ? SolverFeature::kMilling : SolverFeature::kTurning);
  if (process.has_helix()) s.insert(SolverFeature::kHelix);
  if (process.has_variable_pitch()) s.insert(SolverFeature::kVariablePitch);
  if (process.has_variable_helix()) s.insert(SolverFeature::kVariableHelix);
  if (process.has_process_damping()) s.insert(SolverFeature::kProcessDamping);
  if (process.has_speed_variation()) s.insert(SolverFeature::kSpeedVariation);
  if (process.has_profile()) s.insert(SolverFeature::kCutterProfile);
  return s;
}

std::vector<std::string> ignored_feature_notes(const SolverDescriptor& d, const Process& process) {
  std::vector<std::string> out;
  if (process.has_runout() && !d.accepts.contains(SolverFeature::kRunout))
    out.push_back("runout (process.runout_um) is ignored by method \"" + d.name +
                  "\": it changes the static chip only, which a linear method does not see (the nonlinear "
                  "time-domain method does)");
  if (process.has_helix() && d.kind == SolverKind::kAveraged)
    out.push_back("the helix does not change the result of method \"" + d.name +
                  "\": the average of the cutting force over a revolution is the same for any helix");
  return out;
}

const std::vector<SolverDescriptor>& solver_registry() {
  static const std::vector<SolverDescriptor> registry = {analytic_descriptor(), coupled_descriptor(),
                                                         sdm_descriptor(), time_domain_descriptor()};
  return registry;
}

const SolverDescriptor& find_lobe_method(const std::string& method) {
  for (const auto& d : solver_registry())
    if (d.name == method) return d;
  throw InputError("method \"" + method + "\": unknown (this build has: " + known_methods() + ")");
}

std::vector<std::string> lobe_methods() {
  std::vector<std::string> out;
  for (const auto& d : solver_registry()) out.push_back(d.name);
  return out;
}

bool has_lobe_method(const std::string& method) {
  const auto& r = solver_registry();
  return std::any_of(r.begin(), r.end(), [&](const SolverDescriptor& d) { return d.name == method; });
}

std::string resolve_lobe_method(const std::string& requested, const StructuralModel& model, const Process& process,
                                std::string* warning) {
  const bool milling = process.rotating_edges();
  const auto flag_averaged = [&](const SolverDescriptor& d) {
    if (milling && d.kind == SolverKind::kAveraged && warning) *warning = std::string(kFlipLobeWarning);
    return d.name;
  };
  if (requested != kAutoMethod) {
    if (!has_lobe_method(requested))
      throw InputError("method \"" + requested + "\": unknown (this build has: " + kAutoMethod + ", " +
                       known_methods() + ")");
    return flag_averaged(find_lobe_method(requested));
  }
  const FeatureSet needed = needed_features(model, process);
  const SolverKind preferred = milling ? SolverKind::kFloquet : SolverKind::kAveraged;
  for (const auto& d : solver_registry())
    if (d.kind == preferred && d.accepts.missing(needed).empty()) return flag_averaged(d);
  for (const auto& d : solver_registry())
    if (d.kind != SolverKind::kSimulation && d.accepts.missing(needed).empty()) return flag_averaged(d);
  check_accepts(solver_registry().front(), model, process);  // throws, naming what is missing
  return solver_registry().front().name;
}

void check_accepts(const SolverDescriptor& d, const StructuralModel& model, const Process& process) {
  const auto missing = d.accepts.missing(needed_features(model, process));
  if (missing.empty()) return;
  std::string able;
  for (const auto& o : solver_registry())
    if (o.accepts.missing(needed_features(model, process)).empty()) able += (able.empty() ? "" : ", ") + o.name;
  throw InputError("method \"" + d.name + "\" does not handle " + to_string(missing.front()) +
                   (able.empty() ? "" : " (methods that do: " + able + ")"));
}

std::unique_ptr<LobeSolver> make_lobe_solver(const std::string& method, const StructuralModel& model,
                                             const Process& process, double depth_max_m,
                                             const SolverValues& options) {
  const SolverDescriptor& d = find_lobe_method(method);
  const std::string where = "method \"" + method + "\": ";
  if (!(std::isfinite(depth_max_m) && depth_max_m > 0.0))
    throw InputError(where + "depth_max_m = " + message_number(depth_max_m) + ": must be > 0 m");
  for (const auto& entry : options) {
    // Named, not a structured binding: clang 14 (the fuzz build) cannot capture one in a lambda.
    const std::string& name = entry.first;
    const SolverValue& value = entry.second;
    const auto it = std::find_if(d.options.begin(), d.options.end(), [&](const SolverOption& o) { return o.name == name; });
    if (it == d.options.end()) {
      std::string takes;
      for (const auto& o : d.options) takes += (takes.empty() ? "" : ", ") + o.name;
      throw InputError(where + "unknown option \"" + name + "\" (it takes: " + (takes.empty() ? "none" : takes) + ")");
    }
    if (const std::string why = violation(*it, value); !why.empty())
      throw InputError(where + name + " = " + value_text(value) + ": " + why);
  }
  check_accepts(d, model, process);
  return d.make(model, process, depth_max_m, options);
}

std::string option_violation(const SolverOption& option, const SolverValue& value) { return violation(option, value); }

// ------------------------------------------------------- diagnostics hooks

std::vector<DiagnosticColumn> SemiDiscretizationSolver::diagnostic_columns() const {
  return {{"multiplier_type", false}, {"spectral_radius_check", true}};
}

DiagnosedLimit SemiDiscretizationSolver::limit_with_diagnostics(SpindleSpeed speed) const {
  // The type of the dominant multiplier and the spectral radius at the
  // reported limit (1 to within the depth tolerance).
  FloquetResult f;
  DiagnosedLimit r{limit_at(speed, &f), {}};
  if (r.limit.bounded()) r.values = {to_string(f.type), f.spectral_radius};
  else r.values = {std::monostate{}, std::monostate{}};
  return r;
}

PointAnalysis SemiDiscretizationSolver::analyse_point(SpindleSpeed speed, double depth_m) const {
  // The Floquet analysis at the point itself (the limit's values come from
  // limit_with_diagnostics).
  const FloquetResult f = analyse(speed.rpm(), depth_m);
  PointAnalysis a;
  a.stable = f.stable();
  a.spectral_radius = f.spectral_radius;  // +inf (null in JSON) when the map overflowed
  a.floquet_period_s = f.period_s;
  a.extra = {{"steps_per_period", f.steps}};
  if (std::isfinite(f.spectral_radius)) {
    a.dominant_multiplier = f.dominant_multiplier;
    if (std::isfinite(f.chatter_frequency_hz)) a.dominant_frequency_hz = f.chatter_frequency_hz;
    a.dominant_multiplier_type = f.type;
  }
  return a;
}

PointAnalysis TimeDomainSolver::analyse_point(SpindleSpeed speed, double depth_m) const {
  // The simulation at the point itself.
  const SimulationResult r = verdict_run(speed.rpm(), depth_m);
  PointAnalysis a;
  a.stable = r.verdict == SimulationVerdict::kStable;
  if (std::isfinite(r.growth_per_period)) {
    a.growth_per_period = r.growth_per_period;
    a.dominant_multiplier = r.dominant_multiplier;
  }
  const double f = std::isfinite(r.chatter_frequency_hz) ? r.chatter_frequency_hz : r.dominant_nonharmonic_hz;
  if (std::isfinite(f)) a.dominant_frequency_hz = f;
  a.floquet_period_s = r.floquet_period_s;
  a.extra = {{"verdict", to_string(r.verdict)},
             {"verdict_measure", r.verdict_measure},
             {"max_amplitude_mm", r.max_amplitude_m * 1e3},
             {"out_of_cut_fraction", r.out_of_cut_fraction},
             {"periods", r.periods}};
  return a;
}

}  // namespace chatter
