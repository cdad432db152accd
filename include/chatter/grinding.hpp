// Robotic grinding at controlled power: what a power set-point gives (removal
// rate, groove depth, forces, energy partition, impacts per turn), what power
// gives a target depth or removal, and how many wheels a repair needs.
// User guide: docs/grinding.md (the model, the seeds' misprints, every key).
//
// Mechanistic model (Tahvilian 2015, "Numerical and experimental study of a
// flexible robotic grinding process", ch. 4 eqs. 4.3-4.7; ch. 2 eqs. 2.2,
// 2.11, 2.17-2.19). A wheel of radius R, width E, turning at N rev/s, is fed
// along its axis at v_f and cuts a groove of maximum depth h0:
//   section  A = Z_w / v_f = (4/3) sqrt(2R) h0^(3/2),  width w = 2 sqrt(2 R h0) = (12 R Z_w / v_f)^(1/3)
//   power    P = k_e n_c N (3/4) E w + k_c Z_w       (friction/ploughing + chip formation)
//   forces   F_T = P / (2 pi R N),  F_N = F_T / mu   (mu = F_T/F_N, the force ratio)
//   per impact, notch angle phi in (-phi0, phi0), phi0 = sqrt(2 h0 / R):
//            F_T(phi) = k_e E (1 - |phi/phi0|^3) + k_c v_f/(n_c N) (h0 - R phi^2/2)
//   and n_c/(2 pi) times its integral over an impact is the mean F_T (eq. 4.5).
// n_c, the impacts (contacts) per wheel turn, is a number or a table against
// power. Given P the removal Z_w is the unique root of the power balance (the
// right side grows monotonically in Z_w): a safeguarded Newton iteration on
// u = Z_w^(1/3) inside a bracket. Given h0 or Z_w, P follows in closed form
// on each linear piece of the n_c table.
// The seed prints h0 three ways; h0 = [3 Z_w / (4 v_f sqrt(2R))]^(2/3) (its eq.
// 2.13) is the one consistent with its eqs. 2.8, 4.6 and 4.7 (eqs. 2.6 and 4.4
// misplace the square root): docs/grinding.md, "Misprints".
//
// Empirical models (Thuot 2010, "Modélisation du procédé de meulage sous-marin",
// ch. 4 eqs. 4.1-4.16, annexes IV-VI): removal rate, wheel wear rate or normal
// force as functions of the cutting speed V_c = pi D n / 60 (m/s) and the
// useful power P_u (W) or the normal force F_N (N), in the seed's shop units
// (result mm^3/s or N; see EmpiricalForm for the term order).
//
// Units: SI in every field (m, s, N, W, J, kg) unless the name says
// otherwise; the empirical coefficients keep the seed's shop units.
// Everything here is core: the standard library only.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace chatter::grinding {

/// Impacts of the wheel on the part per wheel turn, n_c: one number, or a
/// table against the grinding power, interpolated linearly between rows and
/// held at the end values outside them (seed 001 §4.7: 0.75, 1.29, 1.56,
/// 2.25 at 500, 1000, 1500, 2000 W).
class ImpactsPerTurn {
 public:
  /// n_c = 1 (seed 001 ch. 2).
  ImpactsPerTurn() = default;
  /// @throws InputError unless 0 < impacts < inf.
  explicit ImpactsPerTurn(double impacts);
  /// @pre power_w.size() == impacts.size() >= 1.
  /// @throws InputError when a power is not > 0 and finite, the powers do
  ///         not strictly increase, or an impact count is not > 0 and finite.
  ImpactsPerTurn(std::vector<double> power_w, std::vector<double> impacts);

  /// n_c at `power_w` (W). Cost O(log rows).
  double at(double power_w) const;
  bool is_table() const { return power_w_.size() > 1; }
  const std::vector<double>& power_w() const { return power_w_; }
  const std::vector<double>& impacts() const { return impacts_; }

 private:
  std::vector<double> power_w_{1.0};  // one row: a constant
  std::vector<double> impacts_{1.0};
};

/// The wheel and its kinematics.
struct Wheel {
  double diameter_m = 0.0;        ///< D > 0 (the radius R = D/2).
  double width_m = 0.0;           ///< E > 0, its thickness along the feed.
  double speed_rev_per_s = 0.0;   ///< N > 0 (wheel rev/min / 60).
  double radius_m() const { return 0.5 * diameter_m; }
  /// V_c = pi D N, m/s.
  double cutting_speed_m_per_s() const;
};

/// Seed 001's mechanistic coefficients.
struct MechanisticModel {
  double edge_coefficient_n_per_m = 0.0;      ///< k_e >= 0 (friction/ploughing), N/m (the seed: N/mm x 1e3).
  double cutting_coefficient_n_per_m2 = 0.0;  ///< k_c > 0 (chip formation), N/m^2 = J/m^3.
  ImpactsPerTurn impacts;                     ///< n_c.
};

/// Energy partition into the part (seed 001 ch. 2).
enum class PartitionModel {
  kMalkin,    ///< eps = (u - 0.45 u_ch) / u  (eq. 2.2, conventional grinding)
  kModified,  ///< eps = (u - 0.6 u_ch) / u   (eq. 2.17, the flexible robot)
  kPower,     ///< eps = (alpha P_friction + beta P_chip) / P  (eq. 2.18)
};
/// beta of the power model as a table over power and feed (seed 001 table
/// 2.2: one row per feed, beta against power; 0.49 ... 0.03 falling with
/// both). At a feed between two rows, each row is interpolated linearly in
/// power (held at its end values outside its powers) and the two results
/// linearly in feed; outside the feeds the nearest row is used. Either is
/// said in the notes at().
class BetaTable {
 public:
  struct Row {
    double feed_m_per_s = 0.0;
    std::vector<double> power_w, beta;
  };
  BetaTable() = default;
  /// @throws InputError unless every feed is > 0 and the feeds strictly
  ///         increase, each row has >= 1 power, the powers are > 0 and
  ///         strictly increase, and every beta is in [0, 1].
  explicit BetaTable(std::vector<Row> rows);
  /// beta at (P, v_f); each row or feed held at an end value adds a sentence
  /// to `notes` (may be null). Cost O(rows + log powers).
  double at(double power_w, double feed_m_per_s, std::vector<std::string>* notes) const;
  const std::vector<Row>& rows() const { return rows_; }

 private:
  std::vector<Row> rows_;
};

struct EnergyPartitionModel {
  PartitionModel model = PartitionModel::kModified;
  double chip_energy_j_per_m3 = 13.8e9;  ///< u_ch > 0 (13.8 J/mm^3 for steel); malkin, modified.
  double alpha = 0.76;                   ///< in [0, 1]; power model.
  double beta = 0.27;                    ///< in [0, 1]; power model (seed 001 table 4.1 at 1000 W).
  /// Power model: beta by power and feed instead of the one `beta`.
  std::optional<BetaTable> beta_table;
  /// beta at (P, v_f): the table's, else `beta`.
  double beta_at(double power_w, double feed_m_per_s, std::vector<std::string>* notes) const {
    return beta_table ? beta_table->at(power_w, feed_m_per_s, notes) : beta;
  }
};
const char* partition_model_name(PartitionModel m);  ///< "malkin", "modified", "power"

/// Power to spin the wheel without cutting (drag of the medium, bearings):
/// P_loss = c0 omega^k D^x W, omega the wheel's angular speed in rad/s and D
/// its diameter in mm (seed 000 eq. 4.27; c0 holds the medium's density:
/// underwater with air injection 6.841e-2, k = 1.314, x = 0.350, table 4.5).
struct NoLoadLoss {
  double c0 = 0.0;                 ///< >= 0, W / ((rad/s)^k mm^x)
  double speed_exponent = 0.0;     ///< k, finite
  double diameter_exponent = 0.0;  ///< x, finite
  double loss_w(const Wheel& wheel) const;
};

/// Form of an empirical model. x = V_c (m/s), y = P_u (W) or F_N (N) (the
/// model's variable), n = wheel rev/min, D = wheel diameter (mm). Coefficients
/// in MATLAB's `fit` order, which seed 000's annexes use (its equations 4.3
/// and 4.10 list the same terms in another order):
///   poly11      p00 + p10 x + p01 y                                   (3)
///   poly22      poly11 + p20 x^2 + p11 x y + p02 y^2                  (6)
///   poly33      poly22 + p30 x^3 + p21 x^2 y + p12 x y^2 + p03 y^3    (10)
///   power_law   C n^b1 y^b2 D^b3            coefficients [C, b1, b2, b3] (4)
///   hahn_lindsay  K_p (F_N - F_th) x        coefficients [K_p, F_th]      (2)
///                 (Hahn-Lindsay / Preston; its variable is the normal force)
enum class EmpiricalForm { kPoly11, kPoly22, kPoly33, kPowerLaw, kHahnLindsay };
const char* empirical_form_name(EmpiricalForm f);   ///< "poly11", ...
std::size_t coefficient_count(EmpiricalForm f);     ///< 3, 6, 10, 4, 2
/// Names of the coefficients in order ("p00", "p10", ...; "C", "b1", ...).
std::vector<std::string> coefficient_names(EmpiricalForm f);

/// The model's second variable.
enum class EmpiricalVariable { kUsefulPower, kNormalForce };

/// A closed interval of a tested variable.
struct Interval {
  double lo = 0.0, hi = 0.0;
  bool contains(double v) const { return v >= lo && v <= hi; }
};
/// Where a model was fitted (seed 000 annex VI warns outside it). Absent:
/// not known, not checked.
struct TestedDomain {
  std::optional<Interval> cutting_speed_m_per_s, useful_power_w, normal_force_n, wheel_diameter_mm, wheel_rpm;
};

/// The values an empirical model may read.
struct EmpiricalInputs {
  double cutting_speed_m_per_s = 0.0;
  double useful_power_w = 0.0;
  double normal_force_n = 0.0;
  double wheel_rpm = 0.0;
  double wheel_diameter_mm = 0.0;
};

/// What a least-squares fit knows of its own error, for intervals on the
/// model's predictions (`grind fit --out` writes it). The model is linear in
/// its parameters theta along the design row g(x): poly forms theta = the
/// coefficients, g = the terms (1, x, y, x^2, ...); power_law is linear on
/// logarithms, theta = (ln C, b1, b2, b3), g = (1, ln n, ln y, ln D);
/// hahn_lindsay theta = (K_p, -K_p F_th), g = (F_N V_c, V_c).
struct FitUncertainty {
  std::vector<double> covariance;  ///< s^2 (X'X)^-1 of theta, p x p row-major (symmetric, diagonal >= 0)
  double residual_variance = 0.0;  ///< s^2 = RSS / (m - p) (power_law: of ln y), >= 0
  int degrees_of_freedom = 0;      ///< m - p >= 1
};

/// A prediction with its uncertainty (ordinary least squares, Student t with
/// the fit's degrees of freedom): the fitted mean's standard error
/// se_m = sqrt(g C g'), one new test's se_t = sqrt(s^2 + se_m^2), and their
/// 95 % intervals value -+ t(0.975) se. power_law: both on ln y, the
/// intervals exp of ln y's (not symmetric). In the model's units.
struct PredictionInterval {
  double value = 0.0;
  double standard_error_mean = 0.0;  ///< of the fitted mean (power_law: of ln value)
  double standard_error_test = 0.0;  ///< of one new test (power_law: of ln value)
  Interval mean_95, test_95;         ///< 95 % confidence of the mean; 95 % prediction of one test
  int degrees_of_freedom = 0;
  bool log_scale = false;            ///< power_law: the standard errors are of ln value
  /// The same interval for a quantity `factor` times this one (factor > 0).
  PredictionInterval scaled(double factor) const;
};

struct EmpiricalModel {
  EmpiricalForm form = EmpiricalForm::kPoly11;
  EmpiricalVariable variable = EmpiricalVariable::kUsefulPower;
  std::vector<double> coefficients;
  TestedDomain domain;
  /// The fit's statistics; absent: no intervals.
  std::optional<FitUncertainty> uncertainty;

  /// Empty when valid, else the violated rule (coefficient count, a
  /// Hahn-Lindsay model on power, a non-positive power-law constant).
  std::string validate() const;
  /// The model's value (mm^3/s or N) at `in`. @pre validate().empty();
  /// power_law needs n, y, D > 0. Cost O(1).
  double evaluate(const EmpiricalInputs& in) const;
  /// "cutting speed 36 m/s outside the tested 10 to 31 m/s", one per
  /// variable of the domain outside its interval.
  std::vector<std::string> outside_domain(const EmpiricalInputs& in) const;
  /// The design row g(x) of the fit's linear parameters (see FitUncertainty).
  std::vector<double> design_row(const EmpiricalInputs& in) const;
  /// The value at `in` with its intervals; nullopt without `uncertainty`.
  /// @pre validate().empty(). Cost O(p^2).
  std::optional<PredictionInterval> interval(const EmpiricalInputs& in) const;
};

/// Seed 000's models: removal rate (mm^3/s), wheel wear rate (mm^3/s),
/// normal force (N).
struct EmpiricalModels {
  std::optional<EmpiricalModel> removal, wear, normal_force;
  bool empty() const { return !removal && !wear && !normal_force; }
};

/// The grinder motor's mechanical power from the current the operator sets
/// and the motor's speed (seed 000 §4.4.1, eq. 4.26: a cubic in both, fitted
/// on a dynamometer): P_m = poly(x = current A, y = motor rev/min) W, a
/// poly11, poly22 or poly33 in MATLAB's term order (EmpiricalForm). The
/// useful power at the wheel is P_m minus the no-load loss (eq. 4.27).
struct MotorMap {
  EmpiricalForm form = EmpiricalForm::kPoly33;
  std::vector<double> coefficients;
  std::optional<Interval> current_a, motor_rpm;  ///< where it was measured (warning outside)
  std::optional<double> max_current_a;           ///< the continuous current limit (grind plan at full current)
  /// Empty when valid, else the violated rule (a poly form, its count, finite numbers).
  std::string validate() const;
  /// P_m (W) at `amps` (A) and motor speed `rpm` (rev/min); `warnings` gets
  /// a line per variable outside its measured interval. @pre validate().empty().
  double power_w(double amps, double rpm, std::vector<std::string>* warnings) const;
};

/// Everything a prediction reads: the [grinding] table of a config in SI.
struct Process {
  Wheel wheel;
  /// Wheel rev per motor rev (motor_rpm x ratio = the wheel's speed); 1 when
  /// the config gives wheel_rpm. The motor map reads the motor's speed.
  double transmission_ratio = 1.0;
  std::optional<MotorMap> motor;
  double feed_m_per_s = 0.0;   ///< v_f > 0, along the wheel's axis.
  double force_ratio = 0.0;    ///< mu = F_T / F_N in (0, 10].
  std::optional<double> density_kg_per_m3;       ///< of the part (removal in kg/h).
  std::optional<MechanisticModel> mechanistic;   ///< seed 001; absent: the empirical removal model
  std::optional<EnergyPartitionModel> partition;
  std::optional<NoLoadLoss> no_load_loss;
  EmpiricalModels empirical;
  std::optional<double> min_wheel_diameter_m;    ///< used-up diameter, for planning.

  /// Empty when valid, else the first violated rule (naming the field).
  std::string validate() const;
};

// ------------------------------------------------------------------ geometry

/// Groove section A (m^2) of maximum depth h0 (m) cut by a wheel of radius R (m).
double groove_area_m2(double max_depth_m, double radius_m);
/// Groove width w = 2 sqrt(2 R h0), m.
double groove_width_m(double max_depth_m, double radius_m);
/// h0 (m) of the groove that removes Z_w (m^3/s) at feed v_f (m/s).
double depth_from_removal_m(double removal_m3_per_s, double feed_m_per_s, double radius_m);
/// Contact half-angle phi0 = sqrt(2 h0 / R), rad.
double contact_half_angle_rad(double max_depth_m, double radius_m);

/// The power balance's two parts at removal Z_w (W): k_e n_c N (3/4) E w and k_c Z_w.
struct PowerSplit {
  double friction_w = 0.0;
  double chip_w = 0.0;
  double total() const { return friction_w + chip_w; }
};
/// @pre p.mechanistic; Z_w >= 0, n_c > 0.
PowerSplit power_split(const Process& p, double removal_m3_per_s, double impacts_per_turn);

/// Seed 001 eq. 4.3: the tangential force (N) of one impact when the notch is
/// at angle phi (rad) of the contact arc, groove depth h0 (m), n_c impacts per
/// turn; 0 outside (-phi0, phi0). @pre p.mechanistic.
double impact_tangential_force_n(const Process& p, double max_depth_m, double impacts_per_turn, double phi_rad);

// --------------------------------------------------------------- prediction

struct EnergyPartition {
  PartitionModel model = PartitionModel::kModified;
  std::optional<double> alpha, beta;  ///< the power model's alpha and beta at this point (beta from its table)
  double fraction = 0.0;          ///< eps, clamped to [0, 1]
  double heat_into_part_w = 0.0;  ///< eps P
  bool clamped = false;           ///< the model's formula left [0, 1] (then a warning says so)
};

/// The empirical models' values beside the mechanistic ones (SI).
struct EmpiricalPrediction {
  std::optional<double> removal_rate_m3_per_s, normal_force_n, wear_rate_m3_per_s;
  std::optional<double> g_ratio;  ///< removal / wear, when both models are given
  /// Each model's intervals when its config carries the fit's statistics, in
  /// the model's units (mm^3/s, N); the depth per pass's (mm) follows from
  /// the removal's (removal / (v_f E)).
  std::optional<PredictionInterval> removal_interval, wear_interval, normal_force_interval, depth_per_pass_interval;
};

/// What a power set-point gives: the record of `chatter grind predict`.
struct Prediction {
  std::string mode;                   ///< "power", "target_depth", "target_removal" or "current"
  std::string removal_source;         ///< "mechanistic" or "empirical" (no mechanistic model)
  double power_w = 0.0;               ///< P, the useful grinding power at the wheel
  double removal_rate_m3_per_s = 0.0; ///< Z_w
  std::optional<double> removal_rate_kg_per_h;  ///< with the density
  double max_depth_m = 0.0;           ///< h0
  double groove_width_m = 0.0;        ///< w
  double depth_per_pass_m = 0.0;      ///< Z_w / (v_f E) (seed 000)
  double tangential_force_n = 0.0;    ///< P / V_c
  double normal_force_n = 0.0;        ///< F_T / mu
  std::optional<double> friction_power_w, chip_power_w;  ///< mechanistic model only
  double specific_energy_j_per_m3 = 0.0;                 ///< u = P / Z_w
  std::optional<EnergyPartition> energy_partition;
  std::optional<double> impacts_per_turn;                ///< n_c at P (mechanistic model)
  double contact_half_angle_rad = 0.0;
  double contact_duration_s = 0.0;    ///< 2 phi0 / (2 pi N), one impact
  double cutting_speed_m_per_s = 0.0;
  std::optional<double> no_load_loss_w, motor_power_w;   ///< with [grinding.no_load_loss]: P + loss
  std::optional<double> motor_current_a;                 ///< mode "current": the current set
  std::optional<EmpiricalPrediction> empirical;
  /// Outside a model's tested domain, an impacts table's range, the power
  /// partition's [0, 1], ... Each a sentence naming the model and the value.
  std::vector<std::string> warnings;
};

/// The removal and all else at useful power P (W).
/// @throws InputError "power_w = ...: must be > 0 W" (and finite), or when the
///         process has neither a mechanistic nor an empirical removal model,
///         or the empirical removal is not > 0 there, or the groove would
///         reach the wheel's radius (as predict_for_depth refuses such a
///         target; sweep_power keeps those points with a warning). Cost O(1) (a few dozen
///         Newton steps at most).
Prediction predict_at_power(const Process& p, double power_w);
/// The power that cuts a groove of maximum depth h0 (m), and all else.
/// Without a mechanistic model: the removal of that groove, A(h0) v_f,
/// through the empirical removal model (predict_for_removal).
/// @throws InputError unless 0 < h0 < R, or as predict_for_removal.
Prediction predict_for_depth(const Process& p, double max_depth_m);
/// The power that removes Z_w (m^3/s), and all else. Without a mechanistic
/// model, the empirical removal model inverted inside its tested power range
/// (the first power there whose removal is Z_w, to 1e-12).
/// @throws InputError unless Z_w > 0 and its groove is shallower than R, or
///         without a mechanistic model when no empirical removal model with a
///         tested power range reaches Z_w there (the message gives its range).
Prediction predict_for_removal(const Process& p, double removal_m3_per_s);
/// The useful power (W) at the wheel when the motor draws `current_a` (A) at
/// the process's speed: the motor map's power minus the no-load loss (without
/// [grinding.no_load_loss] the motor's power, and `warnings` says so).
/// @throws InputError without p.motor, for a current not > 0, or when the
///         loss takes all the motor's power (nothing left to grind).
double useful_power_from_current(const Process& p, double current_a, std::vector<std::string>& warnings);
/// predict_at_power at the useful power of `current_a` (mode "current";
/// motor_current_a and motor_power_w set). @throws as both.
Prediction predict_at_current(const Process& p, double current_a);

/// The empirical models at useful power P (W) for this wheel (the normal
/// force they read comes from the normal-force model, else from P / (V_c mu)).
/// `warnings` gets one line per model outside its tested domain.
EmpiricalPrediction predict_empirical(const Process& p, double power_w, std::vector<std::string>& warnings);

/// Predictions at `points` powers evenly spaced from p_min to p_max (both
/// included), for one feed (m/s) of `feeds` each (empty: the process's feed).
struct SweepCurve {
  double feed_m_per_s = 0.0;
  std::vector<Prediction> points;
};
/// @throws InputError unless 0 < p_min < p_max, 2 <= points <= 100 000, each
///         feed > 0 and at most 50 feeds; as predict_at_power.
std::vector<SweepCurve> sweep_power(const Process& p, double p_min_w, double p_max_w, int points,
                                    const std::vector<double>& feeds_m_per_s);

/// The powers the models were measured over, where known: the impacts
/// table's first to last row, and the empirical models' tested power (the
/// intersection of their domains).
struct Envelope {
  std::optional<Interval> impacts_table_w;
  std::optional<Interval> tested_power_w;
};
Envelope operating_envelope(const Process& p);

// ------------------------------------------------------ dynamics (results)

// What `chatter grind simulate` reports: plain data, computed by
// simulate_grinding (include/chatter/grinding_dynamics.hpp, the model).

/// One point of the recorded series.
struct DynamicsSample {
  double time_s = 0.0;
  double depth_m = 0.0;         ///< x, wheel depth below the uncut surface
  double surface_m = 0.0;       ///< s, the surface the previous turn left
  double contact_force_n = 0.0; ///< F_c (normal)
  double push_n = 0.0;          ///< F_p
};

struct DynamicsResult {
  double power_w = 0.0;
  double wheel_rpm = 0.0;
  int turns = 0, analysed_from_turn = 0;
  /// Mean number of contacts per analysed turn. A contact counts once, in
  /// the turn of its largest force (as `grind impacts` counts force peaks);
  /// one lasting a turn or more counts in each turn it spans (continuous
  /// contact: 1 per turn).
  double impacts_per_turn = 0.0;
  std::vector<int> per_turn;            ///< contacts in each analysed turn
  std::vector<int> histogram;           ///< [k] = analysed turns with k contacts
  double turns_without_contact = 0.0;   ///< fraction of the analysed turns
  double contact_fraction = 0.0;        ///< fraction of the analysed time in contact
  bool continuous = false;              ///< in contact throughout the analysed turns
  double mean_normal_force_n = 0.0;     ///< time mean of F_c (the loop's target)
  double peak_normal_force_n = 0.0;     ///< largest F_c
  double mean_contact_peak_n = 0.0;     ///< mean over contacts of each one's largest F_c
  double removal_rate_m3_per_s = 0.0;   ///< time mean of the chip rate Z(t)
  /// Seed 001's power balance at P with the simulated impacts per turn as
  /// n_c (its friction is paid per impact): the removal the impact count
  /// implies in the quasi-static model; absent when no contact was made.
  std::optional<double> removal_at_simulated_impacts_m3_per_s;
  double mean_power_w = 0.0;            ///< mu V_c x mean F_c
  double contact_stiffness_n_per_m = 0.0;  ///< dF_c/dp at the quasi-static point (for comparison with the robot)
  double robot_stiffness_n_per_m = 0.0;    ///< static stiffness of the modes along the normal, 1 / sum S_i^2 / k_i
  Prediction quasi_static;              ///< seed 001's model at P, for comparison
  std::vector<DynamicsSample> series;   ///< the last series_turns turns, every grid point and contact event
  long steps = 0, rhs_evaluations = 0, restarts = 0;
};

// ----------------------------------------------------------------- planning

/// A repair plan (seed 000 §6.6): the wheel is used from its diameter down to
/// the used-up diameter; removal and wear rates follow the diameter. At a
/// fixed wheel speed the cutting speed falls as the wheel wears; with an
/// objective the wheel speed is chosen anew at every diameter.
enum class PlanObjective {
  kFixedSpeed,  ///< the process's wheel speed throughout
  kRemoval,     ///< at each diameter the speed of the largest removal rate (seed 000's "MRR max")
  kGRatio,      ///< at each diameter the speed of the largest G-ratio ("G-ratio max")
};
const char* plan_objective_name(PlanObjective o);  ///< "fixed_speed", "removal", "g-ratio"
/// "removal" or "g-ratio" (the names a user types). @throws InputError
/// "<what> <name>: must be removal or g-ratio".
PlanObjective plan_objective_from_name(const std::string& name, const std::string& what);

struct PlanOptions {
  double volume_m3 = 0.0;        ///< material to remove, > 0
  /// Useful grinding power, > 0; or 0 with current_a (the power then follows
  /// the wheel's speed and diameter through the motor map and no-load loss).
  double power_w = 0.0;
  std::optional<double> current_a;  ///< motor current, A (needs [grinding.motor]); not with power_w
  /// Constant G-ratio (removal / wear) when the process has no wear model; 0: use the model.
  double g_ratio = 0.0;
  double wheel_change_s = 0.0;   ///< time to change a wheel, >= 0
  int diameter_steps = 200;      ///< wear steps over a wheel's life (>= 10)
  PlanObjective objective = PlanObjective::kFixedSpeed;
  /// With an objective: the wheel speeds searched, rev/min (0 < min < max),
  /// `speed_points` of them evenly spaced (seed 000: 100), kept where every
  /// empirical model's tested cutting speed and power hold (and, for the
  /// G-ratio, where it lies in the 0.2 to 20 of rough grinding: beyond, the
  /// wear model is near zero and its ratio meaningless).
  double wheel_rpm_min = 0.0, wheel_rpm_max = 0.0;
  int speed_points = 200;
};
struct PlanStep {
  double diameter_m = 0.0, removal_rate_m3_per_s = 0.0, wear_rate_m3_per_s = 0.0;
  double wheel_rpm = 0.0, cutting_speed_m_per_s = 0.0, power_w = 0.0;  ///< the point ground at
  double removed_m3 = 0.0, time_s = 0.0;  ///< cumulated from the new wheel
};
struct Plan {
  PlanObjective objective = PlanObjective::kFixedSpeed;
  double removal_per_wheel_m3 = 0.0;  ///< over one wheel's life
  double wheel_life_s = 0.0;          ///< grinding time of one wheel
  double usable_wheel_volume_m3 = 0.0;
  double wheels = 0.0;                ///< volume / removal per wheel (fractional)
  int wheels_needed = 0;              ///< ceil(wheels)
  int wheel_changes = 0;              ///< wheels_needed - 1
  double grinding_time_s = 0.0;
  double total_time_s = 0.0;          ///< grinding + changes
  double mean_g_ratio = 0.0;          ///< removal per wheel / usable wheel volume
  std::vector<PlanStep> life;         ///< one wheel, new to used up
  std::vector<std::string> warnings;
};
/// @throws InputError on a bad option, without p.min_wheel_diameter_m (or it
///         is not below the wheel's diameter), without a wear model and without
///         options.g_ratio (or with it for the G-ratio objective), or when a
///         rate is not > 0 along the wheel's life (with an objective: when no
///         searched speed qualifies at some diameter).
/// Cost O(diameter_steps x speed_points) predictions.
Plan plan_repair(const Process& p, const PlanOptions& options);

/// Seed 000 §6.6's comparison: the same repair at the largest removal and at
/// the largest G-ratio at every diameter (options.objective is ignored).
struct PlanComparison {
  Plan removal, g_ratio;
  int wheels_saved = 0;        ///< removal's wheels_needed - g_ratio's
  double time_saved_s = 0.0;   ///< removal's total time - g_ratio's (negative: the removal strategy is faster)
};
PlanComparison compare_plan_objectives(const Process& p, const PlanOptions& options);

}  // namespace chatter::grinding
